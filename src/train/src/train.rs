//! Training: standardisation, the regularised least-squares objective, full-batch
//! L-BFGS, metrics and history.
//!
//! # Loss and what lambda means
//!
//! Inputs are standardised with the training set's mean and population std. The target
//! is standardised too, but only as a reparametrisation: the network is
//! yhat = m_y + s_y * f(x), which is the same function as a network whose last layer
//! works in raw units with weights W_L,raw = s_y W_L. The loss is defined on that
//! raw-output network and the raw target y (N):
//!
//!   L(theta) = (1/n) sum_i (yhat_i - y_i)^2 + (lambda / 2) sum_l ||W_l,raw||^2,
//!
//! over the n training samples, all weight matrices penalised, biases not. In
//! standardised units the optimiser minimises L / s_y^2 (same minimiser, O(1) values):
//!
//!   J = (1/n) sum (z_i - t_i)^2 + (lambda / s_y^2) / 2 sum_{l<L} ||W_l||^2
//!       + (lambda / 2) ||W_L||^2.
//!
//! Relation to other tools (same standardised inputs, raw response, n samples):
//! - MATLAB `fitrnet(..., Lambda=lambda)`: its documentation (verified) says LBFGS
//!   minimises "the mean squared error (MSE)" and that Lambda is the strength of the
//!   ridge (L2) penalty term composed with the MSE. The exact scaling is NOT stated in
//!   what could be checked; this crate ASSUMES the literal reading MSE + lambda/2 ||w||^2,
//!   under which lambda here equals fitrnet's Lambda. If fitrnet uses MSE/2 +
//!   Lambda/2 ||w||^2 instead, fitrnet's Lambda equals lambda/2 here. (fitrnet does not
//!   standardise the response, which matches the raw-output definition above.)
//! - scikit-learn `MLPRegressor(alpha=...)` (verified in its source): it minimises
//!   (1/2) mean((y - yhat)^2) + alpha / (2 n) ||W||^2 = (1/2) [MSE + (alpha/n) ||W||^2],
//!   so alpha = n lambda / 2. The paper's lambda = 0.004 with n = 3500 gives alpha = 7,
//!   the value the project's scikit-learn peer uses (14 if fitrnet halves the MSE).
//!
//! Reported MSE values are always on the raw target in N^2 (or the target's unit
//! squared) and are those of the force the law returns (sign and clamping included).

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::data::{seeded_rng, Dataset, Split, Synthetic, INIT_STREAM};
use crate::error::TrainError;
use crate::lbfgs::{minimize, LbfgsOptions, LbfgsResult, StopReason};
use crate::objective::{initial_parameters, Objective};
use stickslip::neural::network::{Activation, Network, Workspace};
use stickslip::neural::weights::{
    FeatureSpec, Metrics, NeuralModel, TargetSpec, TrainingInfo, Variant, FORMAT_NAME,
    FORMAT_VERSION,
};
use stickslip::neural::{FeatureRole, SyntheticSpec};

/// Default seed of data generation, split and initial weights.
///
/// Why 2 (chosen on the former generator's data, `SyntheticPreset::Former`, that the
/// shipped networks are trained on): the plain variant's test MSE is dominated by the handful of test samples that
/// fall within ~1e-3 m/s of the jump at v = 0, so on 1500 test samples it is a lottery.
/// With the defaults (200 iterations) and seeds 1..7 and 2023 the test MSE ranged from
/// 0.17 to 8.6 N^2, while the same models' MSE on 200 000 fresh samples stayed within
/// 2.2 to 4.5 N^2 (R^2 0.9974 to 0.9987). Seed 2 was picked after such a sweep because
/// its test split is representative (test MSE 3.94 N^2, fresh samples 4.44 N^2; paper
/// 4.52 N^2), not the luckiest (seed 1: 0.17 N^2). Seed 2023, the first choice, puts
/// three test samples within 6e-5 m/s of v = 0 and gets 8.6 N^2 (scikit-learn on that
/// same split: 11.3 N^2).
pub const DEFAULT_SEED: u64 = 2;
/// The paper's regularisation strength.
pub const DEFAULT_LAMBDA: f64 = 0.004;
/// Default iteration limit (scikit-learn's max_iter default, used by the notes' peer).
pub const DEFAULT_ITERATIONS: usize = 200;

