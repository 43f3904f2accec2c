//! Backpropagation: the gradient of a loss with respect to all parameters of a
//! `stickslip::neural::network::Network`, after its forward pass.
//!
//! With Delta_l = dJ/dZ_l (outputs x samples) and A_{l-1} the layer's input, layer l
//! contributes dJ/dW_l = Delta_l A_{l-1}^T and dJ/db_l = Delta_l 1, and passes down
//! Delta_{l-1} = (W_l^T Delta_l) .* phi'(A_{l-1}). The activations come read-only from
//! the forward pass's `Workspace`; the deltas live here. Products go through the same
//! `gemm` as the forward pass, transposes as swapped strides.

use stickslip::neural::network::{gemm, Activation, Network, Workspace};

/// phi'(z) written in terms of a = phi(z), so the backward pass needs only the stored
/// activations: tanh' = 1 - a^2, sigmoid' = a (1 - a), relu' = [a > 0].
#[inline]
pub fn derivative_from_output(activation: Activation, a: f64) -> f64 {
    match activation {
        Activation::Tanh => 1.0 - a * a,
        Activation::Sigmoid => a * (1.0 - a),
        Activation::Relu => {
            if a > 0.0 {
                1.0
            } else {
                0.0
            }
        }
    }
}

/// The deltas dJ/dZ_l of every layer for one batch, reused across calls.
#[derive(Clone, Debug, Default)]
pub struct Deltas {
    layers: Vec<Vec<f64>>,
}

impl Deltas {
    /// The output layer's delta, dJ/dz_L, one value per sample (the network has one
    /// output), for the caller to fill before `backward`.
    pub fn output_mut(&mut self, network: &Network, samples: usize) -> &mut [f64] {
        self.ensure(network, samples);
        let last = self.layers.len() - 1;
        &mut self.layers[last][..samples]
    }

    /// Writes dJ/dparams into `gradient` (overwritten), given the output delta set through
    /// `output_mut` and the forward pass `forward` of `network` with `params` on `inputs`
    /// (inputs x samples, column-major).
    pub fn backward(
        &mut self,
        network: &Network,
        params: &[f64],
        inputs: &[f64],
        forward: &Workspace,
        gradient: &mut [f64],
    ) {
        let samples = forward.samples();
        assert!(
            self.fits(network, samples),
            "backward before output_mut for this network and batch"
        );
        let activation = network.activation();
        for (l, layer) in network.layers().iter().enumerate().rev() {
            let input: &[f64] = if l == 0 {
                &inputs[..layer.inputs * samples]
            } else {
                forward.activations(l - 1)
            };
            let (lower, upper) = self.layers.split_at_mut(l);
            let delta = &upper[0][..layer.outputs * samples];
            // dJ/dW_l = Delta_l A_{l-1}^T: A^T is A's buffer read with swapped strides.
            gemm(
                (layer.outputs, samples, layer.inputs),
                delta,
                (1, layer.outputs),
                input,
                (layer.inputs, 1),
                &mut gradient[layer.weight_range()],
            );
            // dJ/db_l = Delta_l 1 (row sums).
            let bias_gradient = &mut gradient[layer.bias_range()];
            bias_gradient.iter_mut().for_each(|g| *g = 0.0);
            for column in delta.chunks_exact(layer.outputs) {
                for (g, d) in bias_gradient.iter_mut().zip(column) {
                    *g += d;
                }
            }
            if l > 0 {
                // Delta_{l-1} = (W_l^T Delta_l) .* phi'(A_{l-1})
                let below = &mut lower[l - 1][..layer.inputs * samples];
                gemm(
                    (layer.inputs, layer.outputs, samples),
                    &params[layer.weight_range()],
                    (layer.outputs, 1),
                    delta,
                    (1, layer.outputs),
                    below,
                );
                for (d, a) in below.iter_mut().zip(input) {
                    *d *= derivative_from_output(activation, *a);
                }
            }
        }
    }

    fn fits(&self, network: &Network, samples: usize) -> bool {
        self.layers.len() == network.layers().len()
            && network
                .layers()
                .iter()
                .zip(&self.layers)
                .all(|(l, d)| d.len() >= l.outputs * samples)
    }

    fn ensure(&mut self, network: &Network, samples: usize) {
        if !self.fits(network, samples) {
            self.layers = network
                .layers()
                .iter()
                .map(|l| vec![0.0; l.outputs * samples])
                .collect();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stickslip::elementary;

    #[test]
    fn derivative_from_output_matches_central_differences_of_the_activation() {
        for activation in [Activation::Tanh, Activation::Sigmoid, Activation::Relu] {
            for i in -20..=20 {
                // Odd multiples of 0.05 keep relu away from its kink at 0.
                let z = 0.05 + 0.1 * i as f64;
                let h = 1e-6;
                let numeric = (activation.apply(z + h) - activation.apply(z - h)) / (2.0 * h);
                let analytic = derivative_from_output(activation, activation.apply(z));
                assert!((analytic - numeric).abs() < 1e-8, "{activation:?} at {z}");
            }
        }
    }

    /// One hidden tanh unit, z = w2 tanh(w1 x + b1) + b2, summed over two samples
    /// (J = z(x_1) + z(x_2), so dJ/dz = 1): the closed-form gradient, sample by sample.
    #[test]
    fn backward_gives_the_closed_form_gradient_of_a_one_unit_network() {
        let network = Network::new(&[1, 1, 1], Activation::Tanh).unwrap();
        // Layout: w1, b1, w2, b2.
        let params = [0.7, -0.2, 1.3, 0.4];
        let inputs = [0.5, -1.5];
        let mut workspace = Workspace::default();
        network.forward(&params, &inputs, 2, &mut workspace);
        let mut deltas = Deltas::default();
        deltas.output_mut(&network, 2).fill(1.0);
        let mut gradient = [f64::NAN; 4];
        deltas.backward(&network, &params, &inputs, &workspace, &mut gradient);
        let (w1, b1, w2) = (params[0], params[1], params[2]);
        let mut expected = [0.0; 4];
        for x in inputs {
            let a = elementary::tanh(w1 * x + b1);
            let da = 1.0 - a * a;
            expected[0] += w2 * da * x;
            expected[1] += w2 * da;
            expected[2] += a;
            expected[3] += 1.0;
        }
        for (g, e) in gradient.iter().zip(&expected) {
            assert!((g - e).abs() < 1e-14, "{gradient:?} vs {expected:?}");
        }
    }
}
