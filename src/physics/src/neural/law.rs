//! `NeuralLaw`: evaluating a trained model, one sample at a time without allocating (the
//! time-step loop) or in batches, and as the beam's `FrictionLaw`.
//!
//! # Inputs outside the training range
//! Every input is clamped to the range seen in training before standardisation: feature
//! k to [min_k, max_k]; for the signed variant the velocity's magnitude |v| is clamped
//! to the training range of |v| and the sign is kept. A network extrapolates tanh units
//! arbitrarily, while friction data say nothing beyond the measured range; clamping
//! holds the force at its value at the edge of the data (for the paper's set
//! |v| <= 0.4 m/s and 90 <= F_n <= 110 N, so at 10 m/s the law returns its 0.4 m/s
//! force; at 1000 N it returns the 110 N force, it does NOT scale with F_n). Use data
//! covering the operating range.
//!
//! # As the beam's friction law
//! `FrictionLaw::sliding_force(v, F_n)` needs a feature with role `sliding_velocity` and
//! one with role `normal_force`; every other feature must be given a fixed value with
//! `with_fixed_feature`. `NeuralLaw::into_friction_law` (which `LawSource::law` calls)
//! checks this and refuses the model otherwise. A `NeuralLaw` that has not passed that check
//! returns NaN from `sliding_force`.

use std::path::Path;

use nalgebra::DMatrix;

use super::error::NeuralError;
use super::forward::{Forward, Real};
use super::onnx;
use super::weights::FeatureRole;
use super::weights::{network_input_range, NeuralModel, Variant};
use crate::elementary::signum_or_zero;
use crate::files::WEIGHTS_FILE;
use crate::neural::inference::Inference;
use stickslip_formats::sniff::WeightsFileKind;

/// The shipped plain-variant weights (`weights/paper-plain.json`).
pub const PAPER_PLAIN_JSON: &str = include_str!("../../../../weights/paper-plain.json");
/// The shipped signed-variant weights (`weights/paper-signed.json`).
pub const PAPER_SIGNED_JSON: &str = include_str!("../../../../weights/paper-signed.json");

/// A trained neural friction model ready for evaluation.
#[derive(Clone, Debug)]
pub struct NeuralLaw {
    model: NeuralModel,
    /// The network in the time-step loop's layout, with its scratch buffers.
    forward: Forward<f64>,
    /// The same network in f32, which evaluations use instead when present
    /// (`Inference::F32`, see [`NeuralLaw::in_f32`]).
    forward_f32: Option<Forward<f32>>,
    /// The f32 network's largest deviation from the exact one over the training range
    /// (N), measured when it was built.
    pub(crate) f32_deviation: Option<f64>,
    /// Per feature: clamp range of the network input, mean and 1/std.
    input_lo: Vec<f64>,
    input_hi: Vec<f64>,
    input_mean: Vec<f64>,
    input_inverse_std: Vec<f64>,
    /// Feature whose sign gives the direction and whose magnitude is the input (signed).
    signed_velocity: Option<usize>,
    velocity: Option<usize>,
    normal_force: Option<usize>,
    /// Values for features the beam does not supply.
    fixed: Vec<Option<f64>>,
    /// Scratch: the feature vector (no allocation per call).
    features: Vec<f64>,
}

impl NeuralLaw {
    /// A law from a checked model (any features).
    pub fn new(model: NeuralModel) -> Result<NeuralLaw, NeuralError> {
        model.validate("(model)")?;
        let layers: Vec<(Vec<Vec<f64>>, Vec<f64>)> = model
            .layers
            .iter()
            .map(|l| (l.weights.clone(), l.biases.clone()))
            .collect();
        let forward = Forward::new(model.features.len(), &layers, model.activation);
        let (input_lo, input_hi): (Vec<f64>, Vec<f64>) = model
            .features
            .iter()
            .map(|f| network_input_range(f, model.variant))
            .unzip();
        let velocity = model.feature_with_role(FeatureRole::SlidingVelocity);
        let d = model.features.len();
        Ok(NeuralLaw {
            forward,
            forward_f32: None,
            f32_deviation: None,
            input_lo,
            input_hi,
            input_mean: model.features.iter().map(|f| f.input_mean).collect(),
            input_inverse_std: model.features.iter().map(|f| 1.0 / f.input_std).collect(),
            signed_velocity: if model.variant == Variant::Signed {
                velocity
            } else {
                None
            },
            velocity,
            normal_force: model.feature_with_role(FeatureRole::NormalForce),
            fixed: vec![None; d],
            features: vec![0.0; d],
            model,
        })
    }

