//! The trained model and its self-describing JSON weights file.
//!
//! One file holds everything needed to evaluate the law and to know what it is: format
//! name and version, variant, activation, layer sizes, features (name, unit, role,
//! standardisation statistics, training range), target (name, unit, statistics, range),
//! the weights, the training settings and the resulting metrics. Loading checks format,
//! version, shapes and that every number is finite, and returns a `NeuralError` (never
//! panics) for anything else.
//!
//! Training time is deliberately not stored (it is in the training report), so that
//! training twice with the same settings writes byte-identical files.

use std::path::Path;

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use super::error::NeuralError;
use super::file_checks::{check_header, finite, json_error, read_text, to_pretty_json, write_text};
use super::network::{Activation, Network, Workspace};
pub use super::synthetic::{SyntheticPreset, SyntheticSpec};
use crate::elementary::signum_or_zero;

/// What a feature means to the beam. The beam's `FrictionLaw` interface passes the
/// sliding velocity and the normal force; other features need fixed values there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FeatureRole {
    /// Signed relative sliding velocity v (m/s); its sign gives the force direction.
    SlidingVelocity,
    /// Normal force F_n (N).
    NormalForce,
    /// Any other measured quantity (temperature, humidity...).
    Other,
}

/// Why the trainer's L-BFGS (`stickslip_train::lbfgs::minimize`) stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    MaxIterations,
    MaxEvaluations,
    GradientTolerance,
    LossTolerance,
    /// No step along the search direction decreased the objective (usually: converged to
    /// rounding level).
    LineSearchFailed,
}

/// Value of the file's `format` field.
pub const FORMAT_NAME: &str = "stickslip-neural-friction";
/// Value of the file's `version` field that this build reads and writes.
pub const FORMAT_VERSION: u32 = 1;

crate::choice! {
    /// How the network output becomes a friction force.
    #[choice(name = "Variant", description = "How the network output becomes a friction force")]
    #[derive(Default)]
    pub enum Variant {
        /// The paper's model: the network maps (v, F_n, ...) to the signed force directly,
        /// so it must smooth the jump of the force at v = 0.
        #[default]
        Plain = "plain": "the paper's model: the network gives the signed force",
        /// Structured model (beyond the paper): the network maps (|v|, F_n, ...) to the
        /// magnitude g >= 0 and F = sign(v) g, so the jump at v = 0 is exact and the law is
        /// odd in v by construction. Needs a feature with the `sliding_velocity` role, and
        /// the target must be the signed force (positive for v > 0, as the paper's data):
        /// the network is fitted to sign(v) * target.
        Signed = "signed": "the network gives the magnitude, sign(v) the direction (exact jump at v = 0)",
    }
}

/// One input of the network, with the numbers needed to standardise it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FeatureSpec {
    pub name: String,
    /// Empty when the data did not give one.
    pub unit: String,
    pub role: FeatureRole,
    /// Mean of the network input over the training set. For the signed variant's
    /// sliding velocity the network input is |v|, so this is the mean of |v|.
    pub input_mean: f64,
    /// Population standard deviation of the network input over the training set (1 for a
    /// constant feature).
    pub input_std: f64,
    /// Smallest raw value in the training set (signed for the sliding velocity).
    pub min: f64,
    /// Largest raw value in the training set.
    pub max: f64,
}

/// The network output, with the numbers that undo its standardisation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TargetSpec {
    pub name: String,
    pub unit: String,
    /// Mean of the fitted quantity over the training set: the force (plain) or
    /// sign(v) * force (signed).
    pub output_mean: f64,
    /// Its population standard deviation.
    pub output_std: f64,
    /// Smallest raw target in the training set.
    pub min: f64,
    /// Largest raw target in the training set.
    pub max: f64,
}

/// Weights and biases of one layer; `weights[o][i]` connects input i to output o.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LayerWeights {
    pub weights: Vec<Vec<f64>>,
    pub biases: Vec<f64>,
}

