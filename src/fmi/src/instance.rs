//! One FMU instance: the FMI 2.0 co-simulation state machine (standard, section 4.2.4),
//! with FMI 3.0's Event Mode and early return for FMI 3.0 instances (`EventOptions`,
//! `Mode::EventMode`, `do_step3`), logging, and FMU state, over a `Model`. Plain Rust, so that every rule can be tested
//! without a C importer; `ffi` only converts arguments.
//!
//! Decisions where the standard leaves room:
//! - Any call in a mode that does not allow it returns Error with the logged reason
//!   "illegal call sequence" and puts the instance in the Error mode.
//! - In the Error mode an instance accepts what the standard's state table allows
//!   there and nothing else: fmi2Reset, fmi2FreeInstance, fmi2SetDebugLogging, the
//!   reads (fmi2Get*, which then report the values as they were, without computing
//!   anything) and the FMU-state functions, so that a state kept as bytes can be
//!   deserialized and set: the standard's way back from an error. Stepping, setting
//!   and the mode changes are refused.
//! - Functions whose capability flag is false (directional derivatives, input and
//!   output derivatives, asynchronous steps) return Error and log why.
//! - Errors are logged in category logStatusError, which is on even when the importer
//!   instantiates with loggingOn = false; fmi2SetDebugLogging(false, 0, NULL) turns it
//!   off too. The other categories are on only when asked for.

use crate::model::Model;
use crate::model_description::{guid, LOG_CATEGORIES};
use crate::variables::{lookup, AccessError, BaseType, Causality, Variable};
pub use crate::version::FmiVersion;
use serde::{Deserialize, Serialize};
use std::path::Path;

const ERROR: usize = 0;
const WARNING: usize = 1;
const EVENTS: usize = 2;
const CALLS: usize = 3;

/// fmi2Status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
}

/// Where an instance is in the co-simulation state machine: FMI 2.0's (section 4.2.4),
/// which FMI 3.0 co-simulation shares with Step Mode as `StepComplete`, plus FMI 3.0's
/// Event Mode (section 4.2, only for an instance instantiated with eventModeUsed).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    Instantiated,
    InitializationMode,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
    /// FMI 3.0 Event Mode: entered from initialisation or by fmi3EnterEventMode, left by
    /// fmi3EnterStepMode. Inputs can be set and outputs read; time does not advance.
    EventMode,
}

/// The FMI calls the state machine tells apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    SetupExperiment,
    EnterInitializationMode,
    ExitInitializationMode,
    Terminate,
    Get,
    Set,
    GetState,
    SetState,
    FreeState,
    SerializeState,
    DoStep,
    GetStatus,
    EnterEventMode,
    UpdateDiscreteStates,
    EnterStepMode,
}

impl Call {
    fn name(self) -> &'static str {
        match self {
            Call::SetupExperiment => "fmi2SetupExperiment",
            Call::EnterInitializationMode => "fmi2EnterInitializationMode",
            Call::ExitInitializationMode => "fmi2ExitInitializationMode",
            Call::Terminate => "fmi2Terminate",
            Call::Get => "fmi2Get*",
            Call::Set => "fmi2Set*",
            Call::GetState => "fmi2GetFMUstate",
            Call::SetState => "fmi2SetFMUstate",
            Call::FreeState => "fmi2FreeFMUstate",
            Call::SerializeState => "fmi2(De)SerializeFMUstate",
            Call::DoStep => "fmi2DoStep",
            Call::GetStatus => "fmi2Get*Status",
            Call::EnterEventMode => "fmi3EnterEventMode",
            Call::UpdateDiscreteStates => "fmi3UpdateDiscreteStates",
            Call::EnterStepMode => "fmi3EnterStepMode",
        }
    }

    /// The modes in which the call is legal. `EventMode` occurs only in FMI 3.0
    /// instances that use event mode; there, as in Step Mode, inputs can be set, outputs
    /// read, the FMU state saved and restored, and the instance terminated (FMI 3.0,
    /// section 4.2: the co-simulation state machine). Time only advances in Step Mode.
    pub fn allowed_in(self) -> &'static [Mode] {
        use Mode::*;
        match self {
            Call::SetupExperiment | Call::EnterInitializationMode => &[Instantiated],
            Call::ExitInitializationMode => &[InitializationMode],
            Call::Terminate => &[StepComplete, StepFailed, EventMode],
            Call::Get => &[
                InitializationMode,
                StepComplete,
                StepFailed,
                Terminated,
                Error,
                EventMode,
            ],
            Call::Set => &[Instantiated, InitializationMode, StepComplete, EventMode],
            Call::GetState | Call::SerializeState | Call::SetState | Call::FreeState => &[
                Instantiated,
                InitializationMode,
                StepComplete,
                StepFailed,
                Terminated,
                Error,
                EventMode,
            ],
            Call::DoStep => &[StepComplete],
            Call::GetStatus => &[StepComplete, StepFailed, Terminated],
            Call::EnterEventMode => &[StepComplete],
            Call::UpdateDiscreteStates | Call::EnterStepMode => &[EventMode],
        }
    }
}