/// Settings of `train`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrainConfig {
    /// Hidden layer widths; the paper's [100, 100, 100].
    pub hidden_layers: Vec<usize>,
    pub activation: Activation,
    pub variant: Variant,
    /// lambda of the loss (see the module documentation); 0.004 as in the paper.
    pub lambda: f64,
    /// L-BFGS iteration limit.
    pub max_iterations: usize,
    /// Seed of the initial weights (Glorot uniform).
    pub seed: u64,
    /// L-BFGS memory m.
    pub history: usize,
    /// Blocks (threads) the batch is split into. Changes rounding, so it is part of what
    /// makes a training run reproducible; 2 by default.
    pub blocks: usize,
}

impl Default for TrainConfig {
    fn default() -> Self {
        TrainConfig {
            hidden_layers: vec![100, 100, 100],
            activation: Activation::Tanh,
            variant: Variant::Plain,
            lambda: DEFAULT_LAMBDA,
            max_iterations: DEFAULT_ITERATIONS,
            seed: DEFAULT_SEED,
            history: 10,
            blocks: 2,
        }
    }
}

/// One row of the training history (paper Fig. 3d).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HistoryRecord {
    pub iteration: usize,
    /// Objective J in standardised units (data term + penalty).
    pub objective: f64,
    /// Training MSE of the fitted quantity, target units squared.
    pub mse_train: f64,
    /// Test MSE of the law's force, target units squared (NaN without a test set).
    pub mse_test: f64,
    pub evaluations: usize,
}

/// What training measured.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TrainReport {
    pub mse_train: f64,
    pub mse_test: f64,
    pub r2_train: f64,
    pub r2_test: f64,
    pub iterations: usize,
    pub evaluations: usize,
    pub stop_reason: StopReason,
    /// Wall-clock time of the optimisation (s), without data generation and I/O.
    pub seconds: f64,
    pub variant: Variant,
    pub layer_sizes: Vec<usize>,
    pub lambda: f64,
    pub seed: u64,
    pub train_samples: usize,
    pub test_samples: usize,
    pub history: Vec<HistoryRecord>,
}

impl TrainReport {
    /// The history as CSV: iteration,objective,mse_train,mse_test,evaluations.
    pub fn history_csv(&self) -> String {
        let mut text = String::from("iteration,objective,mse_train,mse_test,evaluations\n");
        for h in &self.history {
            text.push_str(&format!(
                "{},{},{},{},{}\n",
                h.iteration, h.objective, h.mse_train, h.mse_test, h.evaluations
            ));
        }
        text
    }
}

/// Mean squared error and coefficient of determination R^2 = 1 - SS_res / SS_tot
/// (SS_tot about the mean of `truth`, as scikit-learn's r2_score).
pub fn mse_and_r2(predicted: &[f64], truth: &[f64]) -> (f64, f64) {
    let n = truth.len() as f64;
    let mean = truth.iter().sum::<f64>() / n;
    let ss_res: f64 = predicted
        .iter()
        .zip(truth)
        .map(|(p, t)| (p - t).powi(2))
        .sum();
    let ss_tot: f64 = truth.iter().map(|t| (t - mean).powi(2)).sum();
    (ss_res / n, 1.0 - ss_res / ss_tot)
}

fn mean_and_std(values: impl Iterator<Item = f64> + Clone) -> (f64, f64) {
    let n = values.clone().count() as f64;
    let mean = values.clone().sum::<f64>() / n;
    let variance = values.map(|v| (v - mean).powi(2)).sum::<f64>() / n;
    let std = variance.sqrt();
    // A constant column carries no information; std 1 keeps it harmless.
    let std = if std > 1e-12 * mean.abs().max(1.0) {
        std
    } else {
        1.0
    };
    (mean, std)
}

/// Where the training data came from, for the weights file.
#[derive(Clone, Debug, PartialEq)]
pub struct DataSource {
    pub description: String,
    pub synthetic: Option<SyntheticSpec>,
    pub seed: u64,
    pub test_fraction: f64,
}