/// How the model was trained.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrainingInfo {
    /// "synthetic (paper, Sec. 3.1)" or the CSV file name.
    pub data: String,
    /// The generator settings when the data were synthetic.
    pub synthetic: Option<SyntheticSpec>,
    /// Seed of data generation, split and initial weights.
    pub seed: u64,
    pub test_fraction: f64,
    pub train_samples: usize,
    pub test_samples: usize,
    /// lambda of the loss (see `stickslip_train::train::TrainConfig::lambda`).
    pub lambda: f64,
    /// Words for the minimised objective.
    pub loss: String,
    pub max_iterations: usize,
    /// L-BFGS iterations done.
    pub iterations: usize,
    /// Objective evaluations done.
    pub evaluations: usize,
    pub stop_reason: StopReason,
}

/// Accuracy of the model; MSE in target units squared (N^2 for forces), on the raw
/// target, of the force the law returns (sign and clamping included).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Metrics {
    pub mse_train: f64,
    pub mse_test: f64,
    pub r2_train: f64,
    pub r2_test: f64,
}

/// A trained neural friction model, as stored in the weights file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NeuralModel {
    pub format: String,
    pub version: u32,
    pub variant: Variant,
    pub activation: Activation,
    /// [inputs, hidden..., 1].
    pub layer_sizes: Vec<usize>,
    pub features: Vec<FeatureSpec>,
    pub target: TargetSpec,
    pub layers: Vec<LayerWeights>,
    pub training: TrainingInfo,
    pub metrics: Metrics,
}

/// A network input range that clamping maps into: [lo, hi] of the network input.
pub(crate) fn network_input_range(feature: &FeatureSpec, variant: Variant) -> (f64, f64) {
    if variant == Variant::Signed && feature.role == FeatureRole::SlidingVelocity {
        // Range of |v| implied by the signed range [min, max].
        let (a, b) = (feature.min.abs(), feature.max.abs());
        if feature.min <= 0.0 && feature.max >= 0.0 {
            (0.0, a.max(b))
        } else {
            (a.min(b), a.max(b))
        }
    } else {
        (feature.min, feature.max)
    }
}

impl NeuralModel {
    /// Feature names in input order.
    pub fn feature_names(&self) -> Vec<&str> {
        self.features.iter().map(|f| f.name.as_str()).collect()
    }

    /// Index of the feature with `role`.
    pub fn feature_with_role(&self, role: FeatureRole) -> Option<usize> {
        self.features.iter().position(|f| f.role == role)
    }

    /// Pretty JSON with a final newline; numbers in shortest round-trip form, so the
    /// same model always gives the same bytes.
    pub fn to_json(&self) -> Result<String, NeuralError> {
        to_pretty_json(self)
    }

    pub fn save(&self, path: &Path) -> Result<(), NeuralError> {
        self.validate(&path.display().to_string())?;
        write_text(path, &self.to_json()?)
    }

    pub fn load(path: &Path) -> Result<NeuralModel, NeuralError> {
        Self::from_json(&read_text(path)?, &path.display().to_string())
    }

    /// Parses and checks a weights file's text; `source_name` appears in errors.
    pub fn from_json(text: &str, source_name: &str) -> Result<NeuralModel, NeuralError> {
        check_header(text, source_name, FORMAT_NAME, FORMAT_VERSION)?;
        let json_error = |e| json_error(source_name, e);
        // Parse the text again (not the Value) so errors carry line and column.
        let model: NeuralModel = serde_json::from_str(text).map_err(json_error)?;
        model.validate(source_name)?;
        Ok(model)
    }

    /// Checks shapes, roles and finiteness: the format, the layers, the features, the
    /// target, then what the file records of its training, each in turn.
    pub fn validate(&self, source_name: &str) -> Result<(), NeuralError> {
        self.check_format(source_name)?;
        self.check_layers(source_name)?;
        self.check_features(source_name)?;
        self.check_target(source_name)?;
        self.check_record(source_name)
    }

    /// The file's format name and version are the ones this reader knows.
    fn check_format(&self, source_name: &str) -> Result<(), NeuralError> {
        if self.format != FORMAT_NAME || self.version != FORMAT_VERSION {
            return Err(shape_error(
                source_name,
                format!(
                    "format '{}' version {} (expected '{FORMAT_NAME}' version {FORMAT_VERSION})",
                    self.format, self.version
                ),
            ));
        }
        Ok(())
    }