/// Receives log messages: (status, category, message).
pub type Logger = Box<dyn FnMut(Status, &str, &str) + Send>;

/// A saved FMU state: plain, versioned data (serialised as JSON), restorable in a fresh
/// instance or another process.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SavedState {
    pub format: String,
    pub version: u32,
    pub guid: String,
    pub mode: Mode,
    pub time: f64,
    pub start_time: f64,
    pub stop_time: Option<f64>,
    pub model: serde_json::Value,
    /// FMI 3.0 with event mode: a step ended at an event that the importer has not yet
    /// handled in Event Mode. Written only when true, so FMI 2.0 states are unchanged.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub event_pending: bool,
}

pub const STATE_FORMAT: &str = "stickslip-fmu-state";
/// The version this FMU writes.
/// - 2: StickSlipBeam's friction model, `auto` flag and tolerance moved into its scene
///   (`friction.law`, `fidelity.level = auto`, `fidelity.tolerance`), so an FMU that
///   reads only version 1 refuses these states by their version rather than as
///   malformed.
/// - 3: StickSlipBeam no longer lists every stick/slip transition made so far (a list
///   that grew with simulated time); the simulation state's count replaces it, so the
///   state's size no longer depends on how long the run has gone.
pub const STATE_VERSION: u32 = 3;
/// The oldest version this FMU still reads (version-1 and version-2 beam states are
/// converted; their transition lists are checked against the count, then dropped).
pub const OLDEST_STATE_VERSION: u32 = 1;

impl SavedState {
    pub fn to_bytes(&self) -> Vec<u8> {
        // A SavedState holds only strings, numbers and JSON values: it always serialises.
        serde_json::to_vec(self).unwrap_or_default()
    }

    /// Reads bytes written by `to_bytes`, refusing anything else with a reason.
    pub fn from_bytes(bytes: &[u8]) -> Result<SavedState, StateError> {
        let state: SavedState = serde_json::from_slice(bytes).map_err(StateError::Malformed)?;
        if state.format != STATE_FORMAT {
            return Err(StateError::Format {
                found: state.format,
            });
        }
        if !(OLDEST_STATE_VERSION..=STATE_VERSION).contains(&state.version) {
            return Err(StateError::Version {
                found: state.version,
            });
        }
        if !state.time.is_finite() || !state.start_time.is_finite() {
            return Err(StateError::NonFiniteTime);
        }
        state.check_clock()?;
        Ok(state)
    }

    /// The instance clock of a state must be one the instance could have reached: no
    /// time before the start, none past the stop, and no time but the start before
    /// initialisation ends.
    fn check_clock(&self) -> Result<(), StateError> {
        let (start, time) = (self.start_time, self.time);
        if !(start.is_finite() && time.is_finite()) {
            return Err(StateError::ClockNotFinite { time, start });
        }
        let slack = 1e-9 * time.abs().max(start.abs()).max(1.0);
        if time < start - slack {
            return Err(StateError::BeforeStart { time, start });
        }
        if let Some(stop) = self.stop_time {
            if !(stop.is_finite() && stop > start) {
                return Err(StateError::StopNotAfterStart { stop, start });
            }
            if time > stop + slack {
                return Err(StateError::PastStop { time, stop });
            }
        }
        let before_steps = matches!(self.mode, Mode::Instantiated | Mode::InitializationMode);
        if before_steps && (time - start).abs() > slack {
            return Err(StateError::NotAtStart {
                mode: self.mode,
                time,
                start,
            });
        }
        Ok(())
    }
}

