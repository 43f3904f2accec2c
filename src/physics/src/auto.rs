//! `fidelity = auto`: the cheapest configuration of the measured Pareto front whose
//! tip-deflection error, measured on the scene at hand, meets a tolerance.
//!
//! The front is the one `stickslip study` measured on the paper scene
//! (`data/pareto_front.json`, cheapest first). Its ordering by cost holds for any scene
//! (cost follows degrees of freedom and steps); its errors do not, since geometry,
//! material and belt speed move the frequencies that a model must resolve. So the
//! errors are measured again, on the scene itself:
//!
//! 1. For front point k, the comparison partner j(k) is the first later point whose
//!    paper-scene error is at most a tenth of point k's (the last point if none is).
//!    Then the partner's own error is about 1/10 of k's or less, and
//!    e_k ~ RMS(tip_k - tip_j(k)) estimates k's true error to ~10 %.
//! 2. Points are tried cheapest first; the first with e_k <= tolerance is chosen. Each
//!    run is done once and reused.
//!
//! A scene asks for this with `fidelity.level = auto` and `fidelity.tolerance`;
//! [`resolve`] turns it into the concrete scene that runs.
//!
//! The last point has no partner, so a tolerance that no earlier point meets is refused
//! with the best estimate, rather than answered with an unverified guess. The
//! calibration costs the runs it made (at most the chosen point's partner and the
//! points before it); the result says how long it took.

use crate::scene::{FidelityLevel, Scene, SceneError};
use crate::study::{
    measure, rms_difference, Configuration, Failed, FrontPoint, MeasureError, Measured,
};
use std::time::Instant;

/// The front measured on the paper scene by `stickslip study --write-front`.
pub const PAPER_FRONT_JSON: &str = include_str!("../../../data/pareto_front.json");

/// A partner must be at least this much more accurate (paper-scene RMS) than the point
/// whose error it estimates.
pub const PARTNER_ACCURACY_RATIO: f64 = 10.0;

/// Why `fidelity = auto` could not choose (or, in [`verify`], check its choice).
#[derive(Debug, thiserror::Error)]
pub enum AutoError {
    /// The shipped front is not valid JSON of front points.
    #[error("data/pareto_front.json: {0}")]
    FrontJson(#[source] serde_json::Error),
    #[error("the front needs at least two points")]
    FrontTooShort,
    /// `first` comes before `second` on the front but is not cheaper and less accurate.
    #[error(
        "the front is not ordered: {} ({} s, {} m) before {} ({} s, {} m)",
        .first.configuration, .first.seconds, .first.rms_error,
        .second.configuration, .second.seconds, .second.rms_error
    )]
    FrontUnordered {
        first: FrontPoint,
        second: FrontPoint,
    },
    /// The tolerance (m) is not finite and positive.
    #[error("fidelity tolerance = {tolerance} m; it must be finite and > 0")]
    Tolerance { tolerance: f64 },
    /// A calibration run of a front point failed.
    #[error("fidelity = auto, running {0}")]
    Calibration(#[source] Failed),
    /// No point with a partner meets `tolerance` (m); `best` is the smallest estimated
    /// RMS error (m).
    #[error("fidelity = auto: no configuration of the front is verified to meet the tolerance {tolerance:e} m on this scene; the best estimated RMS tip-deflection error is {best:.3e} m. Choose a larger tolerance or a fidelity by hand.")]
    Unmet { tolerance: f64, best: f64 },
    /// [`verify`] could not run the choice or the next cheaper point.
    #[error(transparent)]
    Verification(MeasureError),
    /// The scene to choose for is itself invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// An `auto` scene without `fidelity.tolerance`.
    #[error("fidelity = auto needs fidelity.tolerance: the RMS tip-deflection error allowed (m)")]
    NoTolerance,
}

/// The paper-scene front, cheapest first.
pub fn paper_front() -> Result<Vec<FrontPoint>, AutoError> {
    let front: Vec<FrontPoint> =
        serde_json::from_str(PAPER_FRONT_JSON).map_err(AutoError::FrontJson)?;
    check_front(&front)?;
    Ok(front)
}

/// A usable front: at least two points, cost rising and error falling along it.
pub fn check_front(front: &[FrontPoint]) -> Result<(), AutoError> {
    if front.len() < 2 {
        return Err(AutoError::FrontTooShort);
    }
    for pair in front.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if !(a.seconds <= b.seconds && a.rms_error > b.rms_error) {
            return Err(AutoError::FrontUnordered {
                first: *a,
                second: *b,
            });
        }
    }
    Ok(())
}

