//! The calibration horizon and the calibration runs.

use super::drift::distinct_onsets;
use super::{AutoError, HORIZON_MARGIN, PILOT_HORIZON, SLIPS_IN_WINDOW, WINDOW_LIMIT};
use crate::law_source::LawSource;
use crate::scene::Scene;
use crate::structure::StructuralModel;
use crate::study::{measure, measure_on, Configuration, Measured, COMPARISON_INTERVAL};
use std::time::Instant;

/// Announces and makes one calibration run, counting it.
pub(super) fn calibration_run(
    scene: &Scene,
    law: &LawSource,
    configuration: Configuration,
    what: &str,
    started: Instant,
    count: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Result<Measured, AutoError> {
    calibration_run_on(
        scene,
        law,
        configuration,
        None,
        what,
        started,
        count,
        progress,
    )
}

/// [`calibration_run`] on `model` where given (`study::measure_on`: a structure too
/// wide for the band, its modal models reduced once for the whole ladder).
#[allow(clippy::too_many_arguments)]
pub(super) fn calibration_run_on(
    scene: &Scene,
    law: &LawSource,
    configuration: Configuration,
    model: Option<StructuralModel>,
    what: &str,
    started: Instant,
    count: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Result<Measured, AutoError> {
    progress(&format!(
        "fidelity = auto: calibration run {} ({configuration}{what}, to t = {} s), {:.2} s so far",
        *count + 1,
        scene.time.end,
        started.elapsed().as_secs_f64()
    ));
    let measured = match model {
        Some(model) => measure_on(scene, law, configuration, model),
        None => measure(scene, law, configuration),
    }
    .map_err(AutoError::Calibration)?;
    *count += 1;
    Ok(measured)
}

/// The simulated time (s) that the calibration runs need, the calibration window:
/// [`HORIZON_MARGIN`] times the onset of the [`SLIPS_IN_WINDOW`]-th major slip of a
/// pilot run (the cheapest front point), at most the scene's end and
/// [`WINDOW_LIMIT`]. The pilot runs to [`PILOT_HORIZON`], doubling until it shows that
/// onset with the margin inside its horizon or reaches the cap; so the calibration cost
/// follows the first two stick-slip cycles, not the user's horizon (a digital twin may
/// run for days). Rounded up to the comparison interval, which every front step
/// divides.
pub fn calibration_horizon(
    scene: &Scene,
    law: &LawSource,
    pilot: Configuration,
    progress: &mut dyn FnMut(&str),
) -> Result<f64, AutoError> {
    let cap = scene.time.end.min(WINDOW_LIMIT);
    horizon_counted(
        scene,
        law,
        (pilot, None),
        cap,
        Instant::now(),
        &mut 0,
        progress,
    )
}

/// [`calibration_horizon`] capped at `cap` (s), counting its runs into `count`; the
/// pilot runs on its model where one is given ([`calibration_run_on`]).
pub(super) fn horizon_counted(
    scene: &Scene,
    law: &LawSource,
    (pilot, pilot_model): (Configuration, Option<&StructuralModel>),
    cap: f64,
    started: Instant,
    count: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Result<f64, AutoError> {
    let end = cap;
    let mut horizon = PILOT_HORIZON.min(end);
    loop {
        let mut short = scene.clone();
        short.time.end = horizon;
        let run = calibration_run_on(
            &short,
            law,
            pilot,
            pilot_model.cloned(),
            ", the pilot",
            started,
            count,
            progress,
        )?;
        if let Some(onset) = distinct_onsets(&run).get(SLIPS_IN_WINDOW - 1) {
            let needed = HORIZON_MARGIN * onset;
            if needed <= horizon || horizon >= end {
                let steps = (needed.min(end) / COMPARISON_INTERVAL).ceil();
                return Ok((steps * COMPARISON_INTERVAL).min(end));
            }
        }
        if horizon >= end {
            return Ok(end);
        }
        horizon = (2.0 * horizon).min(end);
    }
}