/// Why bytes are not a state this FMU can restore (times in s).
#[derive(Debug, thiserror::Error)]
pub enum StateError {
    #[error("serialized FMU state is malformed: {0}")]
    Malformed(#[source] serde_json::Error),
    #[error("serialized FMU state has format \"{found}\", expected \"{STATE_FORMAT}\"")]
    Format { found: String },
    #[error("serialized FMU state has version {found}, this FMU reads versions {OLDEST_STATE_VERSION} to {STATE_VERSION}")]
    Version { found: u32 },
    #[error("serialized FMU state has a non-finite time")]
    NonFiniteTime,
    #[error("the state's time {time} s or start time {start} s is not finite")]
    ClockNotFinite { time: f64, start: f64 },
    #[error("the state's time {time} s is before its start time {start} s")]
    BeforeStart { time: f64, start: f64 },
    #[error("the state's stop time {stop} s is not after its start time {start} s")]
    StopNotAfterStart { stop: f64, start: f64 },
    #[error("the state's time {time} s is past its stop time {stop} s")]
    PastStop { time: f64, stop: f64 },
    #[error("the state was saved in {mode:?} mode at time {time} s, but before stepping the time must equal the start time {start} s")]
    NotAtStart { mode: Mode, time: f64, start: f64 },
}

/// fmi3UpdateDiscreteStates's output arguments.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DiscreteUpdate {
    pub discrete_states_need_update: bool,
    pub terminate_simulation: bool,
    pub nominals_of_continuous_states_changed: bool,
    pub values_of_continuous_states_changed: bool,
    /// The next time event (s), if any.
    pub next_event_time: Option<f64>,
}

/// Status kinds of fmi2Get*Status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StatusKind {
    DoStepStatus,
    PendingStatus,
    LastSuccessfulTime,
    Terminated,
}

/// How an FMI 3.0 importer instantiated a co-simulation instance
/// (fmi3InstantiateCoSimulation's eventModeUsed and earlyReturnAllowed). FMI 2.0
/// instances use neither.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EventOptions {
    /// The importer handles events in Event Mode: fmi3ExitInitializationMode enters Event
    /// Mode, and a step that ends at an event asks for it (eventHandlingNeeded).
    pub event_mode_used: bool,
    /// The importer accepts a step that ends before its communication point: the model
    /// then stops at its internal events (`Model::do_step_until_event`).
    pub early_return_allowed: bool,
}

/// What an FMI 3.0 step did (fmi3DoStep's output arguments).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepOutcome {
    /// The step ended before currentCommunicationPoint + communicationStepSize.
    pub early_return: bool,
    /// The step ended at an event and the importer uses event mode: it is asked to
    /// enter Event Mode before the next step.
    pub event_handling_needed: bool,
    /// Where the step ended (s).
    pub last_successful_time: f64,
}

/// An FMU instance of model `M`.
pub struct Instance<M: Model> {
    name: String,
    version: FmiVersion,
    events: EventOptions,
    event_pending: bool,
    guid: String,
    model: M,
    mode: Mode,
    logger: Logger,
    categories: [bool; LOG_CATEGORIES.len()],
    start_time: f64,
    stop_time: Option<f64>,
    time: f64,
}

/// The result of a call that failed: already logged, the instance is in Error mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Failed;

pub type CallResult<T> = Result<T, Failed>;

