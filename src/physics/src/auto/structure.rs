//! `fidelity = auto` on a user's structure (a scene with `[structure]`): the cheapest
//! of the structure's modal reductions and full model, each at a time step from a
//! ladder, whose largest tip deviation from the full model's converged run over the
//! horizon meets the tolerance.
//!
//! The paper front does not apply: its points are resolutions of the built-in beam, and
//! its errors and costs were measured on it. So the candidates are measured on the
//! scene itself, against a reference that is itself checked:
//!
//! 1. **Reference.** The full model (the structure's matrices as given) at
//!    [`REFERENCE_START`], the step halved ([`STEPS`]) until two successive halvings
//!    show convergence: with d_j the largest tip deviation between the full runs at
//!    steps h_j and h_j / 2, and r = d_(j-1) / d_j the observed contraction, the finer
//!    run's own error is at most the tail d_j (1/r + 1/r^2 + ...) = d_j / (r - 1) if
//!    the contraction continues. r is capped at [`ASSUMED_CONTRACTION`] (4, halving a
//!    second-order scheme's step) and must be at least [`MIN_CONTRACTION`] (2) to count
//!    as converging at all. The refinement stops when that bound e_ref is at most
//!    1/[`PARTNER_ACCURACY_RATIO`] of the tolerance, or at the finest step.
//! 2. **Candidates.** k modes (k from [`MODE_LADDER`], plus the static correction the
//!    scene asks for) and the full model, each at every step of the ladder down to the
//!    reference's; tried cheapest first by [`cost`]. A candidate's bound is
//!    e <= d(candidate, reference) + e_ref (the triangle inequality; the largest
//!    deviation is a norm), times [`SAFETY_FACTOR`] (1).
//! 3. **Choice.** The first candidate whose bound is at most the tolerance; if none is
//!    (the reference itself included, whose bound is e_ref), the tolerance is refused
//!    with the best bound reached.
//!
//! The horizon is the beam's ([`Reach`]): a run up to [`DIRECT_LIMIT`] is calibrated
//! over its whole length, a longer or open one over the window of its first three major
//! slips (a pilot run of the cheapest candidate finds it), with the drift rate of the
//! choice against the reference reported beside, as a projection, not a bound.

use super::bound::{holds_until, window_deviation, Horizon, Reach, DIRECT_LIMIT};
use super::drift::drift_rate;
use super::horizon::{calibration_run, horizon_counted};
use super::{AutoError, Candidate, Selection, PARTNER_ACCURACY_RATIO, SAFETY_FACTOR, WINDOW_LIMIT};
use crate::law_source::LawSource;
use crate::run::RunError;
use crate::scene::{FidelityLevel, Scene};
use crate::simulation::SimulationError;
use crate::structure::StructuralModel;
use crate::study::{Configuration, Failed, MeasureError, Measured, Resolution};
use std::time::Instant;

/// The mode counts tried (those below the structure's DOFs): 2 resolves the first
/// bending mode and its static shape, and each next count about doubles the band of
/// frequencies kept. On the CalculiX paper beam the largest tip deviation from the
/// full run at 1e-4 s falls 3.96e-4, 2.72e-6, 2.1e-8, 7.4e-9 m over 2, 5, 10, 20 modes
/// (tests/physics/structure_modal.rs), so 40 ends the ladder well past the accuracy the
/// step allows.
pub const MODE_LADDER: [usize; 5] = [2, 5, 10, 20, 40];

/// The time steps (s), coarsest first: each divides the comparison interval (1e-3 s) so
/// that every run is sampled on the same grid, and from 1e-4 s on each is half the one
/// before, so that the reference's refinement halves the step.
pub const STEPS: [f64; 7] = [5e-4, 2e-4, 1e-4, 5e-5, 2.5e-5, 1.25e-5, 6.25e-6];

/// The reference's first step (s): the paper scene's.
pub const REFERENCE_START: f64 = 1e-4;

