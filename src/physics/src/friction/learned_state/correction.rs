//! The learned law's network part: a one-hidden-layer tanh network that corrects the
//! friction level, N(psi, F_n) = sum_k w_k tanh(W_k . x + c_k), with the standardised
//! inputs x = ((psi - m_psi) / s_psi, (F_n - m_F) / s_F), each clamped to the range it
//! was trained on (beyond it the correction is held constant, as the memoryless network
//! clamps its inputs). No output bias: mu_0 is one. Output in the units of the friction
//! coefficient (1).

use serde::{Deserialize, Serialize};

use crate::neural::network::tanh;

/// How a raw input is standardised, and the range it was trained on.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputScale {
    pub name: String,
    pub unit: String,
    pub mean: f64,
    /// > 0.
    pub std: f64,
    pub min: f64,
    pub max: f64,
}

impl InputScale {
    /// The standardised, clamped input and its derivative by the raw input (0 outside
    /// the range).
    fn apply(&self, raw: f64) -> (f64, f64) {
        if raw < self.min || raw > self.max {
            ((raw.clamp(self.min, self.max) - self.mean) / self.std, 0.0)
        } else {
            ((raw - self.mean) / self.std, 1.0 / self.std)
        }
    }
}

/// The correction network (module formula). Parameters, flat, per hidden unit k:
/// W_k (two values), c_k, w_k.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Correction {
    /// The state psi, then the normal force F_n (N).
    pub inputs: [InputScale; 2],
    pub hidden_weights: Vec<[f64; 2]>,
    pub hidden_biases: Vec<f64>,
    pub output_weights: Vec<f64>,
}

/// N and its derivatives by the raw inputs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CorrectionValue {
    pub value: f64,
    pub d_state: f64,
    pub d_normal_force: f64,
}

/// Parameters per hidden unit.
pub const PER_UNIT: usize = 4;

impl Correction {
    pub fn hidden(&self) -> usize {
        self.output_weights.len()
    }

    pub fn parameter_count(&self) -> usize {
        PER_UNIT * self.hidden()
    }

    /// The flat parameters (module layout).
    pub fn parameters(&self) -> Vec<f64> {
        let mut p = Vec::with_capacity(self.parameter_count());
        for k in 0..self.hidden() {
            p.extend_from_slice(&self.hidden_weights[k]);
            p.push(self.hidden_biases[k]);
            p.push(self.output_weights[k]);
        }
        p
    }

    /// Sets the flat parameters; `p` has `parameter_count` values.
    pub fn set_parameters(&mut self, p: &[f64]) {
        for (k, unit) in p.chunks_exact(PER_UNIT).enumerate() {
            self.hidden_weights[k] = [unit[0], unit[1]];
            self.hidden_biases[k] = unit[2];
            self.output_weights[k] = unit[3];
        }
    }

    /// N at (psi, F_n); when `gradient` is given (parameter_count values), adds
    /// `weight` dN/dp to it.
    pub fn evaluate(
        &self,
        state: f64,
        normal_force: f64,
        gradient: Option<(&mut [f64], f64)>,
    ) -> CorrectionValue {
        let (x0, dx0) = self.inputs[0].apply(state);
        let (x1, dx1) = self.inputs[1].apply(normal_force);
        let mut out = CorrectionValue::default();
        let mut gradient = gradient;
        for k in 0..self.hidden() {
            let [w0, w1] = self.hidden_weights[k];
            let h = tanh(w0 * x0 + w1 * x1 + self.hidden_biases[k]);
            let w = self.output_weights[k];
            let dh = w * (1.0 - h * h);
            out.value += w * h;
            out.d_state += dh * w0 * dx0;
            out.d_normal_force += dh * w1 * dx1;
            if let Some((g, weight)) = gradient.as_mut() {
                let unit = &mut g[PER_UNIT * k..PER_UNIT * (k + 1)];
                unit[0] += *weight * dh * x0;
                unit[1] += *weight * dh * x1;
                unit[2] += *weight * dh;
                unit[3] += *weight * h;
            }
        }
        out
    }
}
