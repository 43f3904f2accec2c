//! The converted network, in our terms.

use super::super::super::network::Activation;
use super::super::super::weights::LayerWeights;

/// The precision the ONNX graph computes in: f32 when any weight, the input or a Cast
/// is FLOAT, else f64. The imported model evaluates in f64 either way; an f32 graph
/// agrees with it to f32 rounding (see the module documentation of `onnx`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    F32,
    F64,
}

/// The network an ONNX graph holds, in our terms: network input k is
/// (x_k - input_mean[k]) / input_std[k], the layers `weights[o][i]` as in the weights
/// file with `activation` on every hidden layer, and the output is
/// output_mean + output_std * z.
#[derive(Clone, Debug, PartialEq)]
pub struct OnnxNetwork {
    pub precision: Precision,
    /// Name of the graph input and output.
    pub input_name: String,
    pub output_name: String,
    pub input_mean: Vec<f64>,
    /// Positive.
    pub input_std: Vec<f64>,
    pub layers: Vec<LayerWeights>,
    /// The hidden layers' activation (Tanh when there is no hidden layer).
    pub activation: Activation,
    pub output_mean: f64,
    /// Positive.
    pub output_std: f64,
    /// "producer_name producer_version" of the file.
    pub producer: String,
    /// `metadata_props` of the file.
    pub metadata: Vec<(String, String)>,
}

impl OnnxNetwork {
    /// [inputs, hidden..., outputs].
    pub fn layer_sizes(&self) -> Vec<usize> {
        let mut sizes = vec![self.input_mean.len()];
        sizes.extend(self.layers.iter().map(|l| l.biases.len()));
        sizes
    }
}
