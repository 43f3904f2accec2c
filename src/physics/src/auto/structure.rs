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
//! # A structure too wide for the band
//!
//! A structure the band Cholesky refuses (`BandTooWide`: a 3D solid of some 30,000 DOFs
//! and up) has no full model in the time loop, so the reference above cannot run. Its
//! reference is the modal model with the static correction, converged in both of its
//! resolutions ([`converged_modal_reference`]):
//!
//! - in modes, along [`REFERENCE_MODES`] (20, 40, 80, 160, those below the DOFs), with
//!   the same tail bound as the step's: d_i the largest tip deviation between the runs
//!   of rungs i - 1 and i at the reference's step, r = d_(i-1) / d_i capped at
//!   [`ASSUMED_CONTRACTION`] and at least [`MIN_CONTRACTION`], e_modes = d_i / (r - 1);
//! - in step, as above, at the reference's mode count: e_step.
//!
//! Each refinement stops when its tail is at most half of the tolerance over
//! [`PARTNER_ACCURACY_RATIO`], or its ladder ends; they alternate, each only moving
//! finer, until neither moves, so that both tails are measured at the reference. Its
//! bound is e_ref = e_step + e_modes: with x(K, h) the run of K modes at step h and
//! x(n, 0) the converged full model (the modal model with every mode is the full one),
//! |x(K, h) - x(n, 0)| <= |x(K, h) - x(K, 0)| + |x(K, 0) - x(n, 0)|, the first term
//! bounded by the step tail, the second by the mode tail measured at h rather than at 0
//! (the assumption: the modes dropped act at the reference's step as they would in the
//! limit; at a coarse step generalised-alpha damps high modes, which is why the mode
//! tail is measured at the reference's own step, not at the first). So the promise is
//! relative to the full model through the modal convergence, under that assumption and
//! the geometric tails'. The candidates are the modal models of [`MODE_LADDER`] and the
//! rungs up to the reference's count, the scene's static correction, at every step down
//! to the reference's; all of them come from one sparse factorisation and one Lanczos
//! recurrence (`SparseSection::models`: each model the bits that `fidelity.level =
//! modal` at its count gives, which the chosen run builds again).
//!
//! The horizon is the beam's ([`Reach`]): a run up to [`DIRECT_LIMIT`] is calibrated
//! over its whole length, a longer or open one over the window of its first three major
//! slips (a pilot run of the cheapest candidate finds it), with the drift rate of the
//! choice against the reference reported beside, as a projection, not a bound.

use super::bound::{holds_until, window_deviation, Horizon, Reach, DIRECT_LIMIT};
use super::drift::drift_rate;
use super::horizon::{calibration_run_on, horizon_counted};
use super::{AutoError, Candidate, Selection, PARTNER_ACCURACY_RATIO, SAFETY_FACTOR, WINDOW_LIMIT};
use crate::law_source::LawSource;
use crate::linear_structure::scene_model::read_section;
use crate::linear_structure::sparse_modal::SparseSection;
use crate::linear_structure::{LinearStructure, StructureError};
use crate::run::RunError;
use crate::scene::{FidelityLevel, Scene};
use crate::simulation::SimulationError;
use crate::structure::{ModelError, StructuralModel};
use crate::study::{Configuration, Failed, MeasureError, Measured, Resolution};
use std::time::Instant;

/// The mode counts tried (those below the structure's DOFs): 2 resolves the first
/// bending mode and its static shape, and each next count about doubles the band of
/// frequencies kept. On the CalculiX paper beam the largest tip deviation from the
/// full run at 1e-4 s falls 3.96e-4, 2.72e-6, 2.1e-8, 7.4e-9 m over 2, 5, 10, 20 modes
/// (tests/physics/structure_modal.rs), so 40 ends the ladder well past the accuracy the
/// step allows.
pub const MODE_LADDER: [usize; 5] = [2, 5, 10, 20, 40];