impl<M: Model> Instance<M> {
    /// fmi2Instantiate: loads the resources (network weights) or fails with a logged
    /// reason.
    pub fn new(
        name: &str,
        resources: Option<&Path>,
        logging_on: bool,
        mut logger: Logger,
    ) -> Result<Self, String> {
        let mut model = M::with_defaults();
        let loaded = match resources {
            Some(dir) => model.load_resources(dir),
            None => Err("fmuResourceLocation is NULL: no resource location was given; the FMU reads its network weights from its resources/ folder".into()),
        };
        if let Err(reason) = loaded {
            let message = format!("fmi2Instantiate: {reason}");
            logger(Status::Error, LOG_CATEGORIES[ERROR].0, &message);
            return Err(message);
        }
        let mut categories = [logging_on; LOG_CATEGORIES.len()];
        categories[ERROR] = true;
        Ok(Self {
            name: name.to_owned(),
            version: FmiVersion::V2,
            events: EventOptions::default(),
            event_pending: false,
            guid: guid::<M>(),
            model,
            mode: Mode::Instantiated,
            logger,
            categories,
            start_time: 0.0,
            stop_time: None,
            time: 0.0,
        })
    }

    pub fn name(&self) -> &str {
        &self.name
    }

    /// The same instance, logging FMI 3.0 function names (`ffi3`).
    pub fn with_version(mut self, version: FmiVersion) -> Self {
        self.version = version;
        self
    }

    pub fn version(&self) -> FmiVersion {
        self.version
    }

    /// The same instance with FMI 3.0's event options (fmi3InstantiateCoSimulation).
    pub fn with_events(mut self, events: EventOptions) -> Self {
        self.events = events;
        self
    }

    /// Sets FMI 3.0's event options right after instantiation (the ffi layer).
    pub fn set_events(&mut self, events: EventOptions) {
        self.events = events;
    }

    pub fn events(&self) -> EventOptions {
        self.events
    }

    /// A step ended at an event that has not been handled in Event Mode yet.
    pub fn event_pending(&self) -> bool {
        self.event_pending
    }

    pub fn mode(&self) -> Mode {
        self.mode
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn model(&self) -> &M {
        &self.model
    }

    fn log(&mut self, category: usize, status: Status, message: &str) {
        if self.categories[category] {
            (self.logger)(status, LOG_CATEGORIES[category].0, message);
        }
    }

    /// Logs a call in the logCalls category (the ffi layer formats the arguments).
    pub fn log_call(&mut self, message: impl FnOnce() -> String) {
        if self.categories[CALLS] {
            let text = self.version.rename(&message());
            self.log(CALLS, Status::Ok, &text);
        }
    }

    /// Logs `reason`, enters the Error mode and returns the failure.
    pub fn fail(&mut self, call: &str, reason: &str) -> Failed {
        let message = self.version.rename(&format!("{call}: {reason}"));
        self.log(ERROR, Status::Error, &message);
        self.mode = Mode::Error;
        Failed
    }

    fn warn(&mut self, message: &str) {
        let message = self.version.rename(message);
        self.log(WARNING, Status::Warning, &message);
    }

    /// Checks that `call` is legal now.
    pub fn check(&mut self, call: Call) -> CallResult<()> {
        if call.allowed_in().contains(&self.mode) {
            return Ok(());
        }
        let reason = format!(
            "illegal call sequence: called in mode {:?}; allowed in {:?}",
            self.mode,
            call.allowed_in()
        );
        Err(self.fail(call.name(), &reason))
    }

    /// fmi2SetDebugLogging. Unknown categories are ignored with a warning.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[&str]) -> Status {
        if categories.is_empty() {
            self.categories = [on; LOG_CATEGORIES.len()];
            return Status::Ok;
        }
        let mut status = Status::Ok;
        for name in categories {
            match LOG_CATEGORIES.iter().position(|(c, _)| c == name) {
                Some(k) => self.categories[k] = on,
                None => {
                    let known: Vec<&str> = LOG_CATEGORIES.iter().map(|(c, _)| *c).collect();
                    self.warn(&format!(
                        "fmi2SetDebugLogging: unknown log category \"{name}\" ignored; the categories are {}",
                        known.join(", ")
                    ));
                    status = Status::Warning;
                }
            }
        }
        status
    }

