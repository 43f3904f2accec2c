//! Fitting a learned state law to force records by simulating them (single shooting
//! over each record) with exact gradients by forward sensitivities, minimised by the
//! crate's L-BFGS.
//!
//! Loss, over the n training samples of all training records (N^2):
//!
//! ```text
//! L = (1/n) sum_k (F_law(t_k) - F_k)^2 + (lambda / 2) ||correction weights||^2
//! ```
//!
//! Gradient: the state psi depends on the parameters only through D_c (the aging or
//! slip step; its start, the steady state ln(V_0 / |v_0|), on none), so one scalar
//! sensitivity s = d psi / d ln D_c is carried along each record,
//! s_k = (d psi_k / d psi_{k-1}) s_{k-1} + d psi_k / d ln D_c, and
//! dF_k/dp = dF/dp|_psi + dF/dpsi s_k [p = ln D_c].
//! Exact for the discrete simulation (tested against differences).
//!
//! Why single shooting: either law's state forgets its past over a slip of a few D_c,
//! so records hours long do not make the gradient explode the way a chaotic system's
//! would; what makes the fit non-convex is D_c itself (a guess decades off sees a flat
//! loss), so the fit starts from a grid of D_c (`DC_GRID`) with the structured part
//! only, keeps the best, then trains everything.

use rand::Rng;
use serde::{Deserialize, Serialize};

use super::learned_evolution::LearnedEvolution;
use super::loss::{loss_and_gradient, steady_starts};
use super::series::{rms_error, simulate_from, ForceSeries};
use crate::data::{seeded_rng, INIT_STREAM};
use crate::error::TrainError;
use crate::lbfgs::{minimize, LbfgsOptions, LbfgsResult};
use stickslip::friction::learned_state::{
    Correction, InputScale, LearnedStateLaw, StateEvolution, StateLawFile, StateLawParameters,
    StateMetrics, StateTrainingInfo, TrainingRanges,
};

/// Settings of [`super::evolution::train_state_law`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StateTrainConfig {
    /// Hidden units of the correction network (0: none, the structured law alone).
    pub hidden: usize,
    /// lambda of the loss (N^2 per squared weight).
    pub lambda: f64,
    /// L-BFGS iterations of the final fit.
    pub max_iterations: usize,
    /// L-BFGS iterations from each point of the D_c grid.
    pub grid_iterations: usize,
    /// Seed of the correction's initial weights.
    pub seed: u64,
    /// Every `test_every`-th record (1-based) is held out for testing; 0: none.
    pub test_every: usize,
    /// The learned law's state evolution, or both (`evolution::train_state_law`).
    #[serde(default)]
    pub evolution: LearnedEvolution,
    /// Train each record's initial state psi_0 too (records that start from rest or
    /// mid-transient); otherwise each starts from steady sliding at its first velocity.
    /// Held-out records get theirs fitted with the law fixed.
    #[serde(default)]
    pub train_initial_state: bool,
}

impl Default for StateTrainConfig {
    fn default() -> Self {
        StateTrainConfig {
            hidden: 4,
            lambda: 1e-3,
            max_iterations: 300,
            grid_iterations: 40,
            seed: 2,
            test_every: 5,
            evolution: LearnedEvolution::default(),
            train_initial_state: false,
        }
    }
}

/// D_c start points (m): from 1 um to 1 cm, two per decade (slips a tribometer sees).
const DC_GRID: [f64; 9] = [1e-6, 3e-6, 1e-5, 3e-5, 1e-4, 3e-4, 1e-3, 3e-3, 1e-2];

/// What training did.
#[derive(Clone, Debug, PartialEq)]
pub struct StateTrainReport {
    /// Loss at the best grid point and its D_c (m).
    pub grid_best: (f64, f64),
    pub final_loss: f64,
    pub iterations: usize,
    pub evaluations: usize,
    /// Every evolution trained, with its law's RMS errors (N), in training order; the
    /// file holds the one with the lower held-out error.
    pub candidates: Vec<(StateEvolution, StateMetrics)>,
}