fn check_config(config: &TrainConfig, data: &Dataset) -> Result<(), TrainError> {
    let bad = |m: String| Err(TrainError::InvalidInput(m));
    if !(config.lambda >= 0.0 && config.lambda.is_finite()) {
        return bad(format!(
            "lambda must be a finite number >= 0, got {}",
            config.lambda
        ));
    }
    if config.hidden_layers.contains(&0) {
        return bad("hidden layer widths must be positive".into());
    }
    if config.max_iterations == 0 {
        return bad("at least one iteration is needed".into());
    }
    if config.history == 0 {
        return bad("the L-BFGS memory must hold at least one pair".into());
    }
    if data.len() < 2 {
        return bad(format!("{} training sample(s) are too few", data.len()));
    }
    if config.variant == Variant::Signed
        && data
            .feature_with_role(FeatureRole::SlidingVelocity)
            .is_none()
    {
        return bad(
            "the signed variant needs a sliding-velocity feature (its sign gives the direction)"
                .into(),
        );
    }
    Ok(())
}

/// Trains a model on `split.train` and measures it on both sets. `on_iteration` sees every
/// history record as it is made (for progress output).
pub fn train(
    split: &Split,
    config: &TrainConfig,
    source: &DataSource,
    on_iteration: impl FnMut(&HistoryRecord),
) -> Result<(NeuralModel, TrainReport), TrainError> {
    let data = &split.train;
    check_config(config, data)?;
    let layer_sizes: Vec<usize> = std::iter::once(data.features.len())
        .chain(config.hidden_layers.iter().copied())
        .chain([1])
        .collect();
    let network = Network::new(&layer_sizes, config.activation)?;

    // The signed variant's velocity feature, fitted through |v|.
    let signed_velocity = match config.variant {
        Variant::Signed => data.feature_with_role(FeatureRole::SlidingVelocity),
        Variant::Plain => None,
    };
    let fitted = fitted_targets(data, signed_velocity);
    let (output_mean, output_std) = mean_and_std(fitted.iter().copied());
    let target = target_spec(data, output_mean, output_std);
    let features = feature_specs(data, signed_velocity);
    let mut model = untrained_model(config, &layer_sizes, features, target, source, split);

    // Standardised training inputs use the same mapping as inference (clamping is a
    // no-op inside the training range).
    let (train_inputs, _) = model.network_inputs(&data.inputs);
    let train_targets: Vec<f64> = fitted
        .iter()
        .map(|y| (y - output_mean) / output_std)
        .collect();
    let (test_inputs, test_signs) = model.network_inputs(&split.test.inputs);
    let penalties = penalties(config.lambda, output_std, network.layers().len());
    let mut objective = Objective::new(
        &network,
        &train_inputs,
        &train_targets,
        &penalties,
        config.blocks,
    )?;

    let started = Instant::now();
    let (params, result, history) = optimise(
        &network,
        &mut objective,
        &model,
        config,
        (&test_inputs, &test_signs),
        &split.test,
        on_iteration,
    )?;
    let seconds = started.elapsed().as_secs_f64();

    model.layers = NeuralModel::layers_from_parameters(&network, &params);
    model.training.iterations = result.iterations;
    model.training.evaluations = result.evaluations;
    model.training.stop_reason = result.stop;
    model.metrics = metrics(&model, split)?;
    let report = TrainReport {
        history,
        seconds,
        ..report(config, split, layer_sizes, &model.metrics, &result)
    };
    Ok((model, report))
}

/// The training report of a run with `config` on `split`: its metrics, L-BFGS's
/// `result`, and no history and no time yet.
fn report(
    config: &TrainConfig,
    split: &Split,
    layer_sizes: Vec<usize>,
    metrics: &Metrics,
    result: &LbfgsResult,
) -> TrainReport {
    TrainReport {
        mse_train: metrics.mse_train,
        mse_test: metrics.mse_test,
        r2_train: metrics.r2_train,
        r2_test: metrics.r2_test,
        iterations: result.iterations,
        evaluations: result.evaluations,
        stop_reason: result.stop,
        seconds: 0.0,
        variant: config.variant,
        layer_sizes,
        lambda: config.lambda,
        seed: config.seed,
        train_samples: split.train.len(),
        test_samples: split.test.len(),
        history: Vec::new(),
    }
}

