//! A fully connected feed-forward network y = f(x) with one output, evaluated on whole
//! batches with matrix-matrix products, and the training objective with its gradient by
//! backpropagation.
//!
//! Layer l (1-based) maps a_{l-1} to z_l = W_l a_{l-1} + b_l; hidden layers apply the
//! activation, a_l = phi(z_l); the last layer is linear (regression output).
//!
//! All parameters live in one flat vector (what L-BFGS works on). Per layer, first W_l
//! (outputs x inputs, column-major), then b_l. A batch is a matrix with one column per
//! sample, so a layer is one product W_l A_{l-1} (nalgebra's gemm, which hands such
//! sizes to `matrixmultiply`); transposes are strided views, never copies.

use nalgebra::{DMatrixView, DMatrixViewMut};
use rand::Rng;
use serde::{Deserialize, Serialize};

use super::NeuralError;

/// Hidden-layer activation function.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Activation {
    /// tanh(z); the paper's choice.
    #[default]
    Tanh,
    /// 1 / (1 + exp(-z)).
    Sigmoid,
    /// max(0, z).
    Relu,
}

/// tanh(z) = 1 - 2 / (exp(2z) + 1): one `exp` instead of libm's `tanh` (6 ns against
/// 11 ns here, and a network evaluation needs hundreds). Absolute error within a few
/// 1e-16 of `f64::tanh` (tested), which is all a network needs (its outputs are
/// compared in absolute terms); saturates to exactly +-1 and propagates NaN.
#[inline]
pub fn tanh(z: f64) -> f64 {
    1.0 - 2.0 / ((2.0 * z).exp() + 1.0)
}

impl Activation {
    #[inline]
    pub fn apply(self, z: f64) -> f64 {
        match self {
            Activation::Tanh => tanh(z),
            Activation::Sigmoid => 1.0 / (1.0 + (-z).exp()),
            Activation::Relu => z.max(0.0),
        }
    }

