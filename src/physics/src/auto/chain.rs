//! The choice: front points tried cheapest first, each bounded by its chain of partners.

use super::bound::{holds_until, window_deviation, Horizon, Reach, DIRECT_LIMIT};
use super::drift::drift_rate;
use super::front::affordable;
use super::horizon::{calibration_run, horizon_counted};
use super::{
    check_front, partner, refinement, AutoError, PARTNER_ACCURACY_RATIO, TAIL_FACTOR, WINDOW_LIMIT,
};
use crate::law_source::LawSource;
use crate::scene::Scene;
use crate::study::{Configuration, FrontPoint, Measured};
use std::time::Instant;

/// One front point tried on the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    pub configuration: Configuration,
    /// Estimated largest tip deviation on this scene (m), as the selection's [`Reach`]
    /// counts it: the safety factor ([`super::SAFETY_FACTOR`], for a law with state
    /// [`super::SAFETY_FACTOR_WITH_STATE`]) times the chain's bound d(candidate, last partner) +
    /// [`TAIL_FACTOR`] * d_last, with d_last the last link's deviation.
    pub estimated_error: f64,
    /// The chain's bound on the phase drift rate (s per s of simulated time):
    /// r(candidate, last partner) + [`TAIL_FACTOR`] * r_last
    /// ([`super::drift::drift_rate`]); `None` when the slips are not comparable.
    pub drift_rate: Option<f64>,
    /// The first partner (the first link of the chain).
    pub partner: Configuration,
    /// The chain: each partner run and the deviation d (m) of the run before
    /// it from it, first partner first; for a beam or modal candidate whose chain has no
    /// plane stress, last the model-refinement point ([`refinement`]) and the
    /// candidate's deviation from it.
    pub chain: Vec<(Configuration, f64)>,
}

/// The outcome of the selection: the configuration chosen and how.
#[derive(Clone, Debug, PartialEq)]
pub struct Selection {
    /// Index of the chosen point on the front.
    pub index: usize,
    pub configuration: Configuration,
    /// Estimated largest tip deviation of the choice (m) over what [`Selection::reach`]
    /// says.
    pub estimated_error: f64,
    /// The horizon asked for.
    pub asked: Horizon,
    /// How the bound reaches it from the calibration window.
    pub reach: Reach,
    /// The choice's bound on the phase drift rate (s per s), [`Candidate::drift_rate`].
    pub drift_rate: Option<f64>,
    /// With [`Reach::Window`]: until when (s) the estimate plus the projected drift
    /// stays within the tolerance (infinite without drift); else the horizon.
    pub holds_until: f64,
    /// Every point tried, cheapest first; the last is the choice.
    pub tried: Vec<Candidate>,
    /// Wall time of all calibration runs (s), the pilot's included; 0 when
    /// [`choose_cached`] had the choice.
    pub calibration_seconds: f64,
    /// Number of calibration runs made, the pilot's included.
    pub runs: usize,
    /// Simulated time of each calibration run (s), the calibration window:
    /// [`super::calibration_horizon`].
    pub window: f64,
}

/// [`choose_over`] the scene's own run, to its `time.end`.
pub fn choose(
    scene: &Scene,
    law: &LawSource,
    tolerance: f64,
    front: &[FrontPoint],
    progress: &mut dyn FnMut(&str),
) -> Result<Selection, AutoError> {
    let horizon = Horizon::Until(scene.time.end);
    choose_over(scene, law, tolerance, horizon, front, progress)
}