/// The mode counts of the reference of a structure too wide for the band (those below
/// its DOFs), each twice the one before: the modal model with the static correction
/// converges in modes as the full model converges in step (module doc), and 20 is where
/// the CalculiX beam's and the block's runs are already limited by the step at 1e-4 s
/// (docs/structures.md).
pub const REFERENCE_MODES: [usize; 4] = [20, 40, 80, 160];

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

/// In the wide path's tails ([`modal_tail_bound`]): deviations this many times below the
/// tail's budget are round-off and the contact decisions it flips, not convergence to
/// measure.
pub const NOISE_RATIO: f64 = 100.0;

/// The tail bound of the wide path's refinements (m): [`reference_bound`], except where
/// both deviations are at most the tail's `budget` (m) over [`NOISE_RATIO`]: there the
/// larger of them, the bound at the weakest contraction that counts (2), whether or not
/// they contract. On the 1,500-DOF block at 1.25e-5 s the runs of 20, 40, 80 and 160
/// modes differ by 1.8e-14 to 3.2e-11 m in no order (the 80-mode run's stick decision at
/// 9 ms flips on round-off: 3.2e-11 m from every other), where the full model is 2.7e-14 m
/// from the 20-mode run: converged, but with no contraction to show it.
pub fn modal_tail_bound(previous: f64, last: f64, budget: f64) -> f64 {
    let floor = budget / NOISE_RATIO;
    if previous <= floor && last <= floor {
        return previous.max(last);
    }
    reference_bound(Some(previous), last)
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
    /// Each run by its configuration and the static correction of its modal model.
    made: Vec<((Configuration, bool), Measured)>,
    started: Instant,
    count: usize,
    progress: &'a mut (dyn FnMut(&str) + 'p),
    /// The wide path's modal models; `None` where the full model runs (the band's path,
    /// whose runs build their models from the scene).
    reduced: Option<ModelStore<'a>>,
}

impl Runs<'_, '_> {
    /// The run of `configuration`, a modal one with the scene's static correction.
    fn run(&mut self, configuration: Configuration) -> Result<Measured, AutoError> {
        let correction = self.scene.fidelity.static_correction;
        self.run_corrected(configuration, correction)
    }

    /// The run of `configuration`, a modal one with the static correction `correction`
    /// (the wide path's reference has it whatever the scene says).
    fn run_corrected(
        &mut self,
        configuration: Configuration,
        correction: bool,
    ) -> Result<Measured, AutoError> {
        let key = (configuration, correction);
        if let Some((_, m)) = self.made.iter().find(|(c, _)| *c == key) {
            return Ok(m.clone());
        }
        let model = match (&mut self.reduced, configuration.resolution) {
            (Some(store), Resolution::StructureModal { modes }) => {
                Some(store.get(modes, correction)?)
            }
            _ => None,
        };
        let what = if correction || model.is_none() {
            ""
        } else {
            ", without static correction"
        };
        let measured = calibration_run_on(
            &self.scene,
            self.law,
            configuration,
            model,
            what,
            self.started,
            &mut self.count,
            self.progress,
        )?;
        self.made.push((key, measured.clone()));
        Ok(measured)
    }
}

/// The modal models of a structure too wide for the band, by mode count and static
/// correction, reduced from its sparse factor, each count of one request from one
/// Lanczos recurrence (`SparseSection::models`: each model the bits of
/// `fidelity.level = modal` at its count, which the chosen run builds again).
struct ModelStore<'a> {
    reduced: &'a SparseSection,
    models: Vec<((usize, bool), StructuralModel)>,
}