/// Minimises `objective` by L-BFGS from the seeded initial weights; returns the
/// parameters, L-BFGS's result and the history, each record (with the test MSE of
/// `test`, whose network inputs and signs are `test_prepared`) also handed to
/// `on_iteration`.
fn optimise(
    network: &Network,
    objective: &mut Objective,
    model: &NeuralModel,
    config: &TrainConfig,
    test_prepared: (&[f64], &[f64]),
    test: &Dataset,
    mut on_iteration: impl FnMut(&HistoryRecord),
) -> Result<(Vec<f64>, LbfgsResult, Vec<HistoryRecord>), TrainError> {
    let mut params = initial_parameters(network, &mut seeded_rng(config.seed, INIT_STREAM));
    let options = LbfgsOptions {
        history: config.history,
        max_iterations: config.max_iterations,
        ..LbfgsOptions::default()
    };
    let variance = model.target.output_std * model.target.output_std;
    let mut history: Vec<HistoryRecord> = Vec::new();
    let mut test_workspace = Workspace::default();
    // The objective's last evaluation is always at the accepted iterate (the line search
    // ends on it), so its data term is the training MSE the callback reports.
    let last_train_mse = std::cell::Cell::new(f64::NAN);
    let result = minimize(
        |x, g| {
            let value = objective.value_and_gradient(x, g);
            last_train_mse.set(objective.last_mean_squared_error);
            value
        },
        &mut params,
        &options,
        |info, x| {
            let mse_test = test_mse(model, network, x, test_prepared, test, &mut test_workspace);
            let record = HistoryRecord {
                iteration: info.iteration,
                objective: info.value,
                mse_train: variance * last_train_mse.get(),
                mse_test,
                evaluations: info.evaluations,
            };
            on_iteration(&record);
            history.push(record);
        },
    )?;
    Ok((params, result, history))
}

/// The fitted quantity per sample: the force, or for the signed variant (velocity
/// feature `signed_velocity`) the force projected on sign(v). The projection keeps
/// zero-mean noise zero-mean, where |F| would bias it near F = 0.
fn fitted_targets(data: &Dataset, signed_velocity: Option<usize>) -> Vec<f64> {
    let direction = |sample: usize| match signed_velocity {
        Some(k) if data.inputs[(k, sample)] < 0.0 => -1.0,
        _ => 1.0,
    };
    (0..data.len())
        .map(|i| direction(i) * data.targets[i])
        .collect()
}

/// The target's description: name, unit, the fitted quantity's mean and standard
/// deviation (N) and the training range.
fn target_spec(data: &Dataset, output_mean: f64, output_std: f64) -> TargetSpec {
    let (min, max) = data.target_range();
    TargetSpec {
        name: data.target.name.clone(),
        unit: data.target.unit.clone(),
        output_mean,
        output_std,
        min,
        max,
    }
}

/// The L2 penalty per layer of the standardised problem, L / s_y^2: hidden weights get
/// lambda / s_y^2, the output weights (standardised units, W_L = W_L,raw / s_y) lambda.
fn penalties(lambda: f64, output_std: f64, layers: usize) -> Vec<f64> {
    let mut penalties = vec![lambda / (output_std * output_std); layers];
    if let Some(last) = penalties.last_mut() {
        *last = lambda;
    }
    penalties
}

/// The test MSE (N^2) of the network with parameters `x` on `test`, whose network
/// inputs and signs are `prepared`; NaN on an empty test set.
fn test_mse(
    model: &NeuralModel,
    network: &Network,
    x: &[f64],
    prepared: (&[f64], &[f64]),
    test: &Dataset,
    workspace: &mut Workspace,
) -> f64 {
    if test.is_empty() {
        return f64::NAN;
    }
    let (inputs, signs) = prepared;
    let outputs = network.forward(x, inputs, test.len(), workspace);
    outputs
        .iter()
        .zip(signs)
        .zip(&test.targets)
        .map(|((&z, &s), y)| (model.force_from_output(z, s) - y).powi(2))
        .sum::<f64>()
        / test.len() as f64
}