    /// The same law evaluated in f32 (`friction.inference = f32`): the weights rounded
    /// to f32, every product and sum in f32, inputs and output converted at the edges.
    /// Its largest deviation from the exact network is measured over the training range
    /// here ([`NeuralLaw::f32_deviation`]).
    pub fn in_f32(mut self) -> NeuralLaw {
        let layers: Vec<(Vec<Vec<f64>>, Vec<f64>)> = self
            .model
            .layers
            .iter()
            .map(|l| (l.weights.clone(), l.biases.clone()))
            .collect();
        let f32_forward =
            Forward::<f32>::new(self.model.features.len(), &layers, self.model.activation);
        let mut deviation: f64 = 0.0;
        for point in sample_points(&self) {
            self.forward_f32 = None;
            let exact = self.evaluate(&point);
            self.forward_f32 = Some(f32_forward.clone());
            let single = self.evaluate(&point);
            if let (Ok(exact), Ok(single)) = (exact, single) {
                deviation = deviation.max((single - exact).abs());
            }
        }
        self.forward_f32 = Some(f32_forward);
        self.f32_deviation = Some(deviation);
        self
    }

    /// How this law is evaluated: `Exact` or `F32` (the table is its own law,
    /// `table::TableLaw`).
    pub fn inference(&self) -> Inference {
        if self.forward_f32.is_some() {
            Inference::F32
        } else {
            Inference::Exact
        }
    }

    /// For an f32 law, its largest deviation from the exact network over the training
    /// range (N, target units), measured when it was built; None for the exact law.
    pub fn f32_deviation(&self) -> Option<f64> {
        self.f32_deviation
    }

    /// The values given to features with [`NeuralLaw::with_fixed_feature`], by feature.
    pub fn fixed_features(&self) -> &[Option<f64>] {
        &self.fixed
    }

    /// The feature with the sliding-velocity role.
    pub fn velocity(&self) -> Option<usize> {
        self.velocity
    }

    /// The feature with the normal-force role.
    pub fn normal_force(&self) -> Option<usize> {
        self.normal_force
    }

    /// The training range of the normal force (N), the range the network clamps it to;
    /// (0, 0) without a normal-force feature.
    pub fn normal_force_range(&self) -> (f64, f64) {
        self.normal_force
            .map_or((0.0, 0.0), |k| (self.input_lo[k], self.input_hi[k]))
    }

    /// `normal_force` (N) clamped to the training range, as the network sees it.
    pub fn clamped_normal_force(&self, normal_force: f64) -> f64 {
        let (lo, hi) = self.normal_force_range();
        if self.normal_force.is_some() {
            normal_force.clamp(lo, hi)
        } else {
            0.0
        }
    }

    /// Loads and checks a weights file: our JSON, or an ONNX file described by its own
    /// metadata (`neural::onnx`), told apart by `WeightsFileKind::of`. A MATLAB file is
    /// refused with the command that converts it. Every error names `path` once.
    pub fn from_file(path: &Path) -> Result<NeuralLaw, NeuralError> {
        let load = || {
            if WeightsFileKind::by_extension(path) == Some(WeightsFileKind::Matlab) {
                return Err(NeuralError::Matlab {
                    path: path.to_path_buf(),
                });
            }
            let bytes = WEIGHTS_FILE.read(path)?;
            let source_name = path.display().to_string();
            let model = match WeightsFileKind::of(path, &bytes) {
                WeightsFileKind::Onnx => {
                    onnx::import_onnx(&bytes, &onnx::OnnxImport::named(source_name))?
                }
                WeightsFileKind::Json => {
                    NeuralModel::from_json(&WEIGHTS_FILE.text(path, bytes)?, &source_name)?
                }
                WeightsFileKind::Matlab => {
                    return Err(NeuralError::Matlab {
                        path: path.to_path_buf(),
                    })
                }
            };
            NeuralLaw::new(model)
        };
        load().map_err(|e| e.in_file(path))
    }