    /// fmi2SetupExperiment. The tolerance is not used: the step size is a parameter.
    pub fn setup_experiment(&mut self, start_time: f64, stop_time: Option<f64>) -> CallResult<()> {
        self.check(Call::SetupExperiment)?;
        const CALL: &str = "fmi2SetupExperiment";
        if !start_time.is_finite() {
            return Err(self.fail(CALL, &format!("startTime = {start_time} is not finite")));
        }
        if let Some(stop) = stop_time {
            if !(stop.is_finite() && stop > start_time) {
                return Err(self.fail(
                    CALL,
                    &format!("stopTime = {stop} must be finite and greater than startTime = {start_time}"),
                ));
            }
        }
        self.start_time = start_time;
        self.stop_time = stop_time;
        self.time = start_time;
        Ok(())
    }

    pub fn enter_initialization_mode(&mut self) -> CallResult<()> {
        self.check(Call::EnterInitializationMode)?;
        self.mode = Mode::InitializationMode;
        Ok(())
    }

    /// fmi2ExitInitializationMode: every parameter is checked here, with the scene's
    /// messages.
    pub fn exit_initialization_mode(&mut self) -> CallResult<()> {
        self.check(Call::ExitInitializationMode)?;
        let result = self.model.initialize(self.start_time, self.stop_time);
        for note in self.model.take_notes() {
            self.log(EVENTS, Status::Ok, &note);
        }
        if let Err(reason) = result {
            return Err(self.fail("fmi2ExitInitializationMode", &reason));
        }
        // FMI 3.0 co-simulation with eventModeUsed enters Event Mode here, without it
        // Step Mode (section 4.2).
        self.mode = if self.events.event_mode_used {
            Mode::EventMode
        } else {
            Mode::StepComplete
        };
        Ok(())
    }

    /// fmi3EnterEventMode (only with eventModeUsed): from Step Mode, at the current time;
    /// clears the request of a step that ended at an event.
    pub fn enter_event_mode(&mut self) -> CallResult<()> {
        if !self.events.event_mode_used {
            return Err(self.fail(
                "fmi3EnterEventMode",
                "the instance was instantiated with eventModeUsed = false",
            ));
        }
        self.check(Call::EnterEventMode)?;
        self.mode = Mode::EventMode;
        self.event_pending = false;
        Ok(())
    }

    /// fmi3UpdateDiscreteStates. The models have no discrete states that the inputs
    /// set in Event Mode could change (the beam's stick/slip state is decided within its
    /// steps), so one call settles everything: no further iteration, no time event, no
    /// change of the continuous states.
    pub fn update_discrete_states(&mut self) -> CallResult<DiscreteUpdate> {
        self.check(Call::UpdateDiscreteStates)?;
        Ok(DiscreteUpdate::default())
    }

    /// fmi3EnterStepMode: back to Step Mode at the current time.
    pub fn enter_step_mode(&mut self) -> CallResult<()> {
        self.check(Call::EnterStepMode)?;
        self.mode = Mode::StepComplete;
        Ok(())
    }

    pub fn terminate(&mut self) -> CallResult<()> {
        self.check(Call::Terminate)?;
        self.mode = Mode::Terminated;
        Ok(())
    }

    /// fmi2Reset: back to the state right after instantiation (start values, no
    /// experiment), keeping the loaded resources and the logging settings.
    pub fn reset(&mut self) {
        self.model.reset();
        self.mode = Mode::Instantiated;
        self.event_pending = false;
        self.start_time = 0.0;
        self.stop_time = None;
        self.time = 0.0;
    }

    fn access_failed(&mut self, call: &str, error: AccessError) -> Failed {
        self.fail(call, &error.to_string())
    }

