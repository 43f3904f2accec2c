//! What ONNX does not say about a network: feature names, units, roles and training
//! ranges, the target, the variant. Read from the file's `metadata_props` (keys below)
//! or given by the caller (`OnnxImport`), the caller winning key by key.

use serde::{Deserialize, Serialize};

use super::super::network::Activation;
use super::super::weights::{
    network_input_range, FeatureRole, FeatureSpec, LayerWeights, Metrics, NeuralModel, StopReason,
    TargetSpec, TrainingInfo, Variant, FORMAT_NAME, FORMAT_VERSION,
};
use super::error::OnnxImportError;
use stickslip_formats::onnx::{self as read, OnnxNetwork};

/// Metadata key: JSON array of [`FeatureInfo`], one per input column, in column order.
pub const FEATURES_KEY: &str = "stickslip.features";
/// Metadata key: JSON [`TargetInfo`].
pub const TARGET_KEY: &str = "stickslip.target";
/// Metadata key: "plain" or "signed" (see `Variant`); plain when absent.
pub const VARIANT_KEY: &str = "stickslip.variant";

/// One input column of the ONNX graph: what it is and the range it was trained on (the
/// law clamps inputs to it, see `law`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeatureInfo {
    pub name: String,
    #[serde(default)]
    pub unit: String,
    pub role: FeatureRole,
    /// Smallest raw value in training (signed for the sliding velocity).
    pub min: f64,
    /// Largest raw value in training.
    pub max: f64,
}

impl FeatureInfo {
    /// A feature with no unit and the role other (neither supplied by the beam), e.g.
    /// for a network whose inputs are not described.
    pub fn other(name: impl Into<String>, min: f64, max: f64) -> FeatureInfo {
        FeatureInfo {
            name: name.into(),
            unit: String::new(),
            role: FeatureRole::Other,
            min,
            max,
        }
    }
}

/// The network output.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TargetInfo {
    pub name: String,
    #[serde(default)]
    pub unit: String,
    /// Range of the target in training; informational (nothing evaluates it), 0 when
    /// unknown.
    #[serde(default)]
    pub min: f64,
    #[serde(default)]
    pub max: f64,
}

impl Default for TargetInfo {
    fn default() -> Self {
        TargetInfo {
            name: "friction_force".into(),
            unit: "N".into(),
            min: 0.0,
            max: 0.0,
        }
    }
}

/// The caller's description of an ONNX network; each field set here replaces the
/// file's metadata key of the same meaning. Plain data, so that command-line flags
/// (`--feature NAME:ROLE:UNIT:MIN:MAX`, `--target`, `--variant`) can fill it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OnnxImport {
    /// How the file is named in errors and in the model's training notes.
    pub source_name: String,
    /// One per input column, in column order (replaces `stickslip.features`).
    pub features: Option<Vec<FeatureInfo>>,
    /// Replaces `stickslip.target`; default: friction_force in N, range unknown.
    pub target: Option<TargetInfo>,
    /// Replaces `stickslip.variant`; default: plain.
    pub variant: Option<Variant>,
}

impl OnnxImport {
    /// Options naming the source, everything else from the file's metadata.
    pub fn named(source_name: impl Into<String>) -> OnnxImport {
        OnnxImport {
            source_name: source_name.into(),
            ..OnnxImport::default()
        }
    }
}

fn metadata<'m>(network: &'m OnnxNetwork, key: &str) -> Option<&'m str> {
    network
        .metadata
        .iter()
        .find(|(k, _)| k == key)
        .map(|(_, v)| v.as_str())
}

fn parse<T: serde::de::DeserializeOwned>(
    network: &OnnxNetwork,
    key: &str,
    source_name: &str,
) -> Result<Option<T>, OnnxImportError> {
    metadata(network, key)
        .map(|text| {
            serde_json::from_str(text).map_err(|e| OnnxImportError::Description {
                source_name: source_name.to_string(),
                message: format!("metadata '{key}' is not valid: {e}"),
            })
        })
        .transpose()
}

/// The network as our `NeuralModel`, described by `options` and the file's metadata.
///
/// Training notes and metrics are not in an ONNX file; they are filled with markers that
/// say so (`training.data` names the file and producer, `training.loss` says "unknown",
/// counts and metrics are 0, `stop_reason` max_iterations).
pub fn neural_model(
    network: &OnnxNetwork,
    options: &OnnxImport,
) -> Result<NeuralModel, OnnxImportError> {
    let source_name = options.source_name.as_str();
    let features = described_features(network, options)?;
    let target = match &options.target {
        Some(t) => t.clone(),
        None => parse::<TargetInfo>(network, TARGET_KEY, source_name)?.unwrap_or_default(),
    };
    let variant = described_variant(network, options)?;
    let model = assembled(network, source_name, &features, target, variant);
    model.validate(source_name)?;
    let bound = output_bound(&model);
    if overflows(bound) {
        return Err(OnnxImportError::Overflow {
            source_name: source_name.to_string(),
            bound,
        });
    }
    Ok(model)
}

fn description(source_name: &str, message: String) -> OnnxImportError {
    OnnxImportError::Description {
        source_name: source_name.to_string(),
        message,
    }
}