    /// Parses and checks weights-file text; `source_name` appears in errors.
    pub fn from_json(text: &str, source_name: &str) -> Result<NeuralLaw, NeuralError> {
        NeuralLaw::new(NeuralModel::from_json(text, source_name)?)
    }

    /// The shipped model trained on the paper's synthetic data (plain variant: the
    /// paper's network, 3 x 100 tanh, lambda 0.004), embedded in the library.
    pub fn paper_default() -> Result<NeuralLaw, NeuralError> {
        NeuralLaw::from_json(PAPER_PLAIN_JSON, "weights/paper-plain.json (embedded)")
    }

    /// The shipped signed-variant model on the same data (exact jump at v = 0).
    pub fn paper_signed() -> Result<NeuralLaw, NeuralError> {
        NeuralLaw::from_json(PAPER_SIGNED_JSON, "weights/paper-signed.json (embedded)")
    }

    pub fn model(&self) -> &NeuralModel {
        &self.model
    }

    /// Feature names in the order `evaluate` expects them.
    pub fn feature_names(&self) -> Vec<&str> {
        self.model.feature_names()
    }

    pub fn variant(&self) -> Variant {
        self.model.variant
    }

    /// Gives feature `name` a fixed value for use as the beam's friction law (e.g. the
    /// temperature of a test). Only features without the sliding-velocity or
    /// normal-force role can be fixed.
    pub fn with_fixed_feature(mut self, name: &str, value: f64) -> Result<NeuralLaw, NeuralError> {
        let index = self
            .model
            .features
            .iter()
            .position(|f| f.name == name)
            .ok_or_else(|| {
                NeuralError::InvalidInput(format!(
                    "the model has no feature '{name}' (features: {})",
                    self.feature_names().join(", ")
                ))
            })?;
        if Some(index) == self.velocity || Some(index) == self.normal_force {
            return Err(NeuralError::InvalidInput(format!(
                "'{name}' is supplied by the beam (sliding velocity or normal force) and cannot be fixed"
            )));
        }
        if !value.is_finite() {
            return Err(NeuralError::NonFiniteInput {
                feature: name.to_string(),
                value,
            });
        }
        self.fixed[index] = Some(value);
        Ok(self)
    }

    /// Why the law cannot serve `FrictionLaw::sliding_force`, or None if it can.
    pub fn beam_problem(&self) -> Option<String> {
        if self.velocity.is_none() {
            return Some(format!(
                "no feature has the role sliding_velocity (features: {})",
                self.feature_names().join(", ")
            ));
        }
        if self.normal_force.is_none() {
            return Some(format!(
                "no feature has the role normal_force (features: {})",
                self.feature_names().join(", ")
            ));
        }
        let missing: Vec<&str> = (0..self.fixed.len())
            .filter(|&k| {
                Some(k) != self.velocity && Some(k) != self.normal_force && self.fixed[k].is_none()
            })
            .map(|k| self.model.features[k].name.as_str())
            .collect();
        if !missing.is_empty() {
            return Some(format!(
                "feature(s) {} are not supplied by the beam; give them fixed values with with_fixed_feature",
                missing.join(", ")
            ));
        }
        None
    }

