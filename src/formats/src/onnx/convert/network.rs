//! The converted network, as plain data: a chain of dense layers.

/// The precision the ONNX graph computes in: f32 when any weight, the input or a Cast
/// is FLOAT, else f64. The network is read into f64 either way; an f32 graph agrees
/// with it to f32 rounding (see the module documentation of `onnx`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    F32,
    F64,
}

/// The activation of the hidden layers, as the ONNX operator names it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Activation {
    /// `Tanh`: tanh(z).
    #[default]
    Tanh,
    /// `Sigmoid`: 1 / (1 + exp(-z)).
    Sigmoid,
    /// `Relu`: max(0, z).
    Relu,
}

/// One dense layer, z = W a + b: `weights[o][i]` connects input i to output o.
#[derive(Clone, Debug, PartialEq)]
pub struct DenseLayer {
    pub weights: Vec<Vec<f64>>,
    pub biases: Vec<f64>,
}

/// The network an ONNX graph holds: network input k is
/// (x_k - input_mean[k]) / input_std[k], the layers `layers` with `activation` on every
/// hidden layer and none on the last, and the output is output_mean + output_std * z.
#[derive(Clone, Debug, PartialEq)]
pub struct OnnxNetwork {
    pub precision: Precision,
    /// Name of the graph input and output.
    pub input_name: String,
    pub output_name: String,
    pub input_mean: Vec<f64>,
    /// Positive.
    pub input_std: Vec<f64>,
    pub layers: Vec<DenseLayer>,
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
