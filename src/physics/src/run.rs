//! A scene run from start to end under a resolved friction law (`LawSource`): the
//! simulation, its summary and wall time. The command line, the study and `auto` all run
//! scenes this way.

use crate::choice::Choice;
use crate::friction::FrictionLawKind;
use crate::law_source::LawSource;
use crate::metrics::Summary;
use crate::neural::SceneLawError;
use crate::scene::CheckedScene;
use crate::simulation::{Sample, SensorReading, SimulationError, Simulator};
use crate::structure::StructuralModel;
use std::time::Instant;

/// Why a scene could not be run.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Law(#[from] SceneLawError),
    #[error(transparent)]
    Simulation(#[from] SimulationError),
    /// `friction.law = external` outside the FMU that supplies its inputs.
    #[error("{}", external_refused())]
    External,
}

fn external_refused() -> String {
    let others: Vec<&str> = FrictionLawKind::ALL
        .iter()
        .filter(|law| **law != FrictionLawKind::External)
        .map(|law| law.name())
        .collect();
    format!(
        "friction.law = {}: the friction force comes from the inputs external.kinetic_force and external.static_limit of the StickSlipBeam FMU, and a stand-alone run has none; choose one of {}",
        FrictionLawKind::External.name(),
        others.join(", ")
    )
}

/// A finished run: samples, summary and wall time.
pub struct Run {
    pub samples: Vec<Sample>,
    pub summary: Summary,
    /// Wall time of the simulation (s), model build included.
    pub seconds: f64,
    pub label: String,
    /// Degrees of freedom of the structural model.
    pub dofs: usize,
    /// The law's state variables, as indices in `memory::STATE_VARIABLES` and in each
    /// sample's `law_state` (`Simulator::law_state_slots`); empty for a memoryless law.
    pub law_state_slots: Vec<usize>,
    /// The `[structure]`'s sensors' readings at each sample, in the section's sensor
    /// order; empty without sensors.
    pub sensors: Vec<Vec<SensorReading>>,
}

/// Runs a checked scene to its end time under `law` (resolved from this scene, or
/// shared with others of the same friction settings), keeping every `every`-th sample.
/// `external` is refused: only the FMU has the inputs it reads.
pub fn run_scene(scene: CheckedScene, law: &LawSource, every: usize) -> Result<Run, RunError> {
    run_with(scene, None, law, every)
}

/// [`run_scene`] on a given structural model (the scene's fidelity is then ignored:
/// `Simulator::with_model`); `auto` runs the modal models of a structure too wide for the
/// band this way, each reduced once for its whole ladder.
pub fn run_scene_on(
    scene: CheckedScene,
    model: StructuralModel,
    law: &LawSource,
    every: usize,
) -> Result<Run, RunError> {
    run_with(scene, Some(model), law, every)
}

fn run_with(
    scene: CheckedScene,
    model: Option<StructuralModel>,
    law: &LawSource,
    every: usize,
) -> Result<Run, RunError> {
    if law.is_external() {
        return Err(RunError::External);
    }
    let law = law.law()?;
    let started = Instant::now();
    let mut sim = match model {
        Some(model) => Simulator::with_model(scene, model, law)?,
        None => Simulator::new(scene, law)?,
    };
    // The summary's slip phases and major slips need every transition of the run.
    sim.keep_all_transitions();
    let (samples, sensors) = sim.run_observed(every)?;
    let seconds = started.elapsed().as_secs_f64();
    // The summary wants every step; with decimated samples it is computed on those.
    let summary = Summary::new(&samples, sim.transitions());
    Ok(Run {
        samples,
        summary,
        seconds,
        label: format!("{}, {} friction", sim.model().label, sim.law_name()),
        dofs: sim.model().dofs(),
        law_state_slots: sim.law_state_slots(),
        sensors,
    })
}