/// Halving the step of a second-order scheme divides its error by 4 in the asymptotic
/// range; an observed contraction above that is taken as 4 (a lucky cancellation is
/// not evidence of faster convergence).
pub const ASSUMED_CONTRACTION: f64 = 4.0;

/// Below this contraction between successive halvings the full runs are not taken as
/// converging (a slip that moves by a step, not by a fraction of one), and the
/// reference's error is not bounded from them.
pub const MIN_CONTRACTION: f64 = 2.0;

/// Work per step beside the structure's band (the contact solve, the law, the
/// bookkeeping), in units of one band entry: measured on the CalculiX paper beam at
/// 1e-4 s (test profile), a modal run of 3 to 21 DOFs takes 1.5 to 2.8 us per step and
/// the full model (1002 DOFs, half-bandwidth 15) 98 us, about 1.4 us plus 6 ns per band
/// entry: 1.4 us is about 230 entries.
pub const STEP_OVERHEAD: f64 = 230.0;

/// The relative cost of `resolution` at step `dt` over `end` s: steps times
/// ([`STEP_OVERHEAD`] + band entries), the band entries being the model's DOFs times
/// its half-bandwidth + 1 (a modal model is diagonal). Deterministic, so that the choice
/// does not depend on the machine's load.
pub fn cost(resolution: Resolution, dt: f64, end: f64, full_dofs: usize, full_band: usize) -> f64 {
    let entries = match resolution {
        Resolution::StructureModal { modes } => (modes + 1) as f64,
        _ => (full_dofs * (full_band + 1)) as f64,
    };
    (end / dt).ceil() * (STEP_OVERHEAD + entries)
}

/// The error bound (m) of the finer of two full runs whose deviation is `last`, the one
/// before that having deviated by `previous`: `last / (r - 1)` with r = previous / last
/// capped at [`ASSUMED_CONTRACTION`]; infinite below [`MIN_CONTRACTION`] (no evidence of
/// convergence) or without a previous deviation.
pub fn reference_bound(previous: Option<f64>, last: f64) -> f64 {
    if last == 0.0 {
        return 0.0;
    }
    match previous {
        Some(previous) if previous / last >= MIN_CONTRACTION => {
            last / ((previous / last).min(ASSUMED_CONTRACTION) - 1.0)
        }
        _ => f64::INFINITY,
    }
}

/// The full model, at `dt`, with the scene's integrator.
fn full_at(scene: &Scene, dt: f64) -> Configuration {
    Configuration {
        resolution: Resolution::Structure,
        dt,
        scheme: scene.integrator.scheme,
        inference: None,
    }
}

/// The calibration runs, each made once.
struct Runs<'a, 'p> {
    scene: Scene,
    law: &'a LawSource,
    made: Vec<(Configuration, Measured)>,
    started: Instant,
    count: usize,
    progress: &'a mut (dyn FnMut(&str) + 'p),
}

impl Runs<'_, '_> {
    fn run(&mut self, configuration: Configuration) -> Result<Measured, AutoError> {
        if let Some((_, m)) = self.made.iter().find(|(c, _)| *c == configuration) {
            return Ok(m.clone());
        }
        let measured = calibration_run(
            &self.scene,
            self.law,
            configuration,
            "",
            self.started,
            &mut self.count,
            self.progress,
        )?;
        self.made.push((configuration, measured.clone()));
        Ok(measured)
    }
}

