//! A scene run from start to end: the friction law it asks for, the simulation, its
//! summary and wall time. The command line, the study and `auto` all run scenes this way.

use crate::friction::{analytical_law, FrictionLaw};
use crate::metrics::Summary;
use crate::neural::SceneLawError;
use crate::scene::CheckedScene;
use crate::simulation::{Sample, SimulationError, Simulator};
use std::time::Instant;

/// Why a scene could not be run.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error(transparent)]
    Law(#[from] SceneLawError),
    #[error(transparent)]
    Simulation(#[from] SimulationError),
}

/// The friction law a scene asks for: the analytical one, or the neural law with its
/// weights.
pub fn friction_law(scene: &CheckedScene) -> Result<Box<dyn FrictionLaw>, SceneLawError> {
    match analytical_law(scene) {
        Some(law) => Ok(law),
        None => crate::neural::scene_law(scene),
    }
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
}

/// Runs a checked scene to its end time, keeping every `every`-th sample.
pub fn run_scene(scene: CheckedScene, every: usize) -> Result<Run, RunError> {
    let law = friction_law(&scene)?;
    let started = Instant::now();
    let mut sim = Simulator::new(scene, law)?;
    let samples = sim.run(every)?;
    let seconds = started.elapsed().as_secs_f64();
    // The summary wants every step; with decimated samples it is computed on those.
    let summary = Summary::new(&samples, sim.transitions());
    Ok(Run {
        samples,
        summary,
        seconds,
        label: format!("{}, {} friction", sim.model().label, sim.law_name()),
        dofs: sim.model().dofs(),
    })
}