    /// The force (N) in the direction of `sliding_velocity` (m/s) under `normal_force`
    /// (N) and dF/dv (N s/m) by forward-mode differentiation through the network (see
    /// `evaluate_scratch_with`): the beam's features set from the two, the others fixed;
    /// NaN for both if the law was not checked with `into_friction_law` and lacks an
    /// input. Allocation-free.
    pub fn force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64) {
        if !self.set_beam_features(sliding_velocity, normal_force) {
            return (f64::NAN, f64::NAN);
        }
        self.evaluate_scratch_with::<true>()
    }

    /// Friction force (target units) for one sample of features in model order and raw
    /// units. Refuses a wrong number of inputs and non-finite values. Allocation-free.
    pub fn evaluate(&mut self, features: &[f64]) -> Result<f64, NeuralError> {
        self.load_features(features)?;
        Ok(self.evaluate_scratch())
    }

    /// Checks one sample of features (model order, raw units) and copies it into the
    /// scratch vector: refuses a wrong number of inputs and non-finite values.
    fn load_features(&mut self, features: &[f64]) -> Result<(), NeuralError> {
        if features.len() != self.features.len() {
            return Err(NeuralError::FeatureCount {
                expected: self.features.len(),
                got: features.len(),
                names: self.feature_names().join(", "),
            });
        }
        if let Some(k) = features.iter().position(|v| !v.is_finite()) {
            return Err(NeuralError::NonFiniteInput {
                feature: self.model.features[k].name.clone(),
                value: features[k],
            });
        }
        self.features.copy_from_slice(features);
        Ok(())
    }

    /// The force (target units) of [`NeuralLaw::evaluate`], the same number, and its
    /// derivative dF/dv with respect to the sliding-velocity feature (target units per
    /// m/s), by forward-mode differentiation in the same pass (see
    /// `evaluate_scratch_with`): 0 where the velocity is clamped to the training range,
    /// and for the signed variant F = sign(v) max(y(|v|), 0) the slope y'(|v|) where
    /// y > 0 (else 0) on either side of v = 0 (the jump at 0 itself has no slope). A
    /// network without a sliding-velocity feature gives slope 0. Refuses what `evaluate`
    /// refuses. Allocation-free.
    pub fn evaluate_with_velocity_slope(
        &mut self,
        features: &[f64],
    ) -> Result<(f64, f64), NeuralError> {
        self.load_features(features)?;
        if self.velocity.is_none() {
            return Ok((self.evaluate_scratch(), 0.0));
        }
        Ok(self.evaluate_scratch_with::<true>())
    }

    /// Batch evaluation: `features` has one row per feature (model order) and one column
    /// per sample; uses matrix-matrix products. Same results as `evaluate` up to rounding.
    pub fn evaluate_batch(&self, features: &DMatrix<f64>) -> Result<Vec<f64>, NeuralError> {
        if features.ncols() == 0 {
            return Ok(Vec::new());
        }
        self.model.predict_columns(features)
    }

    /// Evaluates the feature vector in `self.features`.
    #[inline]
    pub(crate) fn evaluate_scratch(&mut self) -> f64 {
        self.evaluate_scratch_with::<false>().0
    }

    /// Evaluates the feature vector in `self.features` and, with `SLOPE`, the force's
    /// derivative with respect to the sliding-velocity feature by forward-mode
    /// differentiation in the same pass: with x' = dx/dv, each layer gives
    /// z' = W x' and a' = phi'(z) z' next to z = W x + b and a = phi(z). The force is
    /// the same number either way. The slope is that of the law as evaluated: 0 where
    /// the velocity is clamped, and for the signed variant g'(|v|) (F = sign(v) g(|v|)
    /// is odd, its slope even), 0 where max(0, g) cuts.
    #[inline]
    pub(crate) fn evaluate_scratch_with<const SLOPE: bool>(&mut self) -> (f64, f64) {
        let NeuralLaw {
            forward,
            forward_f32,
            signed_velocity,
            features,
            model,
            ..
        } = self;
        let mut sign = 1.0;
        if let Some(k) = *signed_velocity {
            sign = signum_or_zero(features[k]);
            features[k] = features[k].abs();
        }
        // d|v|/dv, and at v = 0 that of v > 0 (the slope of the magnitude).
        let seed_sign = if sign == 0.0 { 1.0 } else { sign };
        let inputs = Inputs {
            features,
            lo: &self.input_lo,
            hi: &self.input_hi,
            mean: &self.input_mean,
            inverse_std: &self.input_inverse_std,
            velocity: self.velocity,
            seed_sign,
        };
        let (z, dz) = match forward_f32 {
            Some(forward) => inputs.run::<f32, SLOPE>(forward),
            None => inputs.run::<f64, SLOPE>(forward),
        };
        let force = model.force_from_output(z, sign);
        if !SLOPE {
            return (force, 0.0);
        }
        // F = mean + std z (plain) or sign(v) max(0, mean + std z) (signed: the tangent
        // carries d|v|/dv = sign(v) once more, and sign(v)^2 = 1).
        let cut = model.variant == Variant::Signed
            && model.target.output_mean + model.target.output_std * z < 0.0;
        let slope = if cut {
            0.0
        } else {
            seed_sign * model.target.output_std * dz
        };
        (force, slope)
    }

    /// Fills `self.features` for the beam's (v, F_n); false if the law cannot serve
    /// the beam (a feature is neither supplied nor fixed).
    pub(crate) fn set_beam_features(&mut self, sliding_velocity: f64, normal_force: f64) -> bool {
        let (Some(v), Some(f)) = (self.velocity, self.normal_force) else {
            return false;
        };
        for k in 0..self.features.len() {
            self.features[k] = if k == v {
                sliding_velocity
            } else if k == f {
                normal_force
            } else {
                match self.fixed[k] {
                    Some(value) => value,
                    None => return false,
                }
            };
        }
        true
    }
}