impl ModelStore<'_> {
    /// Reduces the models of `wanted` (mode count, static correction) not yet held.
    fn reduce(&mut self, wanted: &[(usize, bool)]) -> Result<(), AutoError> {
        let missing: Vec<(usize, bool)> = wanted
            .iter()
            .copied()
            .filter(|w| !self.models.iter().any(|(k, _)| k == w))
            .collect();
        if missing.is_empty() {
            return Ok(());
        }
        let models = self.reduced.models(&missing).map_err(|e| {
            AutoError::Calibration(Failed {
                configuration: Box::new(Configuration {
                    resolution: Resolution::StructureModal {
                        modes: missing.iter().map(|&(k, _)| k).max().unwrap_or(0),
                    },
                    dt: REFERENCE_START,
                    scheme: crate::scene::Scheme::GeneralizedAlpha,
                    inference: None,
                }),
                reason: MeasureError::Run(RunError::Simulation(SimulationError::Model(e))),
            })
        })?;
        self.models.extend(missing.into_iter().zip(models));
        Ok(())
    }

    /// The model of `modes` modes with or without the static correction, reduced now if
    /// not yet held.
    fn get(&mut self, modes: usize, correction: bool) -> Result<StructuralModel, AutoError> {
        self.reduce(&[(modes, correction)])?;
        Ok(self
            .models
            .iter()
            .find(|(k, _)| *k == (modes, correction))
            .map(|(_, m)| m.clone())
            .expect("reduced above"))
    }
}

/// [`super::choose_over`] for a scene with a `[structure]` (module doc): against the
/// full model where the band holds the structure, and against the converged modal
/// model ([`choose_reduced`]) where the band refuses it (`BandTooWide`: a 3D solid).
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
    let checked = full_scene.check()?;
    let section = checked
        .structure
        .as_ref()
        .expect("auto::structure chooses for a scene with a [structure]");
    // Its size and band price the candidates; a structure that does not build is
    // reported as the reference's first run would report it.
    let refused = |e: ModelError| {
        AutoError::Calibration(Failed {
            configuration: Box::new(full_at(scene, REFERENCE_START)),
            reason: MeasureError::Run(RunError::Simulation(SimulationError::Model(e))),
        })
    };
    let files = read_section(section).map_err(refused)?;
    let full = match LinearStructure::new(&files.matrices, &files.clamped) {
        Ok(structure) => {
            StructuralModel::from_structure(&structure, section, &files.points).map_err(refused)?
        }
        Err(StructureError::BandTooWide { .. }) => {
            progress("fidelity = auto: the structure is too wide for the band, so its full model does not run; the reference is its modal model refined in modes and step (docs/structures.md)");
            let reduced = SparseSection::new(section, &files).map_err(refused)?;
            drop(files);
            return choose_wide(scene, law, tolerance, horizon, &reduced, started, progress);
        }
        Err(e) => return Err(refused(ModelError::UserStructure(e.to_string()))),
    };
    drop(files);
    let (dofs, band) = (full.dofs(), full.stiffness.half_bandwidth());
    let modes: Vec<usize> = MODE_LADDER.into_iter().filter(|&k| k < dofs).collect();
    let mut count = 0;
    let pilot = pilot_of(scene, &modes);
    let window = calibration_window(
        scene,
        law,
        horizon,
        (pilot, None),
        started,
        &mut count,
        progress,
    )?;
    let mut calibrated = scene.clone();
    calibrated.time.end = window;
    let mut runs = Runs {
        scene: calibrated,
        law,
        made: Vec::new(),
        started,
        count,
        progress,
        reduced: None,
    };
    let (reference, e_ref) = converged_reference(&mut runs, tolerance)?;
    let mut candidates = ladder(scene, &modes, reference.dt, true);
    let price = |c: &Configuration| cost(c.resolution, c.dt, window, dofs, band);
    candidates.sort_by(|a, b| price(a).total_cmp(&price(b)));
    let reference_run = runs.run(reference)?;
    let tried = pick(
        &mut runs,
        candidates,
        (reference, &reference_run),
        e_ref,
        tolerance,
    )?;
    select(
        tried,
        horizon,
        window,
        tolerance,
        runs,
        &reference_run,
        started,
    )
}

/// `auto` on a `[structure]` against its converged modal model (module doc, "A
/// structure too wide for the band"), whatever its band: what [`choose`] does for a
/// structure the band refuses, open to any structure so that a test can check it on one
/// small enough for its full model to run.
pub fn choose_reduced(
    scene: &Scene,
    law: &LawSource,
    tolerance: f64,
    horizon: Horizon,
    progress: &mut dyn FnMut(&str),
) -> Result<Selection, AutoError> {
    let started = Instant::now();
    let checked = scene.clone().check()?;
    let section = checked
        .structure
        .as_ref()
        .expect("auto::structure chooses for a scene with a [structure]");
    let reduced = SparseSection::read(section).map_err(|e| {
        AutoError::Calibration(Failed {
            configuration: Box::new(full_at(scene, REFERENCE_START)),
            reason: MeasureError::Run(RunError::Simulation(SimulationError::Model(e))),
        })
    })?;
    choose_wide(scene, law, tolerance, horizon, &reduced, started, progress)
}