    /// Prepares a get: when outputs are asked for, they are made current first (not in
    /// the Error mode, which only reports).
    fn before_get(&mut self, call: &str, vrs: &[u32], base: BaseType) -> CallResult<()> {
        self.check(Call::Get)?;
        let mut outputs = false;
        for &vr in vrs {
            match lookup(M::variables(), vr, base) {
                Ok(v) => outputs |= v.causality == Causality::Output,
                Err(e) => return Err(self.access_failed(call, e)),
            }
        }
        if outputs && self.mode != Mode::Error {
            if let Err(reason) = self.model.refresh_outputs(self.start_time, self.stop_time) {
                return Err(self.fail(call, &reason));
            }
        }
        Ok(())
    }

    fn get_with<T>(
        &mut self,
        call: &str,
        vrs: &[u32],
        out: &mut [T],
        base: BaseType,
        read: fn(&Variable<M>, &M) -> T,
    ) -> CallResult<()> {
        if vrs.len() != out.len() {
            return Err(self.fail(call, "value buffer and value references differ in length"));
        }
        self.before_get(call, vrs, base)?;
        for (slot, &vr) in out.iter_mut().zip(vrs) {
            // Looked up successfully in before_get.
            if let Ok(v) = lookup(M::variables(), vr, base) {
                *slot = read(v, &self.model);
            }
        }
        Ok(())
    }

    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> CallResult<()> {
        self.get_with("fmi2GetReal", vrs, out, BaseType::Real, Variable::get_real)
    }

    pub fn get_integer(&mut self, vrs: &[u32], out: &mut [i32]) -> CallResult<()> {
        self.get_with(
            "fmi2GetInteger",
            vrs,
            out,
            BaseType::Integer,
            Variable::get_integer,
        )
    }

    pub fn get_boolean(&mut self, vrs: &[u32], out: &mut [bool]) -> CallResult<()> {
        self.get_with(
            "fmi2GetBoolean",
            vrs,
            out,
            BaseType::Boolean,
            Variable::get_boolean,
        )
    }

    pub fn get_string(&mut self, vrs: &[u32]) -> CallResult<Vec<String>> {
        let mut out = vec![String::new(); vrs.len()];
        self.get_with(
            "fmi2GetString",
            vrs,
            &mut out,
            BaseType::String,
            Variable::get_string,
        )?;
        Ok(out)
    }