/// The feature descriptions of `data`: names, units and roles, the network inputs'
/// mean and standard deviation (of |v| for the signed variant's velocity
/// `signed_velocity`) and the training range.
fn feature_specs(data: &Dataset, signed_velocity: Option<usize>) -> Vec<FeatureSpec> {
    (0..data.features.len())
        .map(|k| {
            let network_input = |i: usize| {
                let v = data.inputs[(k, i)];
                if Some(k) == signed_velocity {
                    v.abs()
                } else {
                    v
                }
            };
            let (input_mean, input_std) = mean_and_std((0..data.len()).map(network_input));
            let (min, max) = data.feature_range(k);
            FeatureSpec {
                name: data.features[k].name.clone(),
                unit: data.features[k].unit.clone(),
                role: data.roles[k],
                input_mean,
                input_std,
                min,
                max,
            }
        })
        .collect()
}

/// The model file before training: its shape, scaling and training record, no layers
/// yet, the counts and metrics zero until the training fills them in.
fn untrained_model(
    config: &TrainConfig,
    layer_sizes: &[usize],
    features: Vec<FeatureSpec>,
    target: TargetSpec,
    source: &DataSource,
    split: &Split,
) -> NeuralModel {
    NeuralModel {
        format: FORMAT_NAME.to_string(),
        version: FORMAT_VERSION,
        variant: config.variant,
        activation: config.activation,
        layer_sizes: layer_sizes.to_vec(),
        features,
        target,
        layers: Vec::new(),
        training: TrainingInfo {
            data: source.description.clone(),
            synthetic: source.synthetic.clone(),
            seed: source.seed,
            test_fraction: source.test_fraction,
            train_samples: split.train.len(),
            test_samples: split.test.len(),
            lambda: config.lambda,
            loss: "mean((yhat - y)^2) + lambda/2 * sum(W^2): raw target, standardised inputs, \
                   weights of the raw-output network, biases not penalised"
                .to_string(),
            max_iterations: config.max_iterations,
            iterations: 0,
            evaluations: 0,
            stop_reason: StopReason::MaxIterations,
        },
        metrics: Metrics {
            mse_train: 0.0,
            mse_test: 0.0,
            r2_train: 0.0,
            r2_test: 0.0,
        },
    }
}

/// The trained model's MSE and R^2 on both sets (NaN on an empty test set).
fn metrics(model: &NeuralModel, split: &Split) -> Result<Metrics, TrainError> {
    let (mse_train, r2_train) = mse_and_r2(
        &model.predict_columns(&split.train.inputs)?,
        &split.train.targets,
    );
    let (mse_test, r2_test) = if split.test.is_empty() {
        (f64::NAN, f64::NAN)
    } else {
        mse_and_r2(
            &model.predict_columns(&split.test.inputs)?,
            &split.test.targets,
        )
    };
    Ok(Metrics {
        mse_train,
        mse_test,
        r2_train,
        r2_test,
    })
}

/// Trains on the paper's synthetic data: generate with `seed`, split, train with
/// `config` (whose seed also seeds the weights).
pub fn train_synthetic(
    spec: &SyntheticSpec,
    config: &TrainConfig,
    on_iteration: impl FnMut(&HistoryRecord),
) -> Result<(NeuralModel, TrainReport, Split), TrainError> {
    let split = spec.generate_split(config.seed)?;
    let source = DataSource {
        description: "synthetic (Vater et al. 2023, Sec. 3.1)".to_string(),
        synthetic: Some(spec.clone()),
        seed: config.seed,
        test_fraction: spec.test_fraction,
    };
    let (model, report) = train(&split, config, &source, on_iteration)?;
    Ok((model, report, split))
}

/// Evaluates a model on a data set: (MSE, R^2) of the law's force.
pub fn evaluate_model(model: &NeuralModel, data: &Dataset) -> Result<(f64, f64), TrainError> {
    let predictions = model.predict_columns(&data.inputs)?;
    Ok(mse_and_r2(&predictions, &data.targets))
}