/// Points of the training range at which the f32 network is compared with the exact
/// one when it is built: a 64 x 16 grid over (sliding velocity, normal force), or 1024
/// points of a low-discrepancy sequence over the features' box for other models.
pub const F32_SAMPLES: usize = 1024;

/// The points of the features' box at which to compare two evaluations of `law`: its
/// training range (the range the network clamps to), the beam's features on a grid
/// when the model is a friction law of the beam, otherwise a Halton sequence.
fn sample_points(law: &NeuralLaw) -> Vec<Vec<f64>> {
    let model = law.model();
    let ranges: Vec<(f64, f64)> = model.features.iter().map(|f| (f.min, f.max)).collect();
    let fixed = law.fixed_features();
    let point = |u: &[f64]| -> Vec<f64> {
        ranges
            .iter()
            .zip(u)
            .zip(fixed)
            .map(|(((lo, hi), t), fixed)| fixed.unwrap_or(lo + (hi - lo) * t))
            .collect()
    };
    if let (Some(v), Some(f), None) = (law.velocity(), law.normal_force(), law.beam_problem()) {
        let (columns, rows) = (64, F32_SAMPLES / 64);
        let mut points = Vec::with_capacity(F32_SAMPLES);
        for i in 0..columns {
            for j in 0..rows {
                let mut u = vec![0.5; ranges.len()];
                u[v] = (i as f64 + 0.5) / columns as f64;
                u[f] = j as f64 / (rows - 1) as f64;
                points.push(point(&u));
            }
        }
        points
    } else {
        const PRIMES: [u64; 8] = [2, 3, 5, 7, 11, 13, 17, 19];
        (1..=F32_SAMPLES as u64)
            .map(|n| {
                let u: Vec<f64> = (0..ranges.len())
                    .map(|k| radical_inverse(n, PRIMES[k % PRIMES.len()]))
                    .collect();
                point(&u)
            })
            .collect()
    }
}

/// The van der Corput radical inverse of `n` in base `base`, in [0, 1).
fn radical_inverse(mut n: u64, base: u64) -> f64 {
    let (mut value, mut scale) = (0.0, 1.0 / base as f64);
    while n > 0 {
        value += (n % base) as f64 * scale;
        n /= base;
        scale /= base as f64;
    }
    value
}

/// One sample's features (the signed variant's velocity already |v|) and what maps
/// them to the network's standardised inputs.
struct Inputs<'a> {
    features: &'a [f64],
    lo: &'a [f64],
    hi: &'a [f64],
    mean: &'a [f64],
    inverse_std: &'a [f64],
    velocity: Option<usize>,
    /// d|v|/dv for the signed variant (1 for the plain one).
    seed_sign: f64,
}

impl Inputs<'_> {
    /// Clamps and standardises the features into `forward`'s input buffer (and their
    /// derivatives along v into its tangent buffer), then runs it: z and z'.
    #[inline]
    fn run<T: Real, const SLOPE: bool>(&self, forward: &mut Forward<T>) -> (f64, f64) {
        let (inputs, tangents) = forward.inputs_mut();
        for (k, feature) in self.features.iter().enumerate() {
            inputs[k] = T::from_f64(
                (feature.clamp(self.lo[k], self.hi[k]) - self.mean[k]) * self.inverse_std[k],
            );
            if SLOPE {
                // d input / dv: 1/std on the velocity inside its range (times sign(v) for
                // the signed variant's |v|), 0 for the other features and when clamped.
                let inside = *feature >= self.lo[k] && *feature <= self.hi[k];
                tangents[k] = T::from_f64(if Some(k) == self.velocity && inside {
                    self.inverse_std[k] * self.seed_sign
                } else {
                    0.0
                });
            }
        }
        forward.run::<SLOPE>()
    }
}
