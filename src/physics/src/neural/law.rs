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
//! `with_fixed_feature`. `NeuralLaw::into_friction_law` (and `load_friction_law`) check
//! this and refuse the model otherwise. A `NeuralLaw` that has not passed that check
//! returns NaN from `sliding_force`.

use std::path::Path;

use nalgebra::DMatrix;

use super::error::NeuralError;
use super::network::Activation;
use super::weights::FeatureRole;
use super::weights::{network_input_range, NeuralModel, Variant};
use crate::friction::{signum_or_zero, FrictionLaw};

/// One layer in inference layout: weights row-major (outputs x inputs), so output o is
/// a contiguous dot product.
#[derive(Clone, Debug)]
struct DenseLayer {
    inputs: usize,
    outputs: usize,
    weights: Vec<f64>,
    biases: Vec<f64>,
}

/// The shipped plain-variant weights (`weights/paper-plain.json`).
pub const PAPER_PLAIN_JSON: &str = include_str!("../../../../weights/paper-plain.json");
/// The shipped signed-variant weights (`weights/paper-signed.json`).
pub const PAPER_SIGNED_JSON: &str = include_str!("../../../../weights/paper-signed.json");

/// A trained neural friction model ready for evaluation.
#[derive(Clone, Debug)]
pub struct NeuralLaw {
    model: NeuralModel,
    layers: Vec<DenseLayer>,
    activation: Activation,
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
    /// AVX2 + FMA available (detected once, at construction).
    avx2_fma: bool,
    /// Scratch: the feature vector and two layer buffers (no allocation per call), and
    /// two more for the tangent of `evaluate_with_slope`.
    features: Vec<f64>,
    buffer_a: Vec<f64>,
    buffer_b: Vec<f64>,
    tangent_a: Vec<f64>,
    tangent_b: Vec<f64>,
}

/// Dot product with eight independent partial sums: a single running sum forces strictly
/// sequential additions, eight let the compiler keep several SIMD additions in flight
/// (measured: 100 x 100 matrix-vector product 2.3 us with four, 1.8 us with eight).
/// `FUSED` uses fused multiply-adds; only instantiated where the CPU has FMA.
#[inline(always)]
fn dot<const FUSED: bool>(a: &[f64], b: &[f64]) -> f64 {
    let mut partial = [0.0; 8];
    let (a8, b8) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: f64 = a8
        .remainder()
        .iter()
        .zip(b8.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in a8.zip(b8) {
        for k in 0..8 {
            partial[k] = if FUSED {
                x[k].mul_add(y[k], partial[k])
            } else {
                partial[k] + x[k] * y[k]
            };
        }
    }
    let [p0, p1, p2, p3, p4, p5, p6, p7] = partial;
    ((p0 + p4) + (p1 + p5)) + ((p2 + p6) + (p3 + p7)) + tail
}

/// y = W x + b for a row-major W (outputs x inputs).
#[inline(always)]
fn affine<const FUSED: bool>(layer: &DenseLayer, x: &[f64], y: &mut [f64]) {
    for (o, y_o) in y.iter_mut().enumerate() {
        let row = &layer.weights[o * layer.inputs..(o + 1) * layer.inputs];
        *y_o = dot::<FUSED>(row, x) + layer.biases[o];
    }
}

/// `affine` compiled for AVX2 + FMA (256-bit vectors, fused multiply-add): 1.0 us
/// instead of 1.8 us for a 100 x 100 layer here. Called only after run-time detection.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn affine_avx2_fma(layer: &DenseLayer, x: &[f64], y: &mut [f64]) {
    affine::<true>(layer, x, y);
}

/// Whether this CPU can run `affine_avx2_fma`.
fn cpu_has_avx2_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

