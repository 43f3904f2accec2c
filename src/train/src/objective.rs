//! The training objective: mean squared error of the standardised network plus an L2
//! penalty, with its gradient by backpropagation (`crate::backprop`), evaluated on
//! blocks of samples in parallel with a fixed summation order.

use crate::backprop::Deltas;
use crate::error::TrainError;
use rand::Rng;
use stickslip::neural::network::{Network, Workspace};
#[cfg(test)]
use stickslip::neural::Activation;

/// Glorot (Xavier) uniform weights, W ~ U(-r, r) with r = sqrt(6 / (inputs + outputs)),
/// and zero biases: MATLAB fitrnet's default initialisers.
pub fn initial_parameters(network: &Network, rng: &mut impl Rng) -> Vec<f64> {
    let mut params = vec![0.0; network.parameter_count()];
    for layer in network.layers() {
        let limit = (6.0 / (layer.inputs + layer.outputs) as f64).sqrt();
        for w in &mut params[layer.weight_range()] {
            *w = rng.gen_range(-limit..limit);
        }
    }
    params
}

/// One contiguous block of samples with its own buffers, so blocks run on separate
/// threads and their gradients are summed in a fixed order (deterministic results).
#[derive(Debug)]
struct Block {
    start: usize,
    len: usize,
    workspace: Workspace,
    deltas: Deltas,
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
    ) -> Result<Self, TrainError> {
        let samples = targets.len();
        if penalties.len() != network.layers().len()
            || penalties.iter().any(|p| p.is_nan() || *p < 0.0)
        {
            return Err(TrainError::InvalidInput(format!(
                "{} penalty coefficients (>= 0) for {} layers",
                penalties.len(),
                network.layers().len()
            )));
        }
        if samples == 0 || inputs.len() != samples * network.inputs() {
            return Err(TrainError::InvalidInput(format!(
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
                    deltas: Deltas::default(),
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
            let outputs = network.forward(params, x, block.len, &mut block.workspace);
            let delta = block.deltas.output_mut(network, block.len);
            let mut squared_error = 0.0;
            // Output layer is 1 wide: outputs and deltas are per-sample vectors.
            let scale = 2.0 / n as f64;
            for ((dz, f), t) in delta.iter_mut().zip(outputs.iter()).zip(t) {
                let r = f - t;
                squared_error += r * r;
                *dz = scale * r;
            }
            block.squared_error = squared_error;
            block
                .deltas
                .backward(network, params, x, &block.workspace, &mut block.gradient);
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

    fn problem(samples: usize, activation: Activation) -> (Network, Vec<f64>, Vec<f64>, Vec<f64>) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let network = Network::new(&[2, 7, 5, 1], activation).unwrap();
        let params = initial_parameters(&network, &mut rng);
        let inputs: Vec<f64> = (0..2 * samples).map(|_| rng.gen_range(-2.0..2.0)).collect();
        let targets: Vec<f64> = (0..samples).map(|_| rng.gen_range(-1.0..1.0)).collect();
        (network, params, inputs, targets)
    }

    fn check_gradient(activation: Activation, blocks: usize) {
        let (network, mut params, inputs, targets) = problem(600, activation);
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
    fn relu_gradient_matches_away_from_kinks() {
        // Finite differences across a kink of relu are meaningless; with random data a
        // kink lies within 1e-6 of a pre-activation with negligible probability.
        check_gradient(Activation::Relu, 1);
    }

    #[test]
    fn objective_value_is_mse_plus_half_penalty_norm() {
        let (network, params, inputs, targets) = problem(50, Activation::Tanh);
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
        let squared_weight_norm: f64 = network
            .layers()
            .iter()
            .flat_map(|l| params[l.weight_range()].iter())
            .map(|w| w * w)
            .sum();
        let expected = mse + 0.25 * squared_weight_norm;
        assert!((value - expected).abs() < 1e-12 * expected.abs().max(1.0));
    }
}
