//! The network's exact input Jacobian, and that of its velocity slope, by forward-mode
//! differentiation to second order through the layers (see `crate::jacobian` for what
//! is returned and the conventions at v = 0).
//!
//! # Equations
//! Raw features f_k (model order, units of the weights file) become network inputs
//! x_k = (c_k(f_k) - m_k) / s_k, c_k the clamp to the training range [lo_k, hi_k] (for
//! the signed variant's velocity, |v| clamped to the range of |v|); the layers give
//! z_l = W_l a_(l-1) + b_l, a_l = phi(z_l), and the linear output z; the force is
//! y = mu_y + s_y z (plain) or F = sign(v) max(0, y) with y evaluated at |v| (signed).
//!
//! Next to each layer's values the pass carries the tangents along every input,
//! da/dx_k, and the second derivatives along (x_v, x_k), v the sliding velocity:
//! - dz_l/dx_k = W_l da_(l-1)/dx_k, d2z_l/dx_v dx_k = W_l d2a_(l-1)/dx_v dx_k;
//! - da_l/dx_k = phi'(z_l) dz_l/dx_k;
//! - d2a_l/dx_v dx_k = phi''(z_l) dz_l/dx_v dz_l/dx_k + phi'(z_l) d2z_l/dx_v dx_k;
//!
//! with tanh' = 1 - t^2, tanh'' = -2 t (1 - t^2); sigmoid' = s (1 - s),
//! sigmoid'' = s (1 - s) (1 - 2 s); relu' = [z > 0], relu'' = 0 (the kink at z = 0 takes
//! the branch z <= 0, as the forward pass does). The cost is that of a batched forward
//! pass over 1 + 2d samples for d features (one matrix product per layer).
//!
//! The chain rule then goes back to the raw features: dx_k/df_k = 1/s_k where f_k is in
//! [lo_k, hi_k], edges included (there the derivative is the one-sided limit from
//! inside), and 0 outside, where the clamp holds the input constant; the signed
//! variant's velocity adds d|v|/dv = sign(v). The signed force is cut to 0 where y < 0:
//! there every derivative is 0 (at y = 0 exactly, those of y).
//!
//! # Precision
//! Always the exact (f64) network, from the weights file, whichever inference the law
//! evaluates its force with (f32, or a table): see docs/decisions.md.

use super::error::NeuralError;
use super::law::NeuralLaw;
use nalgebra::{DMatrixView, DMatrixViewMut};

use super::network::{Activation, LayerShape};
use super::weights::{network_input_range, FeatureRole, NeuralModel, Variant};
use crate::elementary;
use crate::elementary::signum_or_zero;
use crate::jacobian::{magnitude_slope, LawJacobian};

/// Values of one layer with their first derivatives along every input and second
/// derivatives along (velocity, input), as m = 1 + 2d components of as many numbers as
/// the layer has units, one after the other: a, da/dx_1 .. da/dx_d,
/// d2a/dx_v dx_1 .. d2a/dx_v dx_d. A layer's product is then one matrix product
/// W [a, da/dx_1, ...].
struct Jet {
    inputs: usize,
    units: usize,
    components: Vec<f64>,
}

impl Jet {
    /// The network inputs `x` as their own variables: dx/dx_k = e_k, no curvature.
    fn inputs(x: &[f64]) -> Jet {
        let d = x.len();
        let mut components = vec![0.0; (1 + 2 * d) * d];
        components[..d].copy_from_slice(x);
        for k in 0..d {
            components[(1 + k) * d + k] = 1.0;
        }
        Jet {
            inputs: d,
            units: d,
            components,
        }
    }

    /// W a + b, and the same linear map (without b) of the derivatives, for the layer
    /// `shape` of the flat parameters `params` (W column-major).
    fn affine(&self, shape: &LayerShape, params: &[f64]) -> Jet {
        let (n, m) = (shape.outputs, 1 + 2 * self.inputs);
        let mut components = vec![0.0; n * m];
        // Contiguous column-major views: nalgebra's product (matrixmultiply, or gemv
        // per column for thin products) without `network::gemm`'s plain loops for
        // dimensions <= 5, which m = 5 (two inputs) would take.
        let weights = DMatrixView::from_slice(&params[shape.weight_range()], n, shape.inputs);
        let inputs = DMatrixView::from_slice(&self.components, self.units, m);
        DMatrixViewMut::from_slice(&mut components, n, m).gemm(1.0, &weights, &inputs, 0.0);
        for (z, b) in components.iter_mut().zip(&params[shape.bias_range()]) {
            *z += b;
        }
        Jet {
            inputs: self.inputs,
            units: n,
            components,
        }
    }