/// The comparison partner of front point `k`, if it has one.
pub fn partner(front: &[FrontPoint], k: usize) -> Option<usize> {
    if k + 1 >= front.len() {
        return None;
    }
    let target = front[k].rms_error / PARTNER_ACCURACY_RATIO;
    Some(
        (k + 1..front.len())
            .find(|&j| front[j].rms_error <= target)
            .unwrap_or(front.len() - 1),
    )
}

/// One front point tried on the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    pub configuration: Configuration,
    /// RMS tip-deflection difference from its partner on this scene (m).
    pub estimated_error: f64,
    pub partner: Configuration,
}

/// The outcome of the selection: the configuration chosen and how.
#[derive(Clone, Debug, PartialEq)]
pub struct Selection {
    /// Index of the chosen point on the front.
    pub index: usize,
    pub configuration: Configuration,
    /// Estimated RMS tip-deflection error of the choice (m).
    pub estimated_error: f64,
    /// Every point tried, cheapest first; the last is the choice.
    pub tried: Vec<Candidate>,
    /// Wall time of all calibration runs (s).
    pub calibration_seconds: f64,
}

/// Picks the cheapest point of `front` whose tip-deflection error on `scene` (RMS over
/// the scene's time span, m) is estimated at or below `tolerance` (m).
pub fn choose(scene: &Scene, tolerance: f64, front: &[FrontPoint]) -> Result<Selection, AutoError> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(AutoError::Tolerance { tolerance });
    }
    check_front(front)?;
    let started = Instant::now();
    let mut runs: Vec<Option<Measured>> = vec![None; front.len()];
    let mut run = |k: usize| -> Result<Measured, AutoError> {
        if runs[k].is_none() {
            let measured =
                measure(scene, front[k].configuration).map_err(AutoError::Calibration)?;
            runs[k] = Some(measured);
        }
        Ok(runs[k].clone().expect("just measured"))
    };
    let mut tried = Vec::new();
    for k in 0..front.len() {
        let Some(j) = partner(front, k) else { break };
        let candidate = run(k)?;
        let reference = run(j)?;
        let estimated_error = rms_difference(&candidate.tip, &reference.tip);
        tried.push(Candidate {
            configuration: front[k].configuration,
            estimated_error,
            partner: front[j].configuration,
        });
        if estimated_error <= tolerance {
            return Ok(Selection {
                index: k,
                configuration: front[k].configuration,
                estimated_error,
                tried,
                calibration_seconds: started.elapsed().as_secs_f64(),
            });
        }
    }
    let best = tried
        .iter()
        .map(|c| c.estimated_error)
        .fold(f64::INFINITY, f64::min);
    Err(AutoError::Unmet { tolerance, best })
}

/// The choice for a scene at its own `fidelity.tolerance` (m). The scene is checked
/// first, so that a bad scene is reported as such, not as a failed calibration run.
pub fn choose_for(scene: &Scene, front: &[FrontPoint]) -> Result<Selection, AutoError> {
    let checked = scene.clone().check()?;
    let tolerance = checked.fidelity.tolerance.ok_or(AutoError::NoTolerance)?;
    choose(scene, tolerance, front)
}

/// Resolves `fidelity.level = auto`: the scene with the fidelity, time step and
/// integrator of the choice (every other field kept), and the choice. A scene with a
/// concrete level comes back as it is, with no choice.
pub fn resolve(
    scene: Scene,
    front: &[FrontPoint],
) -> Result<(Scene, Option<Selection>), AutoError> {
    if scene.fidelity.level != FidelityLevel::Auto {
        return Ok((scene, None));
    }
    let choice = choose_for(&scene, front)?;
    Ok((choice.configuration.apply(&scene), Some(choice)))
}

/// What was chosen and why, in one paragraph for a log.
pub fn describe(choice: &Selection, tolerance: f64) -> String {
    let mut out = format!(
        "fidelity = auto (tolerance {tolerance:e} m RMS tip deflection): chose {}, estimated error {:.3e} m; calibration {:.2} s",
        choice.configuration, choice.estimated_error, choice.calibration_seconds
    );
    for c in &choice.tried[..choice.tried.len().saturating_sub(1)] {
        out += &format!(
            "; rejected {} (estimated {:.3e} m)",
            c.configuration, c.estimated_error
        );
    }
    out
}