/// The wide path (module doc): the reference refined in modes and step
/// ([`converged_modal_reference`]), the modal candidates up to its mode count, each
/// reduced from `reduced` once for the whole ladder.
fn choose_wide(
    scene: &Scene,
    law: &LawSource,
    tolerance: f64,
    horizon: Horizon,
    reduced: &SparseSection,
    started: Instant,
    progress: &mut dyn FnMut(&str),
) -> Result<Selection, AutoError> {
    let dofs = reduced.dofs();
    let rungs: Vec<usize> = REFERENCE_MODES.into_iter().filter(|&k| k < dofs).collect();
    let mut modes: Vec<usize> = MODE_LADDER
        .into_iter()
        .chain(rungs.iter().copied())
        .filter(|&k| k < dofs)
        .collect();
    modes.sort_unstable();
    modes.dedup();
    let correction = scene.fidelity.static_correction;
    // The models of the first three rungs and of every candidate up to them, from one
    // Lanczos recurrence; a fourth rung is reduced when the refinement asks for it.
    let first_rungs = &rungs[..rungs.len().min(3)];
    let mut store = ModelStore {
        reduced,
        models: Vec::new(),
    };
    let largest = first_rungs.last().copied().unwrap_or(0);
    let wanted: Vec<(usize, bool)> = first_rungs
        .iter()
        .map(|&k| (k, true))
        .chain(
            modes
                .iter()
                .filter(|&&k| k <= largest)
                .map(|&k| (k, correction)),
        )
        .collect();
    progress(&format!(
        "fidelity = auto: reducing the {dofs}-DOF structure to {largest} modes (and every count of the ladder below), {:.2} s so far",
        started.elapsed().as_secs_f64()
    ));
    store.reduce(&wanted)?;
    let mut count = 0;
    let pilot = pilot_of(scene, &modes);
    let pilot_model = match pilot.resolution {
        Resolution::StructureModal { modes } => Some(store.get(modes, correction)?),
        _ => None,
    };
    let window = calibration_window(
        scene,
        law,
        horizon,
        (pilot, pilot_model.as_ref()),
        started,
        &mut count,
        progress,
    )?;
    let mut calibrated = scene.clone();
    calibrated.time.end = window;
    let mut runs = Runs {
        scene: calibrated,
        law,
        made: Vec::new(),
        started,
        count,
        progress,
        reduced: Some(store),
    };
    let (reference, e_ref) = converged_modal_reference(&mut runs, &rungs, tolerance)?;
    let Resolution::StructureModal {
        modes: reference_modes,
    } = reference.resolution
    else {
        unreachable!("the reference of the wide path is modal")
    };
    let candidate_modes: Vec<usize> = modes
        .iter()
        .copied()
        .filter(|&k| k <= reference_modes)
        .collect();
    let mut candidates = ladder(scene, &candidate_modes, reference.dt, false);
    let price = |c: &Configuration| cost(c.resolution, c.dt, window, dofs, 0);
    candidates.sort_by(|a, b| price(a).total_cmp(&price(b)));
    let reference_run = runs.run_corrected(reference, true)?;
    let tried = pick(
        &mut runs,
        candidates,
        (reference, &reference_run),
        e_ref,
        tolerance,
    )?;
    select(
        tried,
        horizon,
        window,
        tolerance,
        runs,
        &reference_run,
        started,
    )
}

