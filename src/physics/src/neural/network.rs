//! A fully connected feed-forward network y = f(x) with one output, evaluated on whole
//! batches with matrix-matrix products (inference only). The trainer's backpropagation
//! (`stickslip_train::backprop`) reads a forward pass's activations through
//! `Workspace::activations` and multiplies with the same `gemm`.
//!
//! Layer l (1-based) maps a_{l-1} to z_l = W_l a_{l-1} + b_l; hidden layers apply the
//! activation, a_l = phi(z_l); the last layer is linear (regression output).
//!
//! All parameters live in one flat vector (what L-BFGS works on). Per layer, first W_l
//! (outputs x inputs, column-major), then b_l. A batch is a matrix with one column per
//! sample, so a layer is one product W_l A_{l-1} (nalgebra's gemm, which hands such
//! sizes to `matrixmultiply`); transposes are strided views, never copies.

use nalgebra::{DMatrixView, DMatrixViewMut};

use super::error::NeuralError;
use crate::elementary;

crate::choice! {
    /// Hidden-layer activation function.
    #[choice(name = "Activation", description = "Hidden-layer activation function")]
    #[derive(Default)]
    pub enum Activation {
        /// tanh(z); the paper's choice.
        #[default]
        Tanh = "tanh": "tanh(z); the paper's choice",
        /// 1 / (1 + exp(-z)).
        Sigmoid = "sigmoid": "1 / (1 + exp(-z))",
        /// max(0, z).
        Relu = "relu": "max(0, z)",
    }
}

/// tanh(z) = 1 - 2 / (exp(2z) + 1): one `exp` instead of libm's `tanh` (6 ns against
/// 11 ns here, and a network evaluation needs hundreds). Absolute error within a few
/// 1e-16 of `f64::tanh` (tested), which is all a network needs (its outputs are
/// compared in absolute terms); saturates to exactly +-1 and propagates NaN.
#[inline]
pub fn tanh(z: f64) -> f64 {
    1.0 - 2.0 / (elementary::exp(2.0 * z) + 1.0)
}

impl Activation {
    #[inline]
    pub fn apply(self, z: f64) -> f64 {
        match self {
            Activation::Tanh => tanh(z),
            Activation::Sigmoid => 1.0 / (1.0 + elementary::exp(-z)),
            Activation::Relu => z.max(0.0),
        }
    }
}

/// Where layer l's parameters sit in the flat parameter vector.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LayerShape {
    pub inputs: usize,
    pub outputs: usize,
    /// Offset of W_l (outputs x inputs, column-major).
    pub weights: usize,
    /// Offset of b_l.
    pub biases: usize,
}

impl LayerShape {
    pub fn weight_range(&self) -> std::ops::Range<usize> {
        self.weights..self.weights + self.inputs * self.outputs
    }
    pub fn bias_range(&self) -> std::ops::Range<usize> {
        self.biases..self.biases + self.outputs
    }
}

/// Shape of the network: layer sizes (inputs, hidden..., 1) and activation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Network {
    layer_sizes: Vec<usize>,
    activation: Activation,
    layers: Vec<LayerShape>,
}

impl Network {
    /// `layer_sizes` = [inputs, hidden_1, ..., hidden_k, 1]; k = 0 is a linear model.
    pub fn new(layer_sizes: &[usize], activation: Activation) -> Result<Network, NeuralError> {
        if layer_sizes.len() < 2 {
            return Err(NeuralError::InvalidInput(
                "a network needs at least an input and an output layer".into(),
            ));
        }
        if layer_sizes.contains(&0) {
            return Err(NeuralError::InvalidInput(format!(
                "layer sizes must be positive, got {layer_sizes:?}"
            )));
        }
        if *layer_sizes.last().unwrap_or(&0) != 1 {
            return Err(NeuralError::InvalidInput(
                "the network has exactly one output".into(),
            ));
        }
        let mut layers = Vec::with_capacity(layer_sizes.len() - 1);
        let mut offset = 0;
        for pair in layer_sizes.windows(2) {
            let (inputs, outputs) = (pair[0], pair[1]);
            layers.push(LayerShape {
                inputs,
                outputs,
                weights: offset,
                biases: offset + inputs * outputs,
            });
            offset += inputs * outputs + outputs;
        }
        Ok(Network {
            layer_sizes: layer_sizes.to_vec(),
            activation,
            layers,
        })
    }