fn range(values: impl Iterator<Item = f64>) -> [f64; 2] {
    values.fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], v| {
        [lo.min(v), hi.max(v)]
    })
}

pub(super) fn scale(name: &str, unit: &str, [lo, hi]: [f64; 2]) -> InputScale {
    let half = 0.5 * (hi - lo);
    InputScale {
        name: name.into(),
        unit: unit.into(),
        mean: 0.5 * (lo + hi),
        std: if half > 1e-12 * lo.abs().max(1.0) {
            half
        } else {
            1.0
        },
        min: lo,
        max: hi,
    }
}

/// Trains a learned state law with the evolution `evolution` on `records` (checked
/// first). `data` and `noise_std` describe the data for the file; `on_iteration` sees
/// (iteration, loss) of the final fit.
pub(super) fn fit_state_law(
    records: &[ForceSeries],
    config: &StateTrainConfig,
    evolution: StateEvolution,
    data: &str,
    noise_std: f64,
    on_iteration: &mut impl FnMut(usize, f64),
) -> Result<(StateLawFile, StateTrainReport), TrainError> {
    check_inputs(records, config)?;
    let (train, test) = split_held_out(records, config.test_every)?;
    let summary = DataSummary::of(&train);

    let (grid_loss, mut law) = fit_structured_on_grid(&train, config, evolution, &summary)?;
    let grid_best = (grid_loss, law.parameters.characteristic_slip);
    if config.hidden > 0 {
        law.correction = Some(initial_correction(
            &law,
            &train,
            config,
            summary.normal_forces,
        ));
    }
    let (x, law_len, result) = fit_everything(&mut law, &train, config, on_iteration)?;

    let train_starts = if config.train_initial_state {
        x[law_len..].to_vec()
    } else {
        steady_starts(&law, &train)
    };
    let test_starts = if config.train_initial_state {
        fit_starts(&law, &test, config.grid_iterations)
    } else {
        steady_starts(&law, &test)
    };
    let metrics = StateMetrics {
        rms_error_train: rms_error(&law, &train, &train_starts),
        rms_error_test: if test.is_empty() {
            0.0
        } else {
            rms_error(&law, &test, &test_starts)
        },
    };
    let training = training_info(&train, &test, config, data, noise_std, result);
    let ranges = TrainingRanges {
        sliding_velocity: summary.velocities,
        normal_force: summary.normal_forces,
    };
    let file = StateLawFile::new(&law, ranges, training, metrics);
    file.validate("(trained)")?;
    Ok((
        file,
        StateTrainReport {
            grid_best,
            final_loss: result.value,
            iterations: result.iterations,
            evaluations: result.evaluations,
            candidates: vec![(evolution, metrics)],
        },
    ))
}

/// Refuses settings no fit can use and records that do not hold together (with a
/// trained initial state the records need only their samples, not a steady start).
fn check_inputs(records: &[ForceSeries], config: &StateTrainConfig) -> Result<(), TrainError> {
    if !(config.lambda >= 0.0 && config.lambda.is_finite()) {
        return Err(TrainError::InvalidInput(format!(
            "lambda must be >= 0, got {}",
            config.lambda
        )));
    }
    if config.max_iterations == 0 {
        return Err(TrainError::InvalidInput(
            "at least one iteration is needed".into(),
        ));
    }
    for record in records {
        if config.train_initial_state {
            record.check_samples()?;
        } else {
            record.check()?;
        }
    }
    Ok(())
}

/// The training and held-out records: every `test_every`-th record (1-based) is held
/// out; 0 holds out none.
fn split_held_out(
    records: &[ForceSeries],
    test_every: usize,
) -> Result<(Vec<&ForceSeries>, Vec<&ForceSeries>), TrainError> {
    let held_out = |i: usize| test_every > 0 && (i + 1).is_multiple_of(test_every);
    let train: Vec<&ForceSeries> = records
        .iter()
        .enumerate()
        .filter(|(i, _)| !held_out(*i))
        .map(|(_, r)| r)
        .collect();
    let test: Vec<&ForceSeries> = records
        .iter()
        .enumerate()
        .filter(|(i, _)| held_out(*i))
        .map(|(_, r)| r)
        .collect();
    if train.is_empty() {
        return Err(TrainError::InvalidInput(
            "no record is left for training".into(),
        ));
    }
    Ok((train, test))
}

