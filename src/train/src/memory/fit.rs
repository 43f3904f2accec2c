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

use super::evolution::LearnedEvolution;
use super::series::{rms_error, simulate, ForceSeries};
use crate::data::{seeded_rng, INIT_STREAM};
use crate::error::TrainError;
use crate::lbfgs::{minimize, LbfgsOptions};
use stickslip::neural::memory::correction::PER_UNIT;
use stickslip::neural::memory::law::{LOG_SLIP, STRUCTURED};
use stickslip::neural::memory::{
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

/// Loss and gradient of `law` with trainable parameters `x` over `records`.
fn loss_and_gradient(
    law: &mut LearnedStateLaw,
    records: &[&ForceSeries],
    lambda: f64,
    x: &[f64],
    gradient: &mut [f64],
) -> f64 {
    law.set_trainable(x);
    gradient.iter_mut().for_each(|g| *g = 0.0);
    let n: usize = records.iter().map(|r| r.len()).sum();
    let mut sample_gradient = vec![0.0; x.len()];
    let mut squared = 0.0;
    for record in records {
        let mut state = law.steady_state(record.velocity[0].abs());
        let mut sensitivity = 0.0;
        for k in 0..record.len() {
            if k > 0 {
                let dt = record.time[k] - record.time[k - 1];
                let step = law.step_state(state, record.velocity[k], dt);
                state = step.state;
                sensitivity = step.d_state * sensitivity + step.d_log_slip;
            }
            sample_gradient.iter_mut().for_each(|g| *g = 0.0);
            let f = law.force_with_gradient(
                state,
                record.velocity[k],
                record.normal_force[k],
                Some((&mut sample_gradient, 1.0)),
            );
            sample_gradient[LOG_SLIP] += f.d_state * sensitivity;
            let residual = f.force - record.force[k];
            squared += residual * residual;
            let weight = 2.0 * residual / n as f64;
            for (g, s) in gradient.iter_mut().zip(&sample_gradient) {
                *g += weight * s;
            }
        }
    }
    let mut penalty = 0.0;
    for (i, (g, p)) in gradient.iter_mut().zip(x).enumerate().skip(STRUCTURED) {
        // Weights, not biases: unit slots 0, 1 (hidden) and 3 (output).
        if (i - STRUCTURED) % PER_UNIT != 2 {
            penalty += p * p;
            *g += lambda * p;
        }
    }
    squared / n as f64 + 0.5 * lambda * penalty
}

fn range(values: impl Iterator<Item = f64>) -> [f64; 2] {
    values.fold([f64::INFINITY, f64::NEG_INFINITY], |[lo, hi], v| {
        [lo.min(v), hi.max(v)]
    })
}

fn scale(name: &str, unit: &str, [lo, hi]: [f64; 2]) -> InputScale {
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
        record.check()?;
    }
    let held_out = |i: usize| config.test_every > 0 && (i + 1).is_multiple_of(config.test_every);
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
        for r in &train {
            for k in 0..r.len() {
                if r.velocity[k] != 0.0 {
                    sum += r.force[k] * r.velocity[k].signum() / r.normal_force[k];
                    n += 1.0;
                }
            }
        }
        sum / n
    };
    let options = |iterations| LbfgsOptions {
        max_iterations: iterations,
        ..LbfgsOptions::default()
    };

    // Structured part from each D_c of the grid; keep the best.
    let mut best: Option<(f64, LearnedStateLaw)> = None;
    for d_c in DC_GRID {
        let mut law = LearnedStateLaw {
            parameters: StateLawParameters {
                reference_coefficient: level,
                reference_velocity,
                direct_effect: 0.01,
                evolution_effect: 0.01,
                characteristic_slip: d_c,
                state_evolution: evolution,
            },
            correction: None,
        };
        let mut x = law.trainable();
        let mut fit_law = law.clone();
        let result = minimize(
            |x, g| loss_and_gradient(&mut fit_law, &train, 0.0, x, g),
            &mut x,
            &options(config.grid_iterations),
            |_, _| {},
        );
        let Ok(result) = result else { continue };
        law.set_trainable(&x);
        if best.as_ref().is_none_or(|(loss, _)| result.value < *loss) {
            best = Some((result.value, law));
        }
    }
    let (grid_loss, mut law) = best.ok_or_else(|| {
        TrainError::Training("the loss is not finite from any start of the D_c grid".into())
    })?;
    let grid_best = (grid_loss, law.parameters.characteristic_slip);

    if config.hidden > 0 {
        let mut states = Vec::new();
        for r in &train {
            states.extend(simulate(&law, r).1);
        }
        let mut rng = seeded_rng(config.seed, INIT_STREAM);
        // Glorot-uniform hidden weights; output weights 0, so training starts from the
        // structured fit exactly.
        let limit = (6.0f64 / 3.0).sqrt();
        law.correction = Some(Correction {
            inputs: [
                scale("state", "1", range(states.into_iter())),
                scale("normal_force", "N", normal_forces),
            ],
            hidden_weights: (0..config.hidden)
                .map(|_| [rng.gen_range(-limit..limit), rng.gen_range(-limit..limit)])
                .collect(),
            hidden_biases: vec![0.0; config.hidden],
            output_weights: vec![0.0; config.hidden],
        });
    }
    let mut x = law.trainable();
    let mut fit_law = law.clone();
    let mut iteration_count = 0;
    let result = minimize(
        |x, g| loss_and_gradient(&mut fit_law, &train, config.lambda, x, g),
        &mut x,
        &options(config.max_iterations),
        |info, _| {
            iteration_count = info.iteration;
            on_iteration(info.iteration, info.value);
        },
    )?;
    law.set_trainable(&x);
    let metrics = StateMetrics {
        rms_error_train: rms_error(&law, &train),
        rms_error_test: if test.is_empty() {
            0.0
        } else {
            rms_error(&law, &test)
        },
    };
    let training = StateTrainingInfo {
        data: data.to_string(),
        train_series: train.len(),
        test_series: test.len(),
        samples: train.iter().map(|r| r.len()).sum(),
        noise_std,
        seed: config.seed,
        lambda: config.lambda,
        loss: "mean squared force error of the simulated records (N^2) + lambda/2 ||correction weights||^2; single shooting from steady sliding at each record's first velocity".into(),
        iterations: result.iterations,
        evaluations: result.evaluations,
        stop_reason: result.stop,
    };
    let ranges = TrainingRanges {
        sliding_velocity: velocities,
        normal_force: normal_forces,
    };
    let file = StateLawFile::new(&law, ranges, training, metrics);
    file.validate("(trained)")?;
    let _ = iteration_count;
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::memory::protocol::TribometerSpec;

    /// The forward-sensitivity gradient of the loss against central differences, with a
    /// correction, on short noisy records (relative 1e-5: differences of step 1e-6 in
    /// parameters of O(1) to O(10)), with either evolution law (the slip law's records
    /// and law: its step's D_c sensitivity is another formula).
    #[test]
    fn the_loss_gradient_is_exact_for_the_discrete_simulation() {
        for evolution in [StateEvolution::Aging, StateEvolution::Slip] {
            loss_gradient_matches_differences(evolution);
        }
    }

    fn loss_gradient_matches_differences(evolution: StateEvolution) {
        let mut spec = TribometerSpec {
            hold_slip: 3e-5,
            hold_time: 0.02,
            normal_forces: vec![80.0, 120.0],
            ..TribometerSpec::default()
        };
        spec.law.state_evolution = evolution;
        let records = spec.generate(1).unwrap();
        let refs: Vec<&ForceSeries> = records.iter().collect();
        let mut law = spec.as_learned();
        law.parameters.characteristic_slip = 1.3e-5;
        law.parameters.evolution_effect = 0.018;
        law.correction = Some(Correction {
            inputs: [
                scale("state", "1", [-5.0, 2.0]),
                scale("normal_force", "N", [80.0, 120.0]),
            ],
            hidden_weights: vec![[0.5, -0.3], [0.2, 0.8]],
            hidden_biases: vec![0.1, -0.2],
            output_weights: vec![0.01, -0.02],
        });
        let x = law.trainable();
        let mut g = vec![0.0; x.len()];
        loss_and_gradient(&mut law, &refs, 0.1, &x, &mut g);
        for i in 0..x.len() {
            let e = 1e-6;
            let mut xp = x.clone();
            xp[i] += e;
            let mut scratch = vec![0.0; x.len()];
            let plus = loss_and_gradient(&mut law, &refs, 0.1, &xp, &mut scratch);
            xp[i] -= 2.0 * e;
            let minus = loss_and_gradient(&mut law, &refs, 0.1, &xp, &mut scratch);
            let fd = (plus - minus) / (2.0 * e);
            assert!(
                (g[i] - fd).abs() < 1e-5 * fd.abs().max(1.0),
                "{evolution:?} p{i}: {} vs {fd}",
                g[i]
            );
        }
    }
}