    pub fn layer_sizes(&self) -> &[usize] {
        &self.layer_sizes
    }
    pub fn activation(&self) -> Activation {
        self.activation
    }
    pub fn layers(&self) -> &[LayerShape] {
        &self.layers
    }
    pub fn inputs(&self) -> usize {
        self.layer_sizes[0]
    }
    pub fn parameter_count(&self) -> usize {
        self.layers.last().map_or(0, |l| l.biases + l.outputs)
    }

    /// Forward pass of `samples` columns of `inputs` (inputs x samples, column-major);
    /// returns the outputs (one per sample), which live in `workspace` (as do every
    /// layer's activations, see `Workspace::activations`).
    pub fn forward<'w>(
        &self,
        params: &[f64],
        inputs: &[f64],
        samples: usize,
        workspace: &'w mut Workspace,
    ) -> &'w [f64] {
        workspace.ensure(self, samples);
        let last = self.layers.len() - 1;
        for (l, layer) in self.layers.iter().enumerate() {
            let (before, after) = workspace.activations.split_at_mut(l);
            let input: &[f64] = if l == 0 {
                inputs
            } else {
                &before[l - 1][..layer.inputs * samples]
            };
            let output = &mut after[0][..layer.outputs * samples];
            // Z = W A_{l-1}
            gemm(
                (layer.outputs, layer.inputs, samples),
                &params[layer.weight_range()],
                (1, layer.outputs),
                input,
                (1, layer.inputs),
                output,
            );
            let biases = &params[layer.bias_range()];
            if l == last {
                for column in output.chunks_exact_mut(layer.outputs) {
                    for (z, b) in column.iter_mut().zip(biases) {
                        *z += b;
                    }
                }
            } else {
                let activation = self.activation;
                for column in output.chunks_exact_mut(layer.outputs) {
                    for (z, b) in column.iter_mut().zip(biases) {
                        *z = activation.apply(*z + b);
                    }
                }
            }
        }
        &workspace.activations[last][..samples]
    }
}

/// Products with a dimension at or below this go through `small_gemm`: nalgebra 0.33
/// sends them to a gemv fallback that indexes past the buffer when A is a strided
/// (transposed) view (caught by debug assertions); above it, nalgebra calls
/// `matrixmultiply`, which honours any strides.
const SMALL_DIMENSION: usize = 5;

/// C = A B for column-major C (m x n, overwritten); A (m x k) and B (k x n) are given by
/// their buffers and (row stride, column stride), so a transpose is just swapped strides
/// (the trainer's backward pass multiplies by W^T and A^T this way). The summation order
/// is fixed for given sizes, which the byte-for-byte reproduction of the shipped weights
/// relies on.
pub fn gemm(
    (m, k, n): (usize, usize, usize),
    a: &[f64],
    a_strides: (usize, usize),
    b: &[f64],
    b_strides: (usize, usize),
    c: &mut [f64],
) {
    if m.min(k).min(n) <= SMALL_DIMENSION {
        small_gemm((m, k, n), a, a_strides, b, b_strides, c);
        return;
    }
    let a = DMatrixView::from_slice_with_strides(a, m, k, a_strides.0, a_strides.1);
    let b = DMatrixView::from_slice_with_strides(b, k, n, b_strides.0, b_strides.1);
    let mut c = DMatrixViewMut::from_slice(c, m, n);
    c.gemm(1.0, &a, &b, 0.0);
}