/// What the training records span and where the structured fit starts.
struct DataSummary {
    /// Range of the sliding velocity (m/s), signed.
    velocities: [f64; 2],
    /// Range of the normal force (N).
    normal_forces: [f64; 2],
    /// V_0 (m/s): a power of ten inside the data's speeds.
    reference_velocity: f64,
    /// Mean of F sign(v) / N over the sliding samples: the start of mu_0.
    level: f64,
}

impl DataSummary {
    fn of(train: &[&ForceSeries]) -> DataSummary {
        let speeds = range(
            train
                .iter()
                .flat_map(|r| r.velocity.iter().map(|v| v.abs()))
                .filter(|v| *v > 0.0),
        );
        let velocities = range(train.iter().flat_map(|r| r.velocity.iter().copied()));
        let normal_forces = range(train.iter().flat_map(|r| r.normal_force.iter().copied()));
        // V_0 only shifts mu_0; a power of ten inside the data's speeds keeps mu_0 readable.
        let reference_velocity = stickslip::elementary::powf(
            10f64,
            (0.5 * stickslip::elementary::log10(speeds[0] * speeds[1])).round(),
        );
        let level = {
            let (mut sum, mut n) = (0.0, 0.0);
            for r in train {
                for k in 0..r.len() {
                    if r.velocity[k] != 0.0 {
                        sum += r.force[k] * r.velocity[k].signum() / r.normal_force[k];
                        n += 1.0;
                    }
                }
            }
            sum / n
        };
        DataSummary {
            velocities,
            normal_forces,
            reference_velocity,
            level,
        }
    }
}

fn lbfgs_options(iterations: usize) -> LbfgsOptions {
    LbfgsOptions {
        max_iterations: iterations,
        ..LbfgsOptions::default()
    }
}

/// The structured part (no correction) fitted from each D_c of [`DC_GRID`]; the best
/// start's loss and law.
fn fit_structured_on_grid(
    train: &[&ForceSeries],
    config: &StateTrainConfig,
    evolution: StateEvolution,
    summary: &DataSummary,
) -> Result<(f64, LearnedStateLaw), TrainError> {
    let mut best: Option<(f64, LearnedStateLaw)> = None;
    for d_c in DC_GRID {
        let mut law = LearnedStateLaw {
            parameters: StateLawParameters {
                reference_coefficient: summary.level,
                reference_velocity: summary.reference_velocity,
                direct_effect: 0.01,
                evolution_effect: 0.01,
                characteristic_slip: d_c,
                state_evolution: evolution,
            },
            correction: None,
        };
        let (mut x, law_len) = with_starts(&law, train, config.train_initial_state);
        let mut fit_law = law.clone();
        let result = minimize(
            |x, g| loss_and_gradient(&mut fit_law, train, 0.0, law_len, x, g),
            &mut x,
            &lbfgs_options(config.grid_iterations),
            |_, _| {},
        );
        let Ok(result) = result else { continue };
        law.set_trainable(&x[..law_len]);
        if best.as_ref().is_none_or(|(loss, _)| result.value < *loss) {
            best = Some((result.value, law));
        }
    }
    best.ok_or_else(|| {
        TrainError::Training("the loss is not finite from any start of the D_c grid".into())
    })
}

/// The correction network to start the full fit from: inputs scaled to the ranges of
/// the state (simulated by `law` over the records) and of the normal force;
/// Glorot-uniform hidden weights; output weights 0, so training starts from the
/// structured fit exactly.
fn initial_correction(
    law: &LearnedStateLaw,
    train: &[&ForceSeries],
    config: &StateTrainConfig,
    normal_forces: [f64; 2],
) -> Correction {
    let mut states = Vec::new();
    let starts = steady_starts(law, train);
    for (r, start) in train.iter().zip(starts) {
        states.extend(simulate_from(law, r, start).1);
    }
    let mut rng = seeded_rng(config.seed, INIT_STREAM);
    let limit = (6.0f64 / 3.0).sqrt();
    Correction {
        inputs: [
            scale("state", "1", range(states.into_iter())),
            scale("normal_force", "N", normal_forces),
        ],
        hidden_weights: (0..config.hidden)
            .map(|_| [rng.gen_range(-limit..limit), rng.gen_range(-limit..limit)])
            .collect(),
        hidden_biases: vec![0.0; config.hidden],
        output_weights: vec![0.0; config.hidden],
    }
}