/// The input columns from `options`, else from the metadata; one per network input.
fn described_features(
    network: &OnnxNetwork,
    options: &OnnxImport,
) -> Result<Vec<FeatureInfo>, OnnxImportError> {
    let source_name = options.source_name.as_str();
    let features = match &options.features {
        Some(f) => f.clone(),
        None => {
            parse::<Vec<FeatureInfo>>(network, FEATURES_KEY, source_name)?.ok_or_else(|| {
                description(
                    source_name,
                    format!(
                        "the features (names, roles, training ranges) are not described: give \
                         them in the metadata key '{FEATURES_KEY}' (a JSON array with one \
                         {{\"name\", \"unit\", \"role\", \"min\", \"max\"}} per input column) or \
                         as import options (`stickslip import-network FILE.onnx --feature \
                         NAME:ROLE:UNIT:MIN:MAX ...`, once per column, writes a weights file)"
                    ),
                )
            })?
        }
    };
    let inputs = network.input_mean.len();
    if features.len() != inputs {
        return Err(description(
            source_name,
            format!(
                "{} features are described but the network has {inputs} inputs",
                features.len()
            ),
        ));
    }
    Ok(features)
}

/// The variant from `options`, else from the metadata, else plain.
fn described_variant(
    network: &OnnxNetwork,
    options: &OnnxImport,
) -> Result<Variant, OnnxImportError> {
    match options.variant {
        Some(v) => Ok(v),
        None => match metadata(network, VARIANT_KEY) {
            None => Ok(Variant::Plain),
            Some(text) => <Variant as crate::choice::Choice>::from_name(text).ok_or_else(|| {
                description(
                    &options.source_name,
                    format!("metadata '{VARIANT_KEY}' is '{text}', expected 'plain' or 'signed'"),
                )
            }),
        },
    }
}

/// The network and its description as a `NeuralModel` (not yet validated), with the
/// markers of an import for what ONNX does not hold.
fn assembled(
    network: &OnnxNetwork,
    source_name: &str,
    features: &[FeatureInfo],
    target: TargetInfo,
    variant: Variant,
) -> NeuralModel {
    NeuralModel {
        format: FORMAT_NAME.into(),
        version: FORMAT_VERSION,
        variant,
        activation: activation(network.activation),
        layer_sizes: network.layer_sizes(),
        features: features
            .iter()
            .zip(network.input_mean.iter().zip(&network.input_std))
            .map(|(f, (&input_mean, &input_std))| FeatureSpec {
                name: f.name.clone(),
                unit: f.unit.clone(),
                role: f.role,
                input_mean,
                input_std,
                min: f.min,
                max: f.max,
            })
            .collect(),
        target: TargetSpec {
            name: target.name,
            unit: target.unit,
            output_mean: network.output_mean,
            output_std: network.output_std,
            min: target.min,
            max: target.max,
        },
        layers: network
            .layers
            .iter()
            .map(|layer| LayerWeights {
                weights: layer.weights.clone(),
                biases: layer.biases.clone(),
            })
            .collect(),
        training: TrainingInfo {
            data: format!("imported from ONNX {source_name} ({})", network.producer),
            synthetic: None,
            seed: 0,
            test_fraction: 0.0,
            train_samples: 0,
            test_samples: 0,
            lambda: 0.0,
            loss: "unknown (imported from ONNX)".into(),
            max_iterations: 0,
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

/// The reader's activation as ours (the same functions, named alike).
fn activation(activation: read::Activation) -> Activation {
    match activation {
        read::Activation::Tanh => Activation::Tanh,
        read::Activation::Sigmoid => Activation::Sigmoid,
        read::Activation::Relu => Activation::Relu,
    }
}

/// Bounds at or above this (or NaN) count as overflow: far enough below f64::MAX
/// (1.8e308) for any summation order's rounding.
const LIMIT: f64 = 1e300;

fn overflows(bound: f64) -> bool {
    bound.is_nan() || bound >= LIMIT
}

/// An upper bound of |force| over the training box by interval arithmetic on absolute
/// values: |z_o| <= sum_i |w_oi| |a_i| + |b_o|, tanh and sigmoid bounded by 1, relu by
/// its input's bound. Rounding is monotonic, so where this bound is finite with margin
/// (below 1e300), every evaluation in the box is finite too, whatever the summation
/// order; a pre-activation bound of 1e300 or more counts as overflow.
fn output_bound(model: &NeuralModel) -> f64 {
    let mut bounds: Vec<f64> = model
        .features
        .iter()
        .map(|f| {
            let (lo, hi) = network_input_range(f, model.variant);
            (lo - f.input_mean).abs().max((hi - f.input_mean).abs()) / f.input_std
        })
        .collect();
    let last = model.layers.len() - 1;
    for (l, layer) in model.layers.iter().enumerate() {
        if bounds.iter().any(|&b| overflows(b)) {
            // An overflowing sum could be inf - inf = NaN before a bounded tanh.
            return f64::INFINITY;
        }
        let mut next = Vec::with_capacity(layer.biases.len());
        for (row, b) in layer.weights.iter().zip(&layer.biases) {
            let z = row
                .iter()
                .zip(&bounds)
                .map(|(w, a)| w.abs() * a)
                .sum::<f64>()
                + b.abs();
            next.push(match (l == last, model.activation) {
                (false, Activation::Tanh | Activation::Sigmoid) if !overflows(z) => z.min(1.0),
                _ => z,
            });
        }
        bounds = next;
    }
    model.target.output_mean.abs() + model.target.output_std * bounds[0]
}