/// Plain loops for thin products (a layer with 1 or 2 units): C[:, j] = sum_p A[:, p] B[p, j],
/// accumulated in increasing p.
fn small_gemm(
    (m, k, n): (usize, usize, usize),
    a: &[f64],
    (a_row, a_col): (usize, usize),
    b: &[f64],
    (b_row, b_col): (usize, usize),
    c: &mut [f64],
) {
    for j in 0..n {
        let column = &mut c[j * m..(j + 1) * m];
        column.iter_mut().for_each(|v| *v = 0.0);
        for p in 0..k {
            let b_pj = b[p * b_row + j * b_col];
            for (i, c_ij) in column.iter_mut().enumerate() {
                *c_ij += a[i * a_row + p * a_col] * b_pj;
            }
        }
    }
}

/// Buffers of one batch's forward pass: every layer's activations, reused across calls.
#[derive(Clone, Debug, Default)]
pub struct Workspace {
    /// Samples the buffers hold room for.
    capacity: usize,
    /// Samples of the last `forward`.
    samples: usize,
    /// Per layer, outputs x capacity, column-major.
    activations: Vec<Vec<f64>>,
    /// Per layer, its number of outputs.
    widths: Vec<usize>,
}

impl Workspace {
    /// Samples of the last forward pass.
    pub fn samples(&self) -> usize {
        self.samples
    }

    /// Layer `layer`'s (0-based) activations from the last forward pass, column-major
    /// (outputs x samples): a_l = phi(z_l) for hidden layers, z_L (the network's output)
    /// for the last. Read-only: what backpropagation needs besides the parameters.
    pub fn activations(&self, layer: usize) -> &[f64] {
        &self.activations[layer][..self.widths[layer] * self.samples]
    }

    fn ensure(&mut self, network: &Network, samples: usize) {
        self.samples = samples;
        if self.capacity >= samples && self.activations.len() == network.layers.len() {
            let fits = network
                .layers
                .iter()
                .zip(&self.activations)
                .all(|(l, a)| a.len() >= l.outputs * samples);
            if fits {
                self.widths.clear();
                self.widths.extend(network.layers.iter().map(|l| l.outputs));
                return;
            }
        }
        self.capacity = samples;
        self.activations = network
            .layers
            .iter()
            .map(|l| vec![0.0; l.outputs * samples])
            .collect();
        self.widths = network.layers.iter().map(|l| l.outputs).collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_tanh_matches_libm() {
        for i in -4000..=4000 {
            let z = i as f64 * 0.005;
            assert!((tanh(z) - elementary::tanh(z)).abs() < 5e-16, "{z}");
        }
        assert_eq!(tanh(800.0), 1.0);
        assert_eq!(tanh(-800.0), -1.0);
        assert!(tanh(f64::NAN).is_nan());
    }

    /// The workspace exposes each layer's activations of the last pass: tanh(W_1 x + b_1)
    /// for the hidden layer and the linear output, for exactly the pass's samples even
    /// when its buffers were sized for a larger batch before.
    #[test]
    fn workspace_holds_every_layer_of_the_last_forward_pass() {
        let network = Network::new(&[2, 3, 1], Activation::Tanh).unwrap();
        let params: Vec<f64> = (0..network.parameter_count())
            .map(|i| 0.1 * i as f64 - 0.6)
            .collect();
        let hidden = network.layers()[0];
        let output = network.layers()[1];
        let mut workspace = Workspace::default();
        network.forward(&params, &[0.0; 2 * 5], 5, &mut workspace);
        let inputs = [0.3, -0.8, 1.1, 0.4];
        let outputs = network
            .forward(&params, &inputs, 2, &mut workspace)
            .to_vec();
        assert_eq!(workspace.samples(), 2);
        assert_eq!(workspace.activations(0).len(), 3 * 2);
        assert_eq!(workspace.activations(1), outputs.as_slice());
        for (j, x) in inputs.chunks_exact(2).enumerate() {
            let mut z = params[output.biases];
            for i in 0..3 {
                let w = &params[hidden.weight_range()];
                let a = tanh(w[i] * x[0] + w[3 + i] * x[1] + params[hidden.biases + i]);
                assert!((workspace.activations(0)[3 * j + i] - a).abs() < 1e-15);
                z += params[output.weights + i] * a;
            }
            assert!((outputs[j] - z).abs() < 1e-14);
        }
    }
}