    /// Checks that variable `vr` may be set now: fixed parameters only before
    /// initialisation ends, inputs at any settable time, outputs never.
    fn settable(
        &mut self,
        call: &str,
        vr: u32,
        base: BaseType,
    ) -> CallResult<&'static Variable<M>> {
        let variable = match lookup(M::variables(), vr, base) {
            Ok(v) => v,
            Err(e) => return Err(self.access_failed(call, e)),
        };
        let when_ok = match variable.causality {
            Causality::Parameter => {
                matches!(self.mode, Mode::Instantiated | Mode::InitializationMode)
            }
            Causality::Input => true,
            Causality::Output => false,
        };
        if !variable.access.is_settable() || variable.causality == Causality::Output {
            return Err(self.access_failed(
                call,
                AccessError::NotSettable {
                    name: variable.name,
                    causality: variable.causality,
                },
            ));
        }
        if !when_ok {
            let reason = format!(
                "{} is a fixed parameter; it can be set only before fmi2ExitInitializationMode (mode is {:?})",
                variable.name, self.mode
            );
            return Err(self.fail(call, &reason));
        }
        Ok(variable)
    }

    fn set_with<T: Copy>(
        &mut self,
        call: &str,
        vrs: &[u32],
        values: &[T],
        base: BaseType,
        write: fn(&Variable<M>, &mut M, T) -> Result<(), AccessError>,
    ) -> CallResult<()> {
        self.check(Call::Set)?;
        if vrs.len() != values.len() {
            return Err(self.fail(call, "value buffer and value references differ in length"));
        }
        for (&vr, &value) in vrs.iter().zip(values) {
            let variable = self.settable(call, vr, base)?;
            if let Err(e) = write(variable, &mut self.model, value) {
                return Err(self.access_failed(call, e));
            }
        }
        Ok(())
    }

    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> CallResult<()> {
        self.set_with(
            "fmi2SetReal",
            vrs,
            values,
            BaseType::Real,
            Variable::set_real,
        )
    }

    pub fn set_integer(&mut self, vrs: &[u32], values: &[i32]) -> CallResult<()> {
        self.set_with(
            "fmi2SetInteger",
            vrs,
            values,
            BaseType::Integer,
            Variable::set_integer,
        )
    }

    pub fn set_boolean(&mut self, vrs: &[u32], values: &[bool]) -> CallResult<()> {
        self.set_with(
            "fmi2SetBoolean",
            vrs,
            values,
            BaseType::Boolean,
            Variable::set_boolean,
        )
    }

    pub fn set_string(&mut self, vrs: &[u32], values: &[&str]) -> CallResult<()> {
        self.check(Call::Set)?;
        const CALL: &str = "fmi2SetString";
        if vrs.len() != values.len() {
            return Err(self.fail(CALL, "value buffer and value references differ in length"));
        }
        for (&vr, value) in vrs.iter().zip(values) {
            let variable = self.settable(CALL, vr, BaseType::String)?;
            if let Err(e) = variable.set_string(&mut self.model, value) {
                return Err(self.access_failed(CALL, e));
            }
        }
        Ok(())
    }

    /// fmi2DoStep: the communication point must match the instance's time (within 1e-9
    /// relative), h must be positive and finite, and the step must not pass stopTime.
    pub fn do_step(&mut self, current: f64, h: f64) -> CallResult<()> {
        self.step(current, h, false).map(|_| ())
    }

    /// fmi3DoStep: fmi2DoStep's checks and step, except that with earlyReturnAllowed the
    /// step ends at the model's first internal event (the beam: a stick/slip switch), and
    /// with eventModeUsed a step that ends at an event asks for Event Mode; the next step
    /// is refused until the importer has entered it. Without earlyReturnAllowed the step
    /// always reaches its communication point (events inside it are the model's own
    /// business), so the results are FMI 2.0's.
    pub fn do_step3(&mut self, current: f64, h: f64) -> CallResult<StepOutcome> {
        if self.event_pending {
            self.check(Call::DoStep)?;
            let reason = format!(
                "illegal call sequence: the last step ended at an event at t = {} s (eventHandlingNeeded = true); call fmi3EnterEventMode, fmi3UpdateDiscreteStates and fmi3EnterStepMode first",
                self.time
            );
            return Err(self.fail("fmi3DoStep", &reason));
        }
        let target = current + h;
        let event = self.step(current, h, self.events.early_return_allowed)?;
        let event_handling_needed = event.is_some() && self.events.event_mode_used;
        self.event_pending = event_handling_needed;
        Ok(StepOutcome {
            early_return: self.time < target && event.is_some(),
            event_handling_needed,
            last_successful_time: self.time,
        })
    }

    /// The step of fmi2DoStep and fmi3DoStep; `until_event`: end at the model's first
    /// internal event and return its time.
    fn step(&mut self, current: f64, h: f64, until_event: bool) -> CallResult<Option<f64>> {
        self.check(Call::DoStep)?;
        const CALL: &str = "fmi2DoStep";
        let tolerance = 1e-9 * self.time.abs().max(1.0);
        if !current.is_finite() || (current - self.time).abs() > tolerance {
            return Err(self.fail(
                CALL,
                &format!(
                    "currentCommunicationPoint = {current} s does not match the FMU's time {} s",
                    self.time
                ),
            ));
        }
        if !(h > 0.0 && h.is_finite()) {
            return Err(self.fail(
                CALL,
                &format!("communicationStepSize = {h} s must be positive and finite"),
            ));
        }
        let target = current + h;
        if let Some(stop) = self.stop_time {
            if target > stop + 1e-9 * stop.abs().max(1.0) {
                return Err(self.fail(
                    CALL,
                    &format!("the step to t = {target} s passes stopTime = {stop} s"),
                ));
            }
        }
        let mut events = Vec::new();
        let result = if until_event {
            self.model.do_step_until_event(target, &mut events)
        } else {
            self.model.do_step(target, &mut events).map(|()| None)
        };
        for event in &events {
            self.log(EVENTS, Status::Ok, event);
        }
        match result {
            Ok(None) => {
                self.time = target;
                Ok(None)
            }
            Ok(Some(at)) => {
                self.time = at;
                Ok(Some(at))
            }
            Err(reason) => Err(self.fail(CALL, &reason)),
        }
    }

    /// fmi2GetRealStatus and friends. Only LastSuccessfulTime (Real) and Terminated
    /// (Boolean, always false: the FMU never ends a simulation by itself) are known;
    /// other kinds give Discard, as the standard asks for an unavailable status.
    pub fn real_status(&mut self, kind: StatusKind) -> Result<f64, Status> {
        self.check(Call::GetStatus).map_err(|_| Status::Error)?;
        match kind {
            StatusKind::LastSuccessfulTime => Ok(self.time),
            _ => Err(self.unavailable_status("fmi2GetRealStatus", kind)),
        }
    }

    pub fn boolean_status(&mut self, kind: StatusKind) -> Result<bool, Status> {
        self.check(Call::GetStatus).map_err(|_| Status::Error)?;
        match kind {
            StatusKind::Terminated => Ok(false),
            _ => Err(self.unavailable_status("fmi2GetBooleanStatus", kind)),
        }
    }

    /// Status kinds that this FMU never provides (no asynchronous steps).
    pub fn unavailable_status(&mut self, call: &str, kind: StatusKind) -> Status {
        if self.check(Call::GetStatus).is_err() {
            return Status::Error;
        }
        self.warn(&format!(
            "{call}: status kind {kind:?} is not available (steps are synchronous)"
        ));
        Status::Discard
    }

    /// fmi2GetFMUstate.
    pub fn get_state(&mut self) -> CallResult<SavedState> {
        self.check(Call::GetState)?;
        Ok(SavedState {
            format: STATE_FORMAT.into(),
            version: STATE_VERSION,
            guid: self.guid.clone(),
            mode: self.mode,
            time: self.time,
            start_time: self.start_time,
            stop_time: self.stop_time,
            model: self.model.save(),
            event_pending: self.event_pending,
        })
    }

    /// fmi2SetFMUstate: also the way back from the Error mode.
    pub fn set_state(&mut self, state: &SavedState) -> CallResult<()> {
        self.check(Call::SetState)?;
        const CALL: &str = "fmi2SetFMUstate";
        if state.guid != self.guid {
            return Err(self.fail(
                CALL,
                &format!(
                    "the state belongs to the FMU with GUID {}, this is {}",
                    state.guid, self.guid
                ),
            ));
        }
        if state.mode == Mode::Error {
            return Err(self.fail(CALL, "a state saved in the Error mode cannot be restored"));
        }
        if let Err(e) = state.check_clock() {
            return Err(self.fail(CALL, &e.to_string()));
        }
        if (state.mode == Mode::EventMode || state.event_pending) && !self.events.event_mode_used {
            return Err(self.fail(
                CALL,
                "the state was saved in or before Event Mode, but this instance was instantiated with eventModeUsed = false",
            ));
        }
        if let Err(reason) = self
            .model
            .restore(state.model.clone(), state.version, state.time)
        {
            return Err(self.fail(CALL, &reason));
        }
        self.mode = state.mode;
        self.event_pending = state.event_pending;
        self.time = state.time;
        self.start_time = state.start_time;
        self.stop_time = state.stop_time;
        Ok(())
    }

    /// Checks the mode for fmi2FreeFMUstate (the ffi layer frees the memory).
    pub fn free_state(&mut self) -> CallResult<()> {
        self.check(Call::FreeState)
    }

    pub fn serialize_state(&mut self, state: &SavedState) -> CallResult<Vec<u8>> {
        self.check(Call::SerializeState)?;
        Ok(state.to_bytes())
    }

    pub fn deserialize_state(&mut self, bytes: &[u8]) -> CallResult<SavedState> {
        self.check(Call::SerializeState)?;
        SavedState::from_bytes(bytes)
            .map_err(|e| self.fail("fmi2DeSerializeFMUstate", &e.to_string()))
    }
}