/// [`super::choose_over`] for a scene with a `[structure]` (module doc).
pub fn choose(
    scene: &Scene,
    law: &LawSource,
    tolerance: f64,
    horizon: Horizon,
    progress: &mut dyn FnMut(&str),
) -> Result<Selection, AutoError> {
    let started = Instant::now();
    let mut full_scene = scene.clone();
    full_scene.fidelity.level = FidelityLevel::PlaneStress;
    // Its size and band price the candidates; a structure that does not build is
    // reported as the reference's first run would report it.
    let full = StructuralModel::build(&full_scene.check()?).map_err(|e| {
        AutoError::Calibration(Failed {
            configuration: Box::new(full_at(scene, REFERENCE_START)),
            reason: MeasureError::Run(RunError::Simulation(SimulationError::Model(e))),
        })
    })?;
    let (dofs, band) = (full.dofs(), full.stiffness.half_bandwidth());
    let modes: Vec<usize> = MODE_LADDER.into_iter().filter(|&k| k < dofs).collect();
    let mut count = 0;
    let window = calibration_window(scene, law, horizon, &modes, started, &mut count, progress)?;
    let mut calibrated = scene.clone();
    calibrated.time.end = window;
    let mut runs = Runs {
        scene: calibrated,
        law,
        made: Vec::new(),
        started,
        count,
        progress,
    };
    let (reference, e_ref) = converged_reference(&mut runs, tolerance)?;
    let mut candidates = ladder(scene, &modes, reference.dt);
    let price = |c: &Configuration| cost(c.resolution, c.dt, window, dofs, band);
    candidates.sort_by(|a, b| price(a).total_cmp(&price(b)));
    let reach = Reach::of(horizon, window);
    let (tried, chosen) = pick(&mut runs, candidates, reference, e_ref, tolerance)?;
    let Some(index) = chosen else {
        let best = tried
            .iter()
            .map(|c| c.estimated_error)
            .fold(f64::INFINITY, f64::min);
        return Err(AutoError::Unmet {
            tolerance,
            best,
            over: super::resolve::span(reach, window),
            among: "of the structure's modal reductions and full model".to_string(),
        });
    };
    let choice = tried.last().expect("the choice was tried").clone();
    let room = tolerance - choice.estimated_error;
    let reference_run = runs.run(reference)?;
    Ok(Selection {
        index,
        configuration: choice.configuration,
        estimated_error: choice.estimated_error,
        asked: horizon,
        reach,
        drift_rate: choice.drift_rate,
        holds_until: holds_until(
            horizon,
            reach,
            window,
            choice.drift_rate,
            room,
            &reference_run,
        ),
        tried,
        calibration_seconds: started.elapsed().as_secs_f64(),
        runs: runs.count,
        window,
    })
}