impl NeuralLaw {
    /// A law from a checked model (any features).
    pub fn new(model: NeuralModel) -> Result<NeuralLaw, NeuralError> {
        model.validate("(model)")?;
        let layers: Vec<DenseLayer> = model
            .layers
            .iter()
            .map(|l| DenseLayer {
                inputs: l.weights.first().map_or(0, Vec::len),
                outputs: l.weights.len(),
                weights: l.weights.iter().flatten().copied().collect(),
                biases: l.biases.clone(),
            })
            .collect();
        let widest = model.layer_sizes.iter().copied().max().unwrap_or(1);
        let (input_lo, input_hi): (Vec<f64>, Vec<f64>) = model
            .features
            .iter()
            .map(|f| network_input_range(f, model.variant))
            .unzip();
        let velocity = model.feature_with_role(FeatureRole::SlidingVelocity);
        let d = model.features.len();
        Ok(NeuralLaw {
            layers,
            activation: model.activation,
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
            avx2_fma: cpu_has_avx2_fma(),
            features: vec![0.0; d],
            buffer_a: vec![0.0; widest],
            buffer_b: vec![0.0; widest],
            tangent_a: vec![0.0; widest],
            tangent_b: vec![0.0; widest],
            model,
        })
    }

    /// Loads and checks a weights file.
    pub fn from_file(path: &Path) -> Result<NeuralLaw, NeuralError> {
        NeuralLaw::new(NeuralModel::load(path)?)
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

    /// The law as the beam's `FrictionLaw`, refused with a clear error if the beam cannot
    /// supply every feature (see the module documentation).
    pub fn into_friction_law(self) -> Result<Box<dyn FrictionLaw>, NeuralError> {
        match self.beam_problem() {
            Some(problem) => Err(NeuralError::NotAFrictionLaw(problem)),
            None => Ok(Box::new(self)),
        }
    }

    /// Friction force (target units) for one sample of features in model order and raw
    /// units. Refuses a wrong number of inputs and non-finite values. Allocation-free.
    pub fn evaluate(&mut self, features: &[f64]) -> Result<f64, NeuralError> {
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
        Ok(self.evaluate_scratch())
    }

    /// The force (target units) and its derivative with respect to feature `feature`
    /// (target units per unit of that feature) at one sample of `features` (model
    /// order, raw units), by forward-mode differentiation: the tangent t = dx/dx_k
    /// enters as 1/std_k in input k (0 when x_k is clamped: the law is flat beyond the
    /// data), passes each layer as W t and each activation as a'(z) t, with
    /// tanh' = 1 - a^2, sigmoid' = a (1 - a) and relu' = 1 for z > 0, else 0 (a the
    /// activation), and leaves scaled by the output's std. The force is `evaluate`'s,
    /// bit for bit. For the signed variant, F = sign(v) max(y(|v|), 0): dF/dv = dy/d|v|
    /// where y > 0 (else 0) on either side of v = 0 (the jump at 0 itself has no
    /// slope), and any other feature takes the sign. Refuses what `evaluate` refuses
    /// and a feature index out of range. Allocation-free.
    pub fn evaluate_with_slope(
        &mut self,
        features: &[f64],
        feature: usize,
    ) -> Result<(f64, f64), NeuralError> {
        let force = self.evaluate(features)?;
        if feature >= features.len() {
            return Err(NeuralError::InvalidInput(format!(
                "feature index {feature} is out of range: the model has {} features ({})",
                features.len(),
                self.feature_names().join(", ")
            )));
        }
        let d = features.len();
        let NeuralLaw {
            layers,
            activation,
            input_lo,
            input_hi,
            input_mean,
            input_inverse_std,
            signed_velocity,
            buffer_a: value,
            buffer_b: next_value,
            tangent_a: tangent,
            tangent_b: next_tangent,
            model,
            ..
        } = self;
        let mut output_sign = 1.0;
        for k in 0..d {
            let mut x = features[k];
            if Some(k) == *signed_velocity {
                // F depends on |v| and sign(v): d|v|/dv = sign(v) cancels against the
                // sign F takes, so the velocity's tangent enters unsigned.
                if k != feature {
                    output_sign = signum_or_zero(x);
                }
                x = x.abs();
            }
            let inside = x >= input_lo[k] && x <= input_hi[k];
            value[k] = (x.clamp(input_lo[k], input_hi[k]) - input_mean[k]) * input_inverse_std[k];
            tangent[k] = if k == feature && inside {
                input_inverse_std[k]
            } else {
                0.0
            };
        }
        let last = layers.len() - 1;
        for (l, layer) in layers.iter().enumerate() {
            for o in 0..layer.outputs {
                let row = &layer.weights[o * layer.inputs..(o + 1) * layer.inputs];
                let z = dot::<false>(row, &value[..layer.inputs]) + layer.biases[o];
                let dz = dot::<false>(row, &tangent[..layer.inputs]);
                if l == last {
                    next_value[o] = z;
                    next_tangent[o] = dz;
                } else {
                    let a = activation.apply(z);
                    let derivative = match activation {
                        Activation::Tanh => 1.0 - a * a,
                        Activation::Sigmoid => a * (1.0 - a),
                        Activation::Relu => f64::from(u8::from(z > 0.0)),
                    };
                    next_value[o] = a;
                    next_tangent[o] = derivative * dz;
                }
            }
            std::mem::swap(value, next_value);
            std::mem::swap(tangent, next_tangent);
        }
        let target = &model.target;
        let y = target.output_mean + target.output_std * value[0];
        let slope = target.output_std
            * tangent[0]
            * match model.variant {
                Variant::Plain => 1.0,
                Variant::Signed => output_sign * f64::from(u8::from(y > 0.0)),
            };
        Ok((force, slope))
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
    fn evaluate_scratch(&mut self) -> f64 {
        let NeuralLaw {
            layers,
            activation,
            input_lo,
            input_hi,
            input_mean,
            input_inverse_std,
            signed_velocity,
            features,
            buffer_a,
            buffer_b,
            model,
            avx2_fma,
            ..
        } = self;
        let mut sign = 1.0;
        if let Some(k) = *signed_velocity {
            sign = signum_or_zero(features[k]);
            features[k] = features[k].abs();
        }
        let d = features.len();
        for k in 0..d {
            buffer_a[k] = (features[k].clamp(input_lo[k], input_hi[k]) - input_mean[k])
                * input_inverse_std[k];
        }
        let last = layers.len() - 1;
        let (mut input, mut output) = (buffer_a, buffer_b);
        for (l, layer) in layers.iter().enumerate() {
            let x = &input[..layer.inputs];
            let y = &mut output[..layer.outputs];
            #[cfg(target_arch = "x86_64")]
            if *avx2_fma {
                // SAFETY: avx2_fma is true only if the running CPU has AVX2 and FMA
                // (is_x86_feature_detected at construction), the features this function
                // is compiled for. It has no other safety requirement.
                unsafe { affine_avx2_fma(layer, x, y) };
            } else {
                affine::<false>(layer, x, y);
            }
            #[cfg(not(target_arch = "x86_64"))]
            affine::<false>(layer, x, y);
            if l != last {
                y.iter_mut().for_each(|v| *v = activation.apply(*v));
            }
            std::mem::swap(&mut input, &mut output);
        }
        model.force_from_output(input[0], sign)
    }
}

impl FrictionLaw for NeuralLaw {
    fn name(&self) -> &str {
        crate::choice::Choice::name(crate::scene::FrictionLawKind::Neural)
    }

    /// The plain variant is a smooth network output; the signed variant jumps by
    /// 2 g(0) at v = 0.
    fn continuous(&self) -> bool {
        self.model.variant == Variant::Plain
    }

    /// Signed force (N) in the direction of `sliding_velocity` (m/s) under
    /// `normal_force` (N); NaN if the law was not checked with `into_friction_law`
    /// and lacks an input. Allocation-free.
    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64 {
        let (Some(v), Some(f)) = (self.velocity, self.normal_force) else {
            return f64::NAN;
        };
        for k in 0..self.features.len() {
            self.features[k] = if k == v {
                sliding_velocity
            } else if k == f {
                normal_force
            } else {
                match self.fixed[k] {
                    Some(value) => value,
                    None => return f64::NAN,
                }
            };
        }
        self.evaluate_scratch()
    }
}