    /// `layer_sizes` fits the features and the layers, and every weight and bias is
    /// there and finite.
    fn check_layers(&self, source_name: &str) -> Result<(), NeuralError> {
        let shape = |message: String| shape_error(source_name, message);
        let finite = |field: String, value: f64| finite(source_name, field, value);
        let sizes = &self.layer_sizes;
        if sizes.len() < 2 || sizes.contains(&0) || sizes.last() != Some(&1) {
            return Err(shape(format!(
                "layer_sizes {sizes:?} must be positive, at least [inputs, 1], ending in 1"
            )));
        }
        if sizes[0] != self.features.len() {
            return Err(shape(format!(
                "layer_sizes starts with {} inputs but {} features are listed",
                sizes[0],
                self.features.len()
            )));
        }
        if self.layers.len() != sizes.len() - 1 {
            return Err(shape(format!(
                "{} layers of weights for layer_sizes {sizes:?} (expected {})",
                self.layers.len(),
                sizes.len() - 1
            )));
        }
        for (l, layer) in self.layers.iter().enumerate() {
            let (inputs, outputs) = (sizes[l], sizes[l + 1]);
            if layer.weights.len() != outputs || layer.biases.len() != outputs {
                return Err(shape(format!(
                    "layer {}: {} weight rows and {} biases, expected {outputs} each",
                    l + 1,
                    layer.weights.len(),
                    layer.biases.len()
                )));
            }
            for (o, row) in layer.weights.iter().enumerate() {
                if row.len() != inputs {
                    return Err(shape(format!(
                        "layer {} row {}: {} weights, expected {inputs}",
                        l + 1,
                        o + 1,
                        row.len()
                    )));
                }
                for (i, w) in row.iter().enumerate() {
                    finite(format!("layers[{l}].weights[{o}][{i}]"), *w)?;
                }
            }
            for (o, b) in layer.biases.iter().enumerate() {
                finite(format!("layers[{l}].biases[{o}]"), *b)?;
            }
        }
        Ok(())
    }

    /// Each feature's scaling finite and usable, its name listed once, each role held
    /// by at most one feature, and the sliding velocity present for the signed variant.
    fn check_features(&self, source_name: &str) -> Result<(), NeuralError> {
        let shape = |message: String| shape_error(source_name, message);
        let finite = |field: String, value: f64| finite(source_name, field, value);
        for (k, f) in self.features.iter().enumerate() {
            for (what, v) in [
                ("input_mean", f.input_mean),
                ("input_std", f.input_std),
                ("min", f.min),
                ("max", f.max),
            ] {
                finite(format!("features[{k}] ('{}').{what}", f.name), v)?;
            }
            if f.input_std <= 0.0 || f.min > f.max {
                return Err(shape(format!(
                    "feature '{}': input_std must be positive and min <= max",
                    f.name
                )));
            }
            if self.features[..k].iter().any(|g| g.name == f.name) {
                return Err(shape(format!("feature '{}' is listed twice", f.name)));
            }
        }
        for role in [FeatureRole::SlidingVelocity, FeatureRole::NormalForce] {
            if self.features.iter().filter(|f| f.role == role).count() > 1 {
                return Err(shape(format!(
                    "more than one feature has the role {role:?}"
                )));
            }
        }
        if self.variant == Variant::Signed
            && self
                .feature_with_role(FeatureRole::SlidingVelocity)
                .is_none()
        {
            return Err(shape(
                "the signed variant needs a feature with the role sliding_velocity".into(),
            ));
        }
        Ok(())
    }

    /// The target's scaling finite and usable.
    fn check_target(&self, source_name: &str) -> Result<(), NeuralError> {
        let t = &self.target;
        for (what, v) in [
            ("output_mean", t.output_mean),
            ("output_std", t.output_std),
            ("min", t.min),
            ("max", t.max),
        ] {
            finite(source_name, format!("target.{what}"), v)?;
        }
        if t.output_std <= 0.0 || t.min > t.max {
            return Err(shape_error(
                source_name,
                "target: output_std must be positive and min <= max".into(),
            ));
        }
        Ok(())
    }

    /// What the file records of its training: the regularisation weight, the synthetic
    /// data's settings when given, the error metrics.
    fn check_record(&self, source_name: &str) -> Result<(), NeuralError> {
        finite(source_name, "training.lambda".into(), self.training.lambda)?;
        if let Some(spec) = &self.training.synthetic {
            spec.check()
                .map_err(|message| shape_error(source_name, format!("training.{message}")))?;
        }
        let m = &self.metrics;
        for (what, v) in [
            ("mse_train", m.mse_train),
            ("mse_test", m.mse_test),
            ("r2_train", m.r2_train),
            ("r2_test", m.r2_test),
        ] {
            finite(source_name, format!("metrics.{what}"), v)?;
        }
        Ok(())
    }

