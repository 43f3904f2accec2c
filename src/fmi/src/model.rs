//! What a model behind an FMU provides ([`Model`]) and its static facts ([`ModelInfo`]):
//! the interface between the plain-Rust models (`beam`, `friction`) and the FMI layer
//! (`instance`, `model_description`, `ffi2`, `ffi3`).

use crate::variables::{ArrayVariable, DynamicOutput, Variable};
use std::path::Path;

/// Static facts of an FMU.
#[derive(Debug)]
pub struct ModelInfo {
    /// modelName and modelIdentifier (the binary's file name inside the FMU).
    pub model_identifier: &'static str,
    pub description: &'static str,
    /// DefaultExperiment (s).
    pub start_time: f64,
    pub stop_time: f64,
    /// Suggested communication step (s).
    pub step_size: f64,
    /// Files the FMU carries in `resources/`, by name in the workspace's `weights/`
    /// folder. Names, not contents: fmu-build copies the files, so the library itself
    /// does not carry the networks it reads from `resources/` (1.3 MB).
    pub resources: &'static [&'static str],
    /// The model has internal events at which an FMI 3.0 step can end early
    /// (`Model::do_step_until_event`; modelDescription 3.0's mightReturnEarlyFromDoStep).
    pub returns_early_at_events: bool,
    /// The model gives its outputs' partial derivatives with respect to its inputs
    /// (`Model::partial_derivatives`; modelDescription's providesDirectionalDerivative in
    /// FMI 2.0, providesDirectionalDerivatives in 3.0).
    pub provides_directional_derivatives: bool,
}

/// Partial derivatives d(output)/d(input) at the current inputs, by value reference
/// (outputs and inputs of the variable table); pairs not listed are 0.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PartialDerivatives {
    entries: Vec<(u32, u32, f64)>,
}

impl PartialDerivatives {
    /// Sets d(output)/d(input).
    pub fn set(&mut self, output: u32, input: u32, value: f64) {
        self.entries.push((output, input, value));
    }

    /// d(output)/d(input) (0 where not set).
    pub fn get(&self, output: u32, input: u32) -> f64 {
        self.entries
            .iter()
            .rev()
            .find(|(o, i, _)| *o == output && *i == input)
            .map_or(0.0, |e| e.2)
    }

    /// The first entry that is not finite: (output, input, value).
    pub fn non_finite(&self) -> Option<(u32, u32, f64)> {
        self.entries.iter().copied().find(|e| !e.2.is_finite())
    }
}

/// Where a saved state puts the instance, for the model's checks of its own part.
#[derive(Clone, Copy, Debug)]
pub struct Restoring {
    /// The state's format version (`instance::STATE_VERSION` or an older one that
    /// `instance::SavedState::from_bytes` still reads).
    pub version: u32,
    /// The instance's time (s). A model with a clock of its own refuses a state whose
    /// clock disagrees: the next fmi2DoStep would otherwise have to bridge the gap.
    pub time: f64,
    /// The experiment's start time (s).
    pub start_time: f64,
    /// The state's mode is past fmi2ExitInitializationMode: its parameters were
    /// checked by initialisation, so the model's part must pass those checks too.
    pub initialized: bool,
}

/// A model behind an FMU. Plain Rust: no C types. The `instance` module drives it
/// through the FMI state machine.
///
/// Failures are plain strings here: each is the reason the instance logs (the FMI
/// boundary). The models keep typed errors up to this point (`beam::BuildError`,
/// `friction::EvaluateError`, `networks::NetworkError`, the physics' errors).
pub trait Model: Send + Sized + 'static {
    const INFO: ModelInfo;

    /// The variable table (one source of truth for the XML and the accessors).
    fn variables() -> &'static [Variable<Self>];

    /// The FMI 3.0 array variables made of rows of [`Model::variables`] (none by
    /// default). The FMI 2.0 description keeps the rows as scalars.
    fn arrays() -> &'static [ArrayVariable] {
        &[]
    }

    /// A model with every variable at its start value and nothing loaded.
    fn with_defaults() -> Self;

    /// The outputs this model declares beyond [`Model::variables`] (none by default):
    /// fixed by its start values (an exported FMU's scene), so that its description
    /// and its instances agree.
    fn dynamic_outputs(&self) -> &[DynamicOutput] {
        &[]
    }

    /// The current value of dynamic output `index` (a position in
    /// [`Model::dynamic_outputs`]).
    fn dynamic_output_value(&self, _index: usize) -> f64 {
        f64::NAN
    }

    /// Reads the files in the unpacked `resources/` folder (at instantiation).
    fn load_resources(&mut self, resources: &Path) -> Result<(), String>;

    /// Back to the start values, keeping what `load_resources` read.
    fn reset(&mut self);

    /// Makes the outputs current (called before outputs are read), for the experiment
    /// from `start_time` to `stop_time`.
    fn refresh_outputs(&mut self, start_time: f64, stop_time: Option<f64>) -> Result<(), String>;

    /// Checks every parameter and builds what the simulation needs (at
    /// fmi2ExitInitializationMode). `stop_time` is the experiment's, if defined.
    fn initialize(&mut self, start_time: f64, stop_time: Option<f64>) -> Result<(), String>;

    /// Advances from where the model is (the instance's time) to `to` (s), a step of
    /// `size` (s), the communication step size the importer gave (`to` = its
    /// communication point + `size`). A model that integrates over the step uses `size`,
    /// not `to` minus the previous `to`: masters count time differently (libcosim in
    /// integer nanoseconds), and the difference of two such times is `size` only to
    /// rounding, which would make the results depend on the master. `events` collects
    /// messages for the logEvents category.
    fn do_step(&mut self, to: f64, size: f64, events: &mut Vec<String>) -> Result<(), String>;

    /// Advances towards `to` (s) as `do_step` does, but ends at an internal
    /// event (for the beam: the end of the internal step in which the contact switched
    /// between stick and slip) and returns its time (s), which is then where the model
    /// is. `None`: no event, the model is at `to` exactly as after `do_step`. A model
    /// without events (the default) never stops early.
    fn do_step_until_event(
        &mut self,
        to: f64,
        size: f64,
        events: &mut Vec<String>,
    ) -> Result<Option<f64>, String> {
        self.do_step(to, size, events).map(|()| None)
    }

    /// Messages for the `logEvents` category produced outside a step (for example the
    /// `fidelity = auto` choice at initialisation); taken once.
    fn take_notes(&mut self) -> Vec<String> {
        Vec::new()
    }

    /// Everything that `restore` needs, as plain data.
    fn save(&self) -> serde_json::Value;

    /// Checks what `save` wrote (or bytes that claim to be it) as `restore` would,
    /// without changing what the model computes: every value as its setter and
    /// initialisation check it. fmi2DeSerializeFMUstate calls it, so that a state it
    /// hands out is one `restore` accepts, but for the checks that need the built model
    /// (the simulation's vector lengths), which `restore` alone makes.
    fn check_saved(&mut self, saved: &serde_json::Value, at: &Restoring) -> Result<(), String>;

    /// Restores what `save` wrote; refuses data that does not fit, leaving the model as
    /// it was. Every check of `check_saved` is made.
    fn restore(&mut self, saved: serde_json::Value, at: &Restoring) -> Result<(), String>;

    /// The outputs' partial derivatives with respect to the inputs at the current
    /// inputs (fmi2GetDirectionalDerivative, fmi3GetDirectionalDerivative). Only called
    /// when `INFO.provides_directional_derivatives`; the default refuses.
    fn partial_derivatives(&mut self) -> Result<PartialDerivatives, String> {
        Err("this model provides no directional derivatives".into())
    }
}