    /// phi'(z) written in terms of a = phi(z), so the backward pass needs only the stored
    /// activations: tanh' = 1 - a^2, sigmoid' = a (1 - a), relu' = [a > 0].
    #[inline]
    pub fn derivative_from_output(self, a: f64) -> f64 {
        match self {
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

    pub fn name(self) -> &'static str {
        match self {
            Activation::Tanh => "tanh",
            Activation::Sigmoid => "sigmoid",
            Activation::Relu => "relu",
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

    /// Glorot (Xavier) uniform weights, W ~ U(-r, r) with r = sqrt(6 / (inputs + outputs)),
    /// and zero biases: MATLAB fitrnet's default initialisers.
    pub fn initial_parameters(&self, rng: &mut impl Rng) -> Vec<f64> {
        let mut params = vec![0.0; self.parameter_count()];
        for layer in &self.layers {
            let limit = (6.0 / (layer.inputs + layer.outputs) as f64).sqrt();
            for w in &mut params[layer.weight_range()] {
                *w = rng.gen_range(-limit..limit);
            }
        }
        params
    }

    /// Sum of squared weights (biases excluded), ||W||^2.
    pub fn squared_weight_norm(&self, params: &[f64]) -> f64 {
        self.layers
            .iter()
            .flat_map(|l| params[l.weight_range()].iter())
            .map(|w| w * w)
            .sum()
    }

    /// Forward pass of `samples` columns of `inputs` (inputs x samples, column-major);
    /// returns the outputs (one per sample), which live in `workspace`.
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

    /// Backward pass after `forward` on the same workspace. On entry the workspace's
    /// output delta holds dJ/dz_L per sample; writes dJ/dparams (data term only) into
    /// `gradient` (overwritten).
    fn backward(
        &self,
        params: &[f64],
        inputs: &[f64],
        samples: usize,
        workspace: &mut Workspace,
        gradient: &mut [f64],
    ) {
        for (l, layer) in self.layers.iter().enumerate().rev() {
            let input: &[f64] = if l == 0 {
                inputs
            } else {
                &workspace.activations[l - 1][..layer.inputs * samples]
            };
            let (lower, upper) = workspace.deltas.split_at_mut(l);
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
                let activation = self.activation;
                for (d, a) in below.iter_mut().zip(input) {
                    *d *= activation.derivative_from_output(*a);
                }
            }
        }
    }
}

/// Products with a dimension at or below this go through `small_gemm`: nalgebra 0.33
/// sends them to a gemv fallback that indexes past the buffer when A is a strided
/// (transposed) view (caught by debug assertions); above it, nalgebra calls
/// `matrixmultiply`, which honours any strides.
const SMALL_DIMENSION: usize = 5;

/// C = A B for column-major C (m x n); A (m x k) and B (k x n) are given by their buffers
/// and (row stride, column stride), so a transpose is just swapped strides.
fn gemm(
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

/// Buffers for one batch: activations and deltas of every layer, reused across calls.
#[derive(Clone, Debug, Default)]
pub struct Workspace {
    samples: usize,
    activations: Vec<Vec<f64>>,
    deltas: Vec<Vec<f64>>,
}

impl Workspace {
    fn ensure(&mut self, network: &Network, samples: usize) {
        if self.samples >= samples && self.activations.len() == network.layers.len() {
            let fits = network
                .layers
                .iter()
                .zip(&self.activations)
                .all(|(l, a)| a.len() >= l.outputs * samples);
            if fits {
                return;
            }
        }
        self.samples = samples;
        self.activations = network
            .layers
            .iter()
            .map(|l| vec![0.0; l.outputs * samples])
            .collect();
        self.deltas = self.activations.clone();
    }
}

/// One contiguous block of samples with its own buffers, so blocks run on separate
/// threads and their gradients are summed in a fixed order (deterministic results).
#[derive(Debug)]
struct Block {
    start: usize,
    len: usize,
    workspace: Workspace,
    gradient: Vec<f64>,
    squared_error: f64,
}

/// Training objective on standardised data (see `train` for how it relates to the
/// paper's and scikit-learn's definitions):
///
/// J(theta) = (1/n) sum_i (f(x_i; theta) - t_i)^2 + sum_l (penalty_l / 2) ||W_l||^2,
///
/// with x_i and t_i the standardised inputs and targets, ||W_l||^2 the squared weights of
/// layer l (biases are not penalised). Its gradient comes from backpropagation.
pub struct Objective<'a> {
    network: &'a Network,
    inputs: &'a [f64],
    targets: &'a [f64],
    penalties: Vec<f64>,
    blocks: Vec<Block>,
    /// (1/n) sum (f - t)^2 at the last evaluation (standardised units).
    pub last_mean_squared_error: f64,
}

/// Samples per block below which splitting the batch costs more than it saves.
const MIN_BLOCK: usize = 256;

impl<'a> Objective<'a> {
    /// `inputs`: standardised inputs, one column per sample; `targets`: standardised
    /// targets; `penalties`: one L2 coefficient per layer; `blocks`: how many blocks
    /// (threads) to split the batch into. The split changes the summation order, so a
    /// fixed `blocks` gives bit-identical results.
    pub fn new(
        network: &'a Network,
        inputs: &'a [f64],
        targets: &'a [f64],
        penalties: &[f64],
        blocks: usize,
    ) -> Result<Self, NeuralError> {
        let samples = targets.len();
        if penalties.len() != network.layers.len()
            || penalties.iter().any(|p| p.is_nan() || *p < 0.0)
        {
            return Err(NeuralError::InvalidInput(format!(
                "{} penalty coefficients (>= 0) for {} layers",
                penalties.len(),
                network.layers.len()
            )));
        }
        if samples == 0 || inputs.len() != samples * network.inputs() {
            return Err(NeuralError::InvalidInput(format!(
                "training data: {} input values for {samples} samples of {} features",
                inputs.len(),
                network.inputs()
            )));
        }
        let blocks = blocks.clamp(1, (samples / MIN_BLOCK).max(1));
        let per_block = samples.div_ceil(blocks);
        let blocks = (0..blocks)
            .map(|b| {
                let start = b * per_block;
                Block {
                    start,
                    len: per_block.min(samples - start.min(samples)),
                    workspace: Workspace::default(),
                    gradient: vec![0.0; network.parameter_count()],
                    squared_error: 0.0,
                }
            })
            .filter(|b| b.len > 0)
            .collect();
        Ok(Objective {
            network,
            inputs,
            targets,
            penalties: penalties.to_vec(),
            blocks,
            last_mean_squared_error: f64::NAN,
        })
    }

    pub fn dimension(&self) -> usize {
        self.network.parameter_count()
    }

    /// J(params); writes dJ/dparams into `gradient`.
    pub fn value_and_gradient(&mut self, params: &[f64], gradient: &mut [f64]) -> f64 {
        let network = self.network;
        let d = network.inputs();
        let n = self.targets.len();
        let inputs = self.inputs;
        let targets = self.targets;
        let run = |block: &mut Block| {
            let x = &inputs[block.start * d..(block.start + block.len) * d];
            let t = &targets[block.start..block.start + block.len];
            network.forward(params, x, block.len, &mut block.workspace);
            let last = network.layers.len() - 1;
            let mut squared_error = 0.0;
            let workspace = &mut block.workspace;
            let outputs = &workspace.activations[last][..block.len];
            let delta = &mut workspace.deltas[last];
            // Output layer is 1 wide: outputs and deltas are per-sample vectors.
            let scale = 2.0 / n as f64;
            for ((dz, f), t) in delta.iter_mut().zip(outputs.iter()).zip(t) {
                let r = f - t;
                squared_error += r * r;
                *dz = scale * r;
            }
            block.squared_error = squared_error;
            network.backward(
                params,
                x,
                block.len,
                &mut block.workspace,
                &mut block.gradient,
            );
        };
        if self.blocks.len() == 1 {
            run(&mut self.blocks[0]);
        } else {
            std::thread::scope(|scope| {
                let (first, rest) = self.blocks.split_at_mut(1);
                let run = &run;
                let handles: Vec<_> = rest
                    .iter_mut()
                    .map(|block| scope.spawn(move || run(block)))
                    .collect();
                run(&mut first[0]);
                for handle in handles {
                    // A panic in a worker is a bug in this module; re-raise it here.
                    if let Err(payload) = handle.join() {
                        std::panic::resume_unwind(payload);
                    }
                }
            });
        }
        gradient.copy_from_slice(&self.blocks[0].gradient);
        let mut squared_error = self.blocks[0].squared_error;
        for block in &self.blocks[1..] {
            for (g, b) in gradient.iter_mut().zip(&block.gradient) {
                *g += b;
            }
            squared_error += block.squared_error;
        }
        let mean_squared_error = squared_error / n as f64;
        self.last_mean_squared_error = mean_squared_error;
        let mut penalty_term = 0.0;
        for (layer, &penalty) in network.layers().iter().zip(&self.penalties) {
            let mut weight_norm = 0.0;
            for i in layer.weight_range() {
                weight_norm += params[i] * params[i];
                gradient[i] += penalty * params[i];
            }
            penalty_term += 0.5 * penalty * weight_norm;
        }
        mean_squared_error + penalty_term
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    fn problem(samples: usize) -> (Network, Vec<f64>, Vec<f64>, Vec<f64>) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let network = Network::new(&[2, 7, 5, 1], Activation::Tanh).unwrap();
        let params = network.initial_parameters(&mut rng);
        let inputs: Vec<f64> = (0..2 * samples).map(|_| rng.gen_range(-2.0..2.0)).collect();
        let targets: Vec<f64> = (0..samples).map(|_| rng.gen_range(-1.0..1.0)).collect();
        (network, params, inputs, targets)
    }

    fn check_gradient(activation: Activation, blocks: usize) {
        let (mut network, mut params, inputs, targets) = problem(600);
        network.activation = activation;
        // Non-zero biases so that every term of the gradient is exercised.
        for (i, p) in params.iter_mut().enumerate() {
            *p += 0.01 * ((i % 7) as f64 - 3.0);
        }
        let mut objective =
            Objective::new(&network, &inputs, &targets, &[0.03, 0.05, 0.07], blocks).unwrap();
        let mut gradient = vec![0.0; params.len()];
        objective.value_and_gradient(&params, &mut gradient);
        let mut scratch = vec![0.0; params.len()];
        for i in 0..params.len() {
            let h = 1e-6;
            let mut plus = params.clone();
            plus[i] += h;
            let mut minus = params.clone();
            minus[i] -= h;
            let numeric = (objective.value_and_gradient(&plus, &mut scratch)
                - objective.value_and_gradient(&minus, &mut scratch))
                / (2.0 * h);
            let tolerance = 1e-7 + 1e-5 * numeric.abs();
            assert!(
                (gradient[i] - numeric).abs() < tolerance,
                "{activation:?} parameter {i}: backprop {} vs finite difference {numeric}",
                gradient[i]
            );
        }
    }

    #[test]
    fn backpropagation_matches_central_differences() {
        check_gradient(Activation::Tanh, 1);
        check_gradient(Activation::Sigmoid, 1);
        // Two blocks on two threads must give the same gradient.
        check_gradient(Activation::Tanh, 2);
    }

    #[test]
    fn fast_tanh_matches_libm() {
        for i in -4000..=4000 {
            let z = i as f64 * 0.005;
            assert!((tanh(z) - z.tanh()).abs() < 5e-16, "{z}");
        }
        assert_eq!(tanh(800.0), 1.0);
        assert_eq!(tanh(-800.0), -1.0);
        assert!(tanh(f64::NAN).is_nan());
    }

    #[test]
    fn relu_gradient_matches_away_from_kinks() {
        // Finite differences across a kink of relu are meaningless; with random data a
        // kink lies within 1e-6 of a pre-activation with negligible probability.
        check_gradient(Activation::Relu, 1);
    }

    #[test]
    fn objective_value_is_mse_plus_half_penalty_norm() {
        let (network, params, inputs, targets) = problem(50);
        let mut objective = Objective::new(&network, &inputs, &targets, &[0.5; 3], 1).unwrap();
        let mut gradient = vec![0.0; params.len()];
        let value = objective.value_and_gradient(&params, &mut gradient);
        let mut workspace = Workspace::default();
        let outputs = network
            .forward(&params, &inputs, 50, &mut workspace)
            .to_vec();
        let mse = outputs
            .iter()
            .zip(&targets)
            .map(|(f, t)| (f - t).powi(2))
            .sum::<f64>()
            / 50.0;
        let expected = mse + 0.25 * network.squared_weight_norm(&params);
        assert!((value - expected).abs() < 1e-12 * expected.abs().max(1.0));
    }
}