    /// The network shape.
    pub fn network(&self) -> Result<Network, NeuralError> {
        Network::new(&self.layer_sizes, self.activation)
    }

    /// Flat parameter vector in `Network`'s layout (per layer: W column-major, then b).
    pub fn parameters(&self) -> Vec<f64> {
        let mut params = Vec::new();
        for layer in &self.layers {
            let inputs = layer.weights.first().map_or(0, Vec::len);
            for i in 0..inputs {
                params.extend(layer.weights.iter().map(|row| row[i]));
            }
            params.extend_from_slice(&layer.biases);
        }
        params
    }

    /// Builds the stored layers from a flat parameter vector.
    pub fn layers_from_parameters(network: &Network, params: &[f64]) -> Vec<LayerWeights> {
        network
            .layers()
            .iter()
            .map(|shape| {
                let w = &params[shape.weight_range()];
                LayerWeights {
                    weights: (0..shape.outputs)
                        .map(|o| {
                            (0..shape.inputs)
                                .map(|i| w[o + i * shape.outputs])
                                .collect()
                        })
                        .collect(),
                    biases: params[shape.bias_range()].to_vec(),
                }
            })
            .collect()
    }

    /// Maps raw features (one column per sample) to standardised network inputs: clamp
    /// to the training range (|v| for the signed variant's velocity), then
    /// (x - mean) / std. Returns the inputs and the direction sign(v) of each sample
    /// (all 1 for the plain variant).
    pub fn network_inputs(&self, raw: &DMatrix<f64>) -> (Vec<f64>, Vec<f64>) {
        let samples = raw.ncols();
        let velocity = match self.variant {
            Variant::Signed => self.feature_with_role(FeatureRole::SlidingVelocity),
            Variant::Plain => None,
        };
        let mut inputs = Vec::with_capacity(samples * self.features.len());
        let mut signs = Vec::with_capacity(samples);
        for column in raw.column_iter() {
            for (k, f) in self.features.iter().enumerate() {
                let value = if Some(k) == velocity {
                    column[k].abs()
                } else {
                    column[k]
                };
                let (lo, hi) = network_input_range(f, self.variant);
                inputs.push((value.clamp(lo, hi) - f.input_mean) / f.input_std);
            }
            signs.push(velocity.map_or(1.0, |k| signum_or_zero(column[k])));
        }
        (inputs, signs)
    }

    /// Turns a standardised network output into the force: plain y = mean + std z;
    /// signed y = sign(v) max(0, mean + std z).
    #[inline]
    pub fn force_from_output(&self, z: f64, sign: f64) -> f64 {
        let y = self.target.output_mean + self.target.output_std * z;
        match self.variant {
            Variant::Plain => y,
            Variant::Signed => sign * y.max(0.0),
        }
    }

    /// Batch prediction: `features` has one row per feature (in model order) and one
    /// column per sample, in raw units; returns one force per sample. Same mapping as
    /// `NeuralLaw::evaluate` (clamping, sign), done with matrix products.
    pub fn predict_columns(&self, features: &DMatrix<f64>) -> Result<Vec<f64>, NeuralError> {
        if features.nrows() != self.features.len() {
            return Err(NeuralError::FeatureCount {
                expected: self.features.len(),
                got: features.nrows(),
                names: self.feature_names().join(", "),
            });
        }
        if let Some((index, value)) = features.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(NeuralError::NonFiniteInput {
                feature: self.features[index % self.features.len()].name.clone(),
                value: *value,
            });
        }
        let network = self.network()?;
        let params = self.parameters();
        let (inputs, signs) = self.network_inputs(features);
        let mut workspace = Workspace::default();
        let outputs = network.forward(&params, &inputs, features.ncols(), &mut workspace);
        Ok(outputs
            .iter()
            .zip(&signs)
            .map(|(&z, &s)| self.force_from_output(z, s))
            .collect())
    }
}

/// A fault in a weights file's shape, named after the file (`source_name`).
fn shape_error(source_name: &str, message: String) -> NeuralError {
    NeuralError::Shape {
        source_name: source_name.to_string(),
        message,
    }
}
