//! One run of the grid, timed, and the tip series it gives the comparison.

use super::configuration::Configuration;
use crate::law_source::LawSource;
use crate::metrics::Summary;
use crate::run::{run_scene, run_scene_on, RunError};
use crate::scene::{CheckedScene, Scene, SceneError};
use crate::structure::StructuralModel;

/// The grid of the tip-deflection comparison (s): every time step of a study divides it.
pub const COMPARISON_INTERVAL: f64 = 1e-3;

/// What one run gives the comparison.
#[derive(Clone, Debug)]
pub struct Measured {
    pub configuration: Configuration,
    pub dofs: usize,
    /// Wall time of model build and stepping (s).
    pub seconds: f64,
    pub summary: Summary,
    /// Tip deflection at k * [`COMPARISON_INTERVAL`], k = 0, 1, ... (m).
    pub tip: Vec<f64>,
}

/// Why a configuration could not run.
#[derive(Debug, thiserror::Error)]
pub enum MeasureError {
    /// The scene with this configuration applied does not pass [`Scene::check`].
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The time step does not divide [`COMPARISON_INTERVAL`], so that the run's samples
    /// would miss the comparison grid.
    #[error("time step {dt} s does not divide the comparison interval {COMPARISON_INTERVAL} s")]
    Interval { dt: f64 },
    /// The friction law could not be built or the simulation failed.
    #[error(transparent)]
    Run(#[from] RunError),
}

/// A configuration that could not run, and why.
#[derive(Debug, thiserror::Error)]
#[error("{configuration}: {reason}")]
pub struct Failed {
    /// Boxed so that the error stays small (clippy's result_large_err: it travels in
    /// `auto::AutoError` through every `Result` of the selection).
    pub configuration: Box<Configuration>,
    #[source]
    pub reason: MeasureError,
}

/// Runs `configuration` on `scene` (checked) under `law` (the scene's, resolved once for
/// every configuration; a configuration's inference replaces the law's), timing it.
pub fn measure(
    scene: &Scene,
    law: &LawSource,
    configuration: Configuration,
) -> Result<Measured, Failed> {
    measure_with(scene, law, configuration, None)
}

/// [`measure`] on a given structural model, which stands for the configuration's
/// resolution (the time step, scheme and inference are the configuration's): how `auto`
/// runs the modal models of a structure too wide for the band, reduced once for its
/// whole ladder.
pub fn measure_on(
    scene: &Scene,
    law: &LawSource,
    configuration: Configuration,
    model: StructuralModel,
) -> Result<Measured, Failed> {
    measure_with(scene, law, configuration, Some(model))
}

fn measure_with(
    scene: &Scene,
    law: &LawSource,
    configuration: Configuration,
    model: Option<StructuralModel>,
) -> Result<Measured, Failed> {
    let failed = |reason: MeasureError| Failed {
        configuration: Box::new(configuration),
        reason,
    };
    let checked: CheckedScene = configuration
        .apply(scene)
        .check()
        .map_err(|e| failed(e.into()))?;
    let every = COMPARISON_INTERVAL / configuration.dt;
    if (every - every.round()).abs() > 1e-9 * every || every.round() < 1.0 {
        return Err(failed(MeasureError::Interval {
            dt: configuration.dt,
        }));
    }
    let every = every.round() as usize;
    // Every step is kept so that the summary (corridor, slip detection) does not depend
    // on the time step through its sampling.
    let law = law.with_inference(checked.friction.inference);
    let run = match model {
        Some(model) => run_scene_on(checked, model, &law, 1),
        None => run_scene(checked, &law, 1),
    }
    .map_err(|e| failed(e.into()))?;
    let tip = run
        .samples
        .iter()
        .step_by(every)
        .map(|s| s.tip_deflection)
        .collect();
    Ok(Measured {
        configuration,
        dofs: run.dofs,
        seconds: run.seconds,
        summary: run.summary,
        tip,
    })
}