/// Picks the cheapest point of `front` whose largest tip deviation on `scene` over
/// `horizon` is estimated at or below `tolerance` (m) (over the calibration window
/// when the horizon is open or too long, [`Reach`]); every calibration run uses `law`
/// (the scene's, resolved once). `progress` hears one line per calibration run,
/// before it starts, so that a slow calibration shows where it is.
pub fn choose_over(
    scene: &Scene,
    law: &LawSource,
    tolerance: f64,
    horizon: Horizon,
    front: &[FrontPoint],
    progress: &mut dyn FnMut(&str),
) -> Result<Selection, AutoError> {
    check_request(tolerance, horizon)?;
    if scene.structure.is_some() {
        // A user's structure's ladder (`structure`) was verified with the memoryless
        // laws only (issue 35); the laws with state converge at first order in the step,
        // which its safety factor of 1 was not measured for.
        if super::front::ShippedFront::of(scene, law).has_state() {
            return Err(AutoError::StructureWithState {
                law: crate::choice::Choice::name(scene.friction.law),
            });
        }
        // A user's structure: the paper beam's front does not apply (`structure`).
        return super::structure::choose(scene, law, tolerance, horizon, progress);
    }
    check_front(front)?;
    let given = front;
    let started = Instant::now();
    // The front as this scene takes it: mode counts by its spectrum (`transfer`), only
    // the configurations its rules admit.
    let front = &super::front::for_scene(scene, front)?;
    check_front(front)?;
    let mut count = 0;
    let window = calibration_window(scene, law, horizon, front, started, &mut count, progress)?;
    let reach = Reach::of(horizon, window);
    let mut calibrated = scene.clone();
    calibrated.time.end = window;
    let safety = super::front::ShippedFront::of(scene, law).safety_factor();
    let mut runs = Calibration {
        safety,
        scene: &calibrated,
        law,
        front,
        measured: vec![None; front.len()],
        started,
        count,
        progress,
    };
    let mut tried = Vec::new();
    for k in 0..front.len() {
        let Some(first) = partner(front, k) else {
            break;
        };
        let (candidate, deepest) = bound_by_chain(&mut runs, k, first)?;
        let (estimated_error, drift_rate) = (candidate.estimated_error, candidate.drift_rate);
        tried.push(candidate);
        if estimated_error <= tolerance {
            let room = tolerance - estimated_error;
            return Ok(Selection {
                index: k,
                configuration: front[k].configuration,
                estimated_error,
                asked: horizon,
                reach,
                drift_rate,
                holds_until: holds_until(horizon, reach, window, drift_rate, room, &deepest),
                tried,
                calibration_seconds: started.elapsed().as_secs_f64(),
                runs: runs.count,
                window,
            });
        }
    }
    let best = tried
        .iter()
        .map(|c| c.estimated_error)
        .fold(f64::INFINITY, f64::min);
    let shipped = super::front::ShippedFront::of(scene, law);
    let among = match shipped.front() {
        Ok(points) if points.as_slice() == given => format!("of the front {}", shipped.file()),
        _ => "of the given front".to_string(),
    };
    Err(AutoError::Unmet {
        tolerance,
        best,
        over: super::resolve::span(reach, window),
        among,
    })
}

/// The tolerance (m) must be positive and a bounded horizon's end (s) too.
fn check_request(tolerance: f64, horizon: Horizon) -> Result<(), AutoError> {
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(AutoError::Tolerance { tolerance });
    }
    if let Horizon::Until(end) = horizon {
        if !(end.is_finite() && end > 0.0) {
            return Err(AutoError::Horizon { end });
        }
    }
    Ok(())
}

/// The calibration window (s): a run within the direct limit is calibrated over its
/// whole length; a longer or open one over the window of its first slips, which the
/// pilot (the cheapest front point) finds, its runs counted into `count`.
fn calibration_window(
    scene: &Scene,
    law: &LawSource,
    horizon: Horizon,
    front: &[FrontPoint],
    started: Instant,
    count: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Result<f64, AutoError> {
    let cap = match horizon {
        Horizon::Until(end) if end <= DIRECT_LIMIT => return Ok(end),
        Horizon::Until(end) => end.min(WINDOW_LIMIT),
        Horizon::Open => WINDOW_LIMIT,
    };
    let mut pilot_scene = scene.clone();
    pilot_scene.time.end = cap;
    horizon_counted(
        &pilot_scene,
        law,
        (front[0].configuration, None),
        cap,
        started,
        count,
        progress,
    )
}

/// The calibration runs over the window, each front point run at most once.
struct Calibration<'a, 'p> {
    /// The estimate's safety factor for the law's front
    /// ([`super::front::ShippedFront::safety_factor`]).
    safety: f64,
    /// The scene cut to the calibration window.
    scene: &'a Scene,
    law: &'a LawSource,
    front: &'a [FrontPoint],
    /// The run of each front point, once made.
    measured: Vec<Option<Measured>>,
    started: Instant,
    /// Calibration runs made, the pilot's included.
    count: usize,
    progress: &'a mut (dyn FnMut(&str) + 'p),
}