    /// phi applied element-wise, with the chain rule to second order along
    /// (`velocity`, k); without a velocity input the second derivatives stay 0.
    fn activate(&mut self, activation: Activation, velocity: Option<usize>) {
        let (d, n) = (self.inputs, self.units);
        let c = &mut self.components;
        for o in 0..n {
            let (phi, d1, d2) = derivatives(activation, c[o]);
            c[o] = phi;
            let along_velocity = velocity.map_or(0.0, |v| c[(1 + v) * n + o]);
            for k in 0..d {
                let (first, second) = ((1 + k) * n + o, (1 + d + k) * n + o);
                let dz = c[first];
                c[second] = d2 * along_velocity * dz + d1 * c[second];
                c[first] = d1 * dz;
            }
        }
    }

    /// The first unit's value, da/dx_k and d2a/dx_v dx_k (the output layer has one).
    fn value(&self) -> f64 {
        self.components[0]
    }
    fn first(&self, k: usize) -> f64 {
        self.components[(1 + k) * self.units]
    }
    fn second(&self, k: usize) -> f64 {
        self.components[(1 + self.inputs + k) * self.units]
    }
}

/// phi(z), phi'(z) and phi''(z).
fn derivatives(activation: Activation, z: f64) -> (f64, f64, f64) {
    match activation {
        Activation::Tanh => {
            let t = elementary::tanh(z);
            let d1 = 1.0 - t * t;
            (t, d1, -2.0 * t * d1)
        }
        Activation::Sigmoid => {
            let s = 1.0 / (1.0 + elementary::exp(-z));
            let d1 = s * (1.0 - s);
            (s, d1, d1 * (1.0 - 2.0 * s))
        }
        Activation::Relu => {
            if z > 0.0 {
                (z, 1.0, 0.0)
            } else {
                (0.0, 0.0, 0.0)
            }
        }
    }
}

impl NeuralModel {
    /// The force and velocity slope at `features` (model order, raw units), with their
    /// exact gradients over the features (module notes). A model without a
    /// sliding-velocity feature has slope 0 and a zero slope gradient. Refuses a wrong
    /// number of features and non-finite ones, as `NeuralLaw::evaluate` does.
    pub fn input_jacobian(&self, features: &[f64]) -> Result<LawJacobian, NeuralError> {
        self.check_point(features)?;
        let d = self.features.len();
        let velocity = self.feature_with_role(FeatureRole::SlidingVelocity);
        let signed = self.variant == Variant::Signed && velocity.is_some();
        let sign = match velocity {
            Some(v) if signed => signum_or_zero(features[v]),
            _ => 1.0,
        };
        let (x, scale) = self.inputs_and_scales(features, velocity, signed);
        let z = self.output_jet(&x, velocity)?;
        let (mean, std) = (self.target.output_mean, self.target.output_std);
        let y = mean + std * z.value();
        let cut = signed && y < 0.0;
        let force = self.force_from_output(z.value(), sign);
        if cut {
            return Ok(LawJacobian {
                force,
                slope: 0.0,
                force_gradient: vec![0.0; d],
                slope_gradient: vec![0.0; d],
            });
        }
        // dy/df_k; the signed force is sign(v) y, except that dF/dv is dy/d|v| (sign(v)
        // twice) and at v = 0 that of v > 0 (module notes of `crate::jacobian`).
        let dy: Vec<f64> = (0..d).map(|k| std * z.first(k) * scale[k]).collect();
        let force_gradient = (0..d)
            .map(|k| match velocity {
                Some(v) if signed && k == v => dy[k] * magnitude_slope(features[v]),
                _ if signed => sign * dy[k],
                _ => dy[k],
            })
            .collect();
        let Some(v) = velocity else {
            return Ok(LawJacobian {
                force,
                slope: 0.0,
                force_gradient,
                slope_gradient: vec![0.0; d],
            });
        };
        // S = dF/dv = s_y dz/dx_v dx_v/dv (sign(v)^2 = 1 for the signed variant), and
        // dS/df_k = s_y d2z/dx_v dx_k (dx_v/dv) (dx_k/df_k).
        let velocity_scale = scale[v] * magnitude_slope(features[v]).powi(signed as i32);
        let slope = std * z.first(v) * velocity_scale;
        let slope_gradient = (0..d)
            .map(|k| std * z.second(k) * velocity_scale * scale[k])
            .collect();
        Ok(LawJacobian {
            force,
            slope,
            force_gradient,
            slope_gradient,
        })
    }

    /// Refuses a wrong number of features and non-finite ones.
    fn check_point(&self, features: &[f64]) -> Result<(), NeuralError> {
        let d = self.features.len();
        if features.len() != d {
            return Err(NeuralError::FeatureCount {
                expected: d,
                got: features.len(),
                names: self.feature_names().join(", "),
            });
        }
        if let Some(k) = features.iter().position(|f| !f.is_finite()) {
            return Err(NeuralError::NonFiniteInput {
                feature: self.features[k].name.clone(),
                value: features[k],
            });
        }
        Ok(())
    }