/// The scenes on which `stickslip study --verify-auto` checks the choice: the paper's,
/// and three that move the answer (faster belt: more, shorter cycles; shorter beam:
/// stiffer tip, higher frequencies; larger normal force: later breakaway, larger
/// deflections).
pub fn verification_scenes() -> Vec<(&'static str, Scene)> {
    let paper = Scene::default();
    let mut fast_belt = paper.clone();
    fast_belt.loading.belt_speed = 0.05;
    let mut short_beam = paper.clone();
    short_beam.geometry.length = 1.5;
    let mut pressed = paper.clone();
    pressed.loading.normal_force = 180.0;
    vec![
        ("paper", paper),
        ("belt 0.05 m/s", fast_belt),
        ("beam 1.5 m", short_beam),
        ("normal force 180 N", pressed),
    ]
}

/// The choice on one scene, checked against the scene's own converged reference.
#[derive(Clone, Debug)]
pub struct Verification {
    pub choice: Selection,
    /// RMS tip-deflection error of the choice against the reference (m).
    pub true_error: f64,
    /// The next cheaper front point and its error against the reference (m).
    pub cheaper: Option<(Configuration, f64)>,
}

impl Verification {
    /// The choice meets the tolerance and the next cheaper point does not.
    pub fn holds(&self, tolerance: f64) -> bool {
        self.true_error <= tolerance && self.cheaper.is_none_or(|(_, e)| e > tolerance)
    }
}

/// Runs [`choose`] on `scene`, then measures the choice and the next cheaper point
/// against `reference` (an already measured run of the same scene).
pub fn verify(
    scene: &Scene,
    tolerance: f64,
    front: &[FrontPoint],
    reference: &Measured,
) -> Result<Verification, AutoError> {
    let choice = choose(scene, tolerance, front)?;
    let error_of = |configuration: Configuration| -> Result<f64, AutoError> {
        let run = measure(scene, configuration).map_err(|f| AutoError::Verification(f.reason))?;
        Ok(rms_difference(&run.tip, &reference.tip))
    };
    let true_error = error_of(choice.configuration)?;
    let cheaper = match choice.index.checked_sub(1) {
        Some(k) => Some((front[k].configuration, error_of(front[k].configuration)?)),
        None => None,
    };
    Ok(Verification {
        choice,
        true_error,
        cheaper,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scheme;
    use crate::study::Resolution;

    fn point(elements: usize, seconds: f64, rms_error: f64) -> FrontPoint {
        FrontPoint {
            configuration: Configuration {
                resolution: Resolution::Beam { elements },
                dt: 1e-3,
                scheme: Scheme::GeneralizedAlpha,
                inference: None,
            },
            seconds,
            rms_error,
        }
    }

    #[test]
    fn the_partner_is_the_first_point_ten_times_more_accurate() {
        let front = [
            point(1, 1.0, 1.0),
            point(2, 2.0, 0.5),
            point(3, 3.0, 0.1),
            point(4, 4.0, 0.04),
            point(5, 5.0, 0.02),
        ];
        assert_eq!(partner(&front, 0), Some(2));
        assert_eq!(partner(&front, 1), Some(3));
        // None is ten times better: the last point.
        assert_eq!(partner(&front, 2), Some(4));
        assert_eq!(partner(&front, 4), None);
    }

    #[test]
    fn an_unordered_front_or_a_bad_tolerance_is_refused() {
        let unordered = [point(1, 1.0, 1.0), point(2, 2.0, 2.0)];
        let e = check_front(&unordered).unwrap_err();
        assert!(matches!(e, AutoError::FrontUnordered { .. }), "{e}");
        assert!(e.to_string().contains("not ordered"), "{e}");
        assert!(matches!(
            check_front(&unordered[..1]),
            Err(AutoError::FrontTooShort)
        ));
        let front = [point(1, 1.0, 1.0), point(2, 2.0, 0.5)];
        for tolerance in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = choose(&Scene::default(), tolerance, &front).unwrap_err();
            assert!(matches!(e, AutoError::Tolerance { .. }), "{e}");
            assert!(e.to_string().contains("tolerance"), "{e}");
        }
    }

    #[test]
    fn the_shipped_front_is_ordered_and_reachable() {
        let front = paper_front().unwrap();
        assert!(front.len() >= 3);
        for p in &front {
            assert!(Configuration::apply(&p.configuration, &Scene::default())
                .check()
                .is_ok());
        }
    }
}