impl Calibration<'_, '_> {
    /// Front point `k` run over the window, made on first use.
    fn run(&mut self, k: usize) -> Result<Measured, AutoError> {
        if self.measured[k].is_none() {
            self.measured[k] = Some(calibration_run(
                self.scene,
                self.law,
                self.front[k].configuration,
                "",
                self.started,
                &mut self.count,
                self.progress,
            )?);
        }
        Ok(self.measured[k].clone().expect("just measured"))
    }
}

/// Front point `k` bounded by its chain of partners from `first`, with the model
/// refinement where the chain needs one; also the deepest partner's run, from which
/// the drift's room is read.
///
/// The chain: e_k <= d(k, p) + e_p for any partner p, so the bound is
/// d(k, last) + [`TAIL_FACTOR`] d_last, the same for the drift rate r, each times
/// the safety factor of the law's front ([`super::front::ShippedFront::safety_factor`]).
fn bound_by_chain(
    runs: &mut Calibration,
    k: usize,
    first: usize,
) -> Result<(Candidate, Measured), AutoError> {
    let front = runs.front;
    let candidate = runs.run(k)?;
    let mut before = candidate.clone();
    let mut chain: Vec<(Configuration, f64)> = Vec::new();
    // d(k, deepest partner so far).
    let mut direct = f64::NAN;
    let mut rates;
    let mut deepest;
    let mut link = first;
    loop {
        let linked = runs.run(link)?;
        let d = window_deviation(&before.tip, &linked.tip);
        let previous = direct;
        direct = window_deviation(&candidate.tip, &linked.tip);
        rates = (
            drift_rate(&candidate, &linked),
            drift_rate(&before, &linked),
        );
        chain.push((front[link].configuration, d));
        deepest = linked.clone();
        // The previous partner is verified when its deviation from its own partner
        // is small against its deviation from the candidate; otherwise the chain
        // goes on, where that is affordable.
        let verified = chain.len() >= 2 && d <= previous / PARTNER_ACCURACY_RATIO;
        match partner(front, link) {
            Some(next) if !verified && affordable(front, next, first) => {
                before = linked;
                link = next;
            }
            _ => break,
        }
    }
    let last = chain.last().map_or(f64::NAN, |(_, d)| *d);
    let mut bound = direct + TAIL_FACTOR * last;
    if let Some(refined) = refine(runs, k, &candidate, &mut chain)? {
        bound = bound.max(refined);
    }
    let candidate = Candidate {
        configuration: front[k].configuration,
        estimated_error: runs.safety * bound,
        drift_rate: match rates {
            (Some(direct), Some(last)) => Some(runs.safety * (direct + TAIL_FACTOR * last)),
            _ => None,
        },
        partner: front[first].configuration,
        chain,
    };
    Ok((candidate, deepest))
}

/// The model-refinement bound (m) on front point `k`, its link pushed onto `chain`;
/// `None` where the chain needs none or the front has no refinement point.
///
/// Beam and modal points can share a model error (shear on a stubby beam) that no
/// chain among them sees. A chain without plane stress (full or modal, both have
/// shear) is checked against the cheapest plane-stress point 5x more accurate on the
/// paper scene, if any ([`refinement`]). With rho the paper-scene error ratio of k to
/// m (>= 5) and e_m <= e_k / rho: e_k <= d(k, m) rho / (rho - 1).
fn refine(
    runs: &mut Calibration,
    k: usize,
    candidate: &Measured,
    chain: &mut Vec<(Configuration, f64)>,
) -> Result<Option<f64>, AutoError> {
    let front = runs.front;
    let refined = |c: &Configuration| c.resolution.is_continuum();
    if refined(&front[k].configuration) || chain.iter().any(|(c, _)| refined(c)) {
        return Ok(None);
    }
    let Some(m) = refinement(front, k) else {
        return Ok(None);
    };
    let d = window_deviation(&candidate.tip, &runs.run(m)?.tip);
    chain.push((front[m].configuration, d));
    let rho = front[k].rms_error / front[m].rms_error;
    Ok(Some(d * rho / (rho - 1.0)))
}