/// The calibration window (s), as the beam's `auto` takes it: a run up to
/// [`DIRECT_LIMIT`] whole; a longer or open one up to 1.5 times the third major-slip
/// onset of a pilot run, the cheapest candidate at the coarsest step (its runs counted
/// into `count`).
fn calibration_window(
    scene: &Scene,
    law: &LawSource,
    horizon: Horizon,
    modes: &[usize],
    started: Instant,
    count: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Result<f64, AutoError> {
    let cap = match horizon {
        Horizon::Until(end) if end <= DIRECT_LIMIT => return Ok(end),
        Horizon::Until(end) => end.min(WINDOW_LIMIT),
        Horizon::Open => WINDOW_LIMIT,
    };
    let pilot = Configuration {
        resolution: match modes.first() {
            Some(&modes) => Resolution::StructureModal { modes },
            None => Resolution::Structure,
        },
        ..full_at(scene, STEPS[0])
    };
    let mut capped = scene.clone();
    capped.time.end = cap;
    horizon_counted(&capped, law, pilot, cap, started, count, progress)
}

/// The reference (module doc, step 1): the full model from [`REFERENCE_START`], its step
/// halved until the bound on its own error ([`reference_bound`]) is at most the
/// tolerance over [`PARTNER_ACCURACY_RATIO`], or the ladder ends; and that bound (m).
fn converged_reference(runs: &mut Runs, tolerance: f64) -> Result<(Configuration, f64), AutoError> {
    // The calibration scene: the user's, cut to the window (its integrator is theirs).
    let scheme_of = runs.scene.clone();
    let first = STEPS
        .iter()
        .position(|&dt| dt == REFERENCE_START)
        .expect("the ladder holds the reference's first step");
    let mut reference = full_at(&scheme_of, STEPS[first]);
    let mut reference_run = runs.run(reference)?;
    let mut previous: Option<f64> = None;
    let mut e_ref = f64::INFINITY;
    for &dt in &STEPS[first + 1..] {
        let finer = full_at(&scheme_of, dt);
        let finer_run = runs.run(finer)?;
        let d = window_deviation(&reference_run.tip, &finer_run.tip);
        (runs.progress)(&format!(
            "fidelity = auto: the full model at {dt:e} s deviates {d:.3e} m from the step before"
        ));
        e_ref = reference_bound(previous, d);
        previous = Some(d);
        reference = finer;
        reference_run = finer_run;
        if e_ref <= tolerance / PARTNER_ACCURACY_RATIO {
            break;
        }
    }
    Ok((reference, e_ref))
}

/// The candidates (module doc, step 2): each mode count of `modes` and the full model at
/// every step of [`STEPS`] down to `finest`.
fn ladder(scene: &Scene, modes: &[usize], finest: f64) -> Vec<Configuration> {
    let mut candidates = Vec::new();
    for &dt in STEPS.iter().filter(|&&dt| dt >= finest) {
        for &k in modes {
            candidates.push(Configuration {
                resolution: Resolution::StructureModal { modes: k },
                ..full_at(scene, dt)
            });
        }
        candidates.push(full_at(scene, dt));
    }
    candidates
}

/// The choice (module doc, step 3): `candidates` run in order, each bounded by its
/// deviation from the `reference` run plus the reference's bound `e_ref` (m), until one is
/// within `tolerance`. Every candidate tried, and the index of the one chosen (the last
/// tried) if any.
fn pick(
    runs: &mut Runs,
    candidates: Vec<Configuration>,
    reference: Configuration,
    e_ref: f64,
    tolerance: f64,
) -> Result<(Vec<Candidate>, Option<usize>), AutoError> {
    let reference_run = runs.run(reference)?;
    let mut tried = Vec::new();
    for (index, configuration) in candidates.into_iter().enumerate() {
        let run = runs.run(configuration)?;
        let d = window_deviation(&run.tip, &reference_run.tip);
        let estimated_error = SAFETY_FACTOR * (d + e_ref);
        tried.push(Candidate {
            configuration,
            estimated_error,
            drift_rate: drift_rate(&run, &reference_run),
            partner: reference,
            chain: vec![(reference, d)],
        });
        if estimated_error <= tolerance {
            return Ok((tried, Some(index)));
        }
    }
    Ok((tried, None))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_bound_is_the_geometric_tail_of_the_observed_contraction() {
        // r = 3: the tail d (1/3 + 1/9 + ...) = d / 2.
        assert_eq!(reference_bound(Some(3e-6), 1e-6), 0.5e-6);
        // r = 10 is taken as 4: d / 3.
        assert_eq!(reference_bound(Some(1e-5), 1e-6), 1e-6 / 3.0);
        // No contraction, or none measured yet: no bound.
        assert_eq!(reference_bound(Some(1.5e-6), 1e-6), f64::INFINITY);
        assert_eq!(reference_bound(None, 1e-6), f64::INFINITY);
        // Two identical runs: nothing left to converge.
        assert_eq!(reference_bound(Some(1e-6), 0.0), 0.0);
    }

    #[test]
    fn a_modal_step_costs_less_than_a_full_one_and_halving_the_step_doubles_the_cost() {
        let modal = Resolution::StructureModal { modes: 10 };
        let a = cost(modal, 1e-4, 1.2, 1002, 15);
        assert_eq!(cost(modal, 5e-5, 1.2, 1002, 15), 2.0 * a);
        assert!(cost(Resolution::Structure, 1e-4, 1.2, 1002, 15) > 10.0 * a);
    }
}
