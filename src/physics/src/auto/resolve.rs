//! Resolving `fidelity = auto` for a scene: the tolerance, the per-process cache and the log line.

use super::bound::{Horizon, Reach, DIRECT_LIMIT};
use super::{choose_over, AutoError, Selection, DEFAULT_TOLERANCE};
use crate::law_source::LawSource;
use crate::scene::{FidelityLevel, Scene};
use crate::study::FrontPoint;
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

/// The tolerance of an `auto` scene: its own, or [`DEFAULT_TOLERANCE`].
pub fn tolerance_of(scene: &Scene) -> f64 {
    scene.fidelity.tolerance.unwrap_or(DEFAULT_TOLERANCE)
}

/// The choices made in this process, by scene (as JSON, tolerance included), law
/// ([`LawSource::fingerprint`]: another network is another choice) and front.
fn cache() -> &'static Mutex<HashMap<String, Selection>> {
    static CACHE: OnceLock<Mutex<HashMap<String, Selection>>> = OnceLock::new();
    CACHE.get_or_init(|| Mutex::new(HashMap::new()))
}

/// [`choose_over`] `horizon` at the scene's own tolerance ([`tolerance_of`]), once per
/// scene, law, tolerance, horizon and front in the process: later calls (another FMU instance of the same scene, a
/// reset) get the first call's choice with `calibration_seconds` = 0 and no runs. The
/// scene is checked first, so that a bad scene is reported as such, not as a failed
/// calibration run.
pub fn choose_cached(
    scene: &Scene,
    law: &LawSource,
    horizon: Horizon,
    front: &[FrontPoint],
    progress: &mut dyn FnMut(&str),
) -> Result<Selection, AutoError> {
    scene.clone().check()?;
    let tolerance = tolerance_of(scene);
    let mut keyed = scene.clone();
    keyed.fidelity.tolerance = Some(tolerance);
    // A scene or a network that does not serialize is not cached (it is still chosen for).
    let key = law
        .fingerprint()
        .and_then(|law| serde_json::to_string(&(&keyed, law, horizon, front)).ok());
    if let Some(key) = &key {
        let cached = cache().lock().ok().and_then(|c| c.get(key).cloned());
        if let Some(mut choice) = cached {
            progress("fidelity = auto: the choice for this scene, law, tolerance and horizon is already made in this process");
            choice.calibration_seconds = 0.0;
            choice.runs = 0;
            return Ok(choice);
        }
    }
    let choice = choose_over(&keyed, law, tolerance, horizon, front, progress)?;
    if let (Some(key), Ok(mut c)) = (key, cache().lock()) {
        c.insert(key, choice.clone());
    }
    Ok(choice)
}

/// Resolves `fidelity.level = auto`: the scene with the fidelity, time step and
/// integrator of the choice (every other field kept), and the choice; the calibration
/// runs use `law`, the scene's law resolved once, and the horizon is the scene's run,
/// to its `time.end`. A scene with a concrete level comes
/// back as it is, with no choice.
pub fn resolve(
    scene: Scene,
    law: &LawSource,
    front: &[FrontPoint],
    progress: &mut dyn FnMut(&str),
) -> Result<(Scene, Option<Selection>), AutoError> {
    if scene.fidelity.level != FidelityLevel::Auto {
        return Ok((scene, None));
    }
    let horizon = Horizon::Until(scene.time.end);
    let choice = choose_cached(&scene, law, horizon, front, progress)?;
    Ok((choice.configuration.apply(&scene), Some(choice)))
}

/// What a bound of `reach` over a calibration window of `window` s covers, in words.
pub fn span(reach: Reach, window: f64) -> String {
    match reach {
        Reach::Whole => format!("the whole run, 0 to {window:.3} s"),
        Reach::Window { asked: None } => format!(
            "the calibration window, 0 to {window:.3} s (the horizon is open: no stop time)"
        ),
        Reach::Window { asked: Some(end) } => format!(
            "the calibration window, 0 to {window:.3} s (the run's {end} s is beyond the {DIRECT_LIMIT} s that auto calibrates over)"
        ),
    }
}

/// A phase drift rate (s per s) in words: milliseconds of shift per second simulated.
fn drift_words(rate: Option<f64>) -> String {
    match rate {
        Some(rate) => format!("{:.3} ms per s of simulated time", rate * 1e3),
        None => "unknown (the runs' slips do not match)".into(),
    }
}

/// What was chosen, what is promised over which horizon, and why, in one paragraph for
/// a log and the command line's summary.
pub fn describe(choice: &Selection, tolerance: f64) -> String {
    let mut out = format!(
        "fidelity = auto (tolerance {tolerance:e} m, largest tip deviation over {}): chose {}, estimated deviation {:.3e} m",
        span(choice.reach, choice.window),
        choice.configuration,
        choice.estimated_error
    );
    if let Some(last) = choice.tried.last() {
        let partners: Vec<String> = last.chain.iter().map(|(c, _)| c.to_string()).collect();
        out += &format!(" (partners: {})", partners.join(" -> "));
    }
    out += &format!(
        "; projected phase drift of the slips <= {}",
        drift_words(choice.drift_rate)
    );
    if let Reach::Window { .. } = choice.reach {
        out += &if choice.holds_until.is_finite() {
            format!(
                "; projected linearly, the deviation would reach the tolerance at about t = {:.3} s (a projection, not a bound: the slips' phase drift grows faster than linearly on most scenes)",
                choice.holds_until
            )
        } else {
            "; no phase drift measured in the window, so beyond it nothing is bounded".into()
        };
    }
    out += &format!(
        "; calibration {} runs to t = {:.3} s, {:.2} s",
        choice.runs, choice.window, choice.calibration_seconds
    );
    for c in &choice.tried[..choice.tried.len().saturating_sub(1)] {
        out += &format!(
            "; rejected {} (estimated {:.3e} m)",
            c.configuration, c.estimated_error
        );
    }
    out
}