    /// The network inputs x_k (clamped to the network's input range, standardised) and
    /// dx_k/df_k: 1 / std inside the range, 0 where the clamp holds x_k still; for the
    /// signed variant's velocity, x_v follows |v| and carries d|v|/dv.
    fn inputs_and_scales(
        &self,
        features: &[f64],
        velocity: Option<usize>,
        signed: bool,
    ) -> (Vec<f64>, Vec<f64>) {
        let d = self.features.len();
        let mut x = Vec::with_capacity(d);
        let mut scale = Vec::with_capacity(d);
        for (k, spec) in self.features.iter().enumerate() {
            let raw = if signed && Some(k) == velocity {
                features[k].abs()
            } else {
                features[k]
            };
            let (lo, hi) = network_input_range(spec, self.variant);
            x.push((raw.clamp(lo, hi) - spec.input_mean) / spec.input_std);
            let inside = (lo..=hi).contains(&raw);
            let chain = if signed && Some(k) == velocity {
                magnitude_slope(features[k])
            } else {
                1.0
            };
            scale.push(if inside { chain / spec.input_std } else { 0.0 });
        }
        (x, scale)
    }

    /// The network's output z (one value) as a jet over the inputs `x`.
    fn output_jet(&self, x: &[f64], velocity: Option<usize>) -> Result<Jet, NeuralError> {
        let network = self.network()?;
        let params = self.parameters();
        let mut jet = Jet::inputs(x);
        let last = network.layers().len() - 1;
        for (l, shape) in network.layers().iter().enumerate() {
            jet = jet.affine(shape, &params);
            if l < last {
                jet.activate(self.activation, velocity);
            }
        }
        Ok(jet)
    }
}

impl NeuralLaw {
    /// The exact network's Jacobian at `features` ([`NeuralModel::input_jacobian`]),
    /// whether this law evaluates its force in f64 or in f32.
    pub fn input_jacobian(&self, features: &[f64]) -> Result<LawJacobian, NeuralError> {
        self.model().input_jacobian(features)
    }
}

#[cfg(test)]
mod finite_differences;

#[cfg(test)]
mod tests {
    use super::*;

    /// The Jacobian's force and slope are the forward pass's, to its rounding: the
    /// shipped networks (3 x 100 tanh) at points across and beyond their training box.
    #[test]
    fn force_and_slope_are_the_laws() {
        for mut law in [
            NeuralLaw::paper_default().unwrap(),
            NeuralLaw::paper_signed().unwrap(),
        ] {
            for &(v, n) in &[
                (0.013, 100.0),
                (-0.2, 92.0),
                (0.0, 100.0),
                (3.0, 150.0),
                (-0.39, 109.0),
            ] {
                let j = law.input_jacobian(&[v, n]).unwrap();
                let (force, slope) = law.evaluate_with_velocity_slope(&[v, n]).unwrap();
                // 1e-12 N against forces of 50 N: the libm tanh here and the forward
                // pass's (within 3 ulp) differ by rounding only.
                assert!((j.force - force).abs() < 1e-12 * 50.0, "{v} {n}");
                assert!(
                    (j.slope - slope).abs() < 1e-11 * (1.0 + slope.abs()),
                    "{v} {n}: {} {slope}",
                    j.slope
                );
                assert_eq!(j.force_gradient[0], j.slope, "dF/dv is the slope");
            }
        }
    }

    /// Outside the training box the clamped inputs have zero derivatives, and at its
    /// edge the derivative is the limit from inside.
    #[test]
    fn clamped_inputs_have_zero_derivatives() {
        let law = NeuralLaw::paper_default().unwrap();
        let (lo, hi) = law.normal_force_range();
        let outside = law.input_jacobian(&[0.1, hi + 5.0]).unwrap();
        assert_eq!(outside.force_gradient[1], 0.0);
        assert_eq!(outside.slope_gradient[1], 0.0);
        assert_ne!(outside.force_gradient[0], 0.0);
        let fast = law.input_jacobian(&[10.0, 0.5 * (lo + hi)]).unwrap();
        assert_eq!((fast.slope, fast.force_gradient[0]), (0.0, 0.0));
        assert_eq!(fast.slope_gradient, vec![0.0, 0.0]);
        let edge = law.input_jacobian(&[0.1, hi]).unwrap();
        let inside = law.input_jacobian(&[0.1, hi - 1e-9]).unwrap();
        assert!(edge.force_gradient[1] != 0.0);
        assert!(
            (edge.force_gradient[1] - inside.force_gradient[1]).abs()
                < 1e-6 * inside.force_gradient[1].abs()
        );
    }
}