/// The final fit of everything trainable (the law, with `train_initial_state` each
/// record's start too) from `law`, which it leaves holding the result; the flat
/// parameters, the law's count among them, and what L-BFGS reported.
fn fit_everything(
    law: &mut LearnedStateLaw,
    train: &[&ForceSeries],
    config: &StateTrainConfig,
    on_iteration: &mut impl FnMut(usize, f64),
) -> Result<(Vec<f64>, usize, LbfgsResult), TrainError> {
    let (mut x, law_len) = with_starts(law, train, config.train_initial_state);
    let mut fit_law = law.clone();
    let result = minimize(
        |x, g| loss_and_gradient(&mut fit_law, train, config.lambda, law_len, x, g),
        &mut x,
        &lbfgs_options(config.max_iterations),
        |info, _| on_iteration(info.iteration, info.value),
    )?;
    law.set_trainable(&x[..law_len]);
    Ok((x, law_len, result))
}

/// How the file's law was trained.
fn training_info(
    train: &[&ForceSeries],
    test: &[&ForceSeries],
    config: &StateTrainConfig,
    data: &str,
    noise_std: f64,
    result: LbfgsResult,
) -> StateTrainingInfo {
    StateTrainingInfo {
        data: data.to_string(),
        train_series: train.len(),
        test_series: test.len(),
        samples: train.iter().map(|r| r.len()).sum(),
        noise_std,
        seed: config.seed,
        lambda: config.lambda,
        loss: if config.train_initial_state {
            "mean squared force error of the simulated records (N^2) + lambda/2 ||correction weights||^2; single shooting from a trained initial state per record (held-out records: fitted with the law fixed)"
        } else {
            "mean squared force error of the simulated records (N^2) + lambda/2 ||correction weights||^2; single shooting from steady sliding at each record's first velocity"
        }
        .into(),
        iterations: result.iterations,
        evaluations: result.evaluations,
        stop_reason: result.stop,
    }
}

/// The flat parameters to start from: the law's, then (`trained`) each record's start,
/// first guessed at steady sliding; and the law's count.
fn with_starts(
    law: &LearnedStateLaw,
    records: &[&ForceSeries],
    trained: bool,
) -> (Vec<f64>, usize) {
    let mut x = law.trainable();
    let law_len = x.len();
    if trained {
        x.extend(steady_starts(law, records));
    }
    (x, law_len)
}

/// Each record's start fitted with `law` fixed (`iterations` of L-BFGS in one
/// variable): how held-out records that do not start from steady sliding are compared.
fn fit_starts(law: &LearnedStateLaw, records: &[&ForceSeries], iterations: usize) -> Vec<f64> {
    let guesses = steady_starts(law, records);
    let law_x = law.trainable();
    let law_len = law_x.len();
    let mut fit_law = law.clone();
    records
        .iter()
        .zip(guesses)
        .map(|(record, guess)| {
            let mut start = [guess];
            let mut full = vec![0.0; law_len + 1];
            let objective = |y: &[f64], g: &mut [f64]| {
                let x = [law_x.as_slice(), y].concat();
                let value =
                    loss_and_gradient(&mut fit_law, &[*record], 0.0, law_len, &x, &mut full);
                g[0] = full[law_len];
                value
            };
            let options = LbfgsOptions {
                max_iterations: iterations,
                ..LbfgsOptions::default()
            };
            // A failed search leaves the guess, which is then what the error measures.
            let _ = minimize(objective, &mut start, &options, |_, _| {});
            start[0]
        })
        .collect()
}