/// The pilot of the calibration window: the cheapest candidate (the fewest modes) at the
/// coarsest step, the full model if no mode count is below the structure's DOFs.
fn pilot_of(scene: &Scene, modes: &[usize]) -> Configuration {
    Configuration {
        resolution: match modes.first() {
            Some(&modes) => Resolution::StructureModal { modes },
            None => Resolution::Structure,
        },
        ..full_at(scene, STEPS[0])
    }
}

/// The choice (module doc, step 3) from the candidates `tried`, or the refusal with the
/// best bound.
fn select(
    (tried, chosen): (Vec<Candidate>, Option<usize>),
    horizon: Horizon,
    window: f64,
    tolerance: f64,
    runs: Runs,
    reference_run: &Measured,
    started: Instant,
) -> Result<Selection, AutoError> {
    let reach = Reach::of(horizon, window);
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
            reference_run,
        ),
        tried,
        calibration_seconds: started.elapsed().as_secs_f64(),
        runs: runs.count,
        window,
    })
}

/// The calibration window (s), as the beam's `auto` takes it: a run up to
/// [`DIRECT_LIMIT`] whole; a longer or open one up to 1.5 times the third major-slip
/// onset of a pilot run, the cheapest candidate at the coarsest step ([`pilot_of`], on
/// its model where given; its runs counted into `count`).
fn calibration_window(
    scene: &Scene,
    law: &LawSource,
    horizon: Horizon,
    pilot: (Configuration, Option<&StructuralModel>),
    started: Instant,
    count: &mut usize,
    progress: &mut dyn FnMut(&str),
) -> Result<f64, AutoError> {
    let cap = match horizon {
        Horizon::Until(end) if end <= DIRECT_LIMIT => return Ok(end),
        Horizon::Until(end) => end.min(WINDOW_LIMIT),
        Horizon::Open => WINDOW_LIMIT,
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

/// The reference of a structure too wide for the band (module doc, "A structure too
/// wide for the band"): the modal model with the static correction at `rungs[i]` modes
/// and step `STEPS[j]`, refined in both until the two tails are each at most half of
/// the tolerance over [`PARTNER_ACCURACY_RATIO`], or their ladders end; and its bound
/// e_ref = e_step + e_modes (m). The step tail is measured along the reference's mode
/// count, the mode tail along its step; each refinement only moves finer, and they
/// alternate until neither moves, so that both tails are measured at the reference.
fn converged_modal_reference(
    runs: &mut Runs,
    rungs: &[usize],
    tolerance: f64,
) -> Result<(Configuration, f64), AutoError> {
    let scene = runs.scene.clone();
    let budget = tolerance / (2.0 * PARTNER_ACCURACY_RATIO);
    let first = STEPS
        .iter()
        .position(|&dt| dt == REFERENCE_START)
        .expect("the ladder holds the reference's first step");
    let at = |modes: usize, dt: f64| Configuration {
        resolution: Resolution::StructureModal { modes },
        ..full_at(&scene, dt)
    };
    let Some(last_rung) = rungs.len().checked_sub(1) else {
        // No mode count below the structure's DOFs: nothing to refine.
        return Ok((at(1, STEPS[first]), f64::INFINITY));
    };
    let (mut j, mut i) = (first + 2, last_rung.min(2));
    let (mut e_step, mut e_modes);
    loop {
        // The step at rungs[i] modes, from STEPS[j] on.
        let mut jj = j;
        loop {
            let runs_at = [jj - 2, jj - 1, jj].map(|s| at(rungs[i], STEPS[s]));
            let d = tail_deviations(runs, runs_at)?;
            e_step = modal_tail_bound(d[0], d[1], budget);
            (runs.progress)(&format!(
                "fidelity = auto: {} modes at {:e} s deviate {:.3e} m from {:e} s (step tail {:.3e} m)",
                rungs[i], STEPS[jj], d[1], STEPS[jj - 1], e_step
            ));
            if e_step <= budget || jj + 1 == STEPS.len() {
                break;
            }
            jj += 1;
        }
        // The modes at STEPS[jj], from rungs[i] on.
        let mut ii = i;
        loop {
            if ii < 2 {
                e_modes = f64::INFINITY;
                break;
            }
            let runs_at = [ii - 2, ii - 1, ii].map(|r| at(rungs[r], STEPS[jj]));
            let d = tail_deviations(runs, runs_at)?;
            e_modes = modal_tail_bound(d[0], d[1], budget);
            (runs.progress)(&format!(
                "fidelity = auto: {} modes at {:e} s deviate {:.3e} m from {} modes (mode tail {:.3e} m)",
                rungs[ii], STEPS[jj], d[1], rungs[ii - 1], e_modes
            ));
            if e_modes <= budget || ii == last_rung {
                break;
            }
            ii += 1;
        }
        if (jj, ii) == (j, i) {
            break;
        }
        (j, i) = (jj, ii);
    }
    Ok((at(rungs[i], STEPS[j]), e_step + e_modes))
}

/// The largest tip deviations between the runs of `configurations` (modal, with the
/// static correction), the first and second and the second and third.
fn tail_deviations(
    runs: &mut Runs,
    configurations: [Configuration; 3],
) -> Result<[f64; 2], AutoError> {
    let mut made = Vec::with_capacity(3);
    for c in configurations {
        made.push(runs.run_corrected(c, true)?);
    }
    Ok([
        window_deviation(&made[0].tip, &made[1].tip),
        window_deviation(&made[1].tip, &made[2].tip),
    ])
}

/// The candidates (module doc, step 2): each mode count of `modes` and, `with_full`, the
/// full model at every step of [`STEPS`] down to `finest`.
fn ladder(scene: &Scene, modes: &[usize], finest: f64, with_full: bool) -> Vec<Configuration> {
    let mut candidates = Vec::new();
    for &dt in STEPS.iter().filter(|&&dt| dt >= finest) {
        for &k in modes {
            candidates.push(Configuration {
                resolution: Resolution::StructureModal { modes: k },
                ..full_at(scene, dt)
            });
        }
        if with_full {
            candidates.push(full_at(scene, dt));
        }
    }
    candidates
}

/// The choice (module doc, step 3): `candidates` run in order, each bounded by its
/// deviation from the `reference`'s run plus the reference's bound `e_ref` (m), until
/// one is within `tolerance`. Every candidate tried, and the index of the one chosen (the last
/// tried) if any.
fn pick(
    runs: &mut Runs,
    candidates: Vec<Configuration>,
    (reference, reference_run): (Configuration, &Measured),
    e_ref: f64,
    tolerance: f64,
) -> Result<(Vec<Candidate>, Option<usize>), AutoError> {
    let mut tried = Vec::new();
    for (index, configuration) in candidates.into_iter().enumerate() {
        let run = runs.run(configuration)?;
        let d = window_deviation(&run.tip, &reference_run.tip);
        let estimated_error = SAFETY_FACTOR * (d + e_ref);
        tried.push(Candidate {
            configuration,
            estimated_error,
            drift_rate: drift_rate(&run, reference_run),
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
    fn below_the_noise_floor_a_modal_tail_is_the_larger_deviation_whatever_the_contraction() {
        // Budget 1e-7 m: the floor is 1e-9 m.
        assert_eq!(modal_tail_bound(3.2e-11, 3.2e-11, 1e-7), 3.2e-11);
        assert_eq!(modal_tail_bound(1.8e-14, 3.2e-11, 1e-7), 3.2e-11);
        // Above it, the step refinement's bound: r = 4 gives d / 3, r = 1 none.
        assert_eq!(modal_tail_bound(4e-8, 1e-8, 1e-7), 1e-8 / 3.0);
        assert_eq!(modal_tail_bound(3.2e-11, 3.2e-11, 1e-9), f64::INFINITY);
    }

    #[test]
    fn a_modal_step_costs_less_than_a_full_one_and_halving_the_step_doubles_the_cost() {
        let modal = Resolution::StructureModal { modes: 10 };
        let a = cost(modal, 1e-4, 1.2, 1002, 15);
        assert_eq!(cost(modal, 5e-5, 1.2, 1002, 15), 2.0 * a);
        assert!(cost(Resolution::Structure, 1e-4, 1.2, 1002, 15) > 10.0 * a);
    }
}
