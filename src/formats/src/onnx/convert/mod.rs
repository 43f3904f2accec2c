//! A decoded ONNX graph to a chain of dense layers: input normalisation, layers with one
//! hidden activation, output scaling (`OnnxNetwork`).
//!
//! The graph must be one chain from its one input to its one output; each node on it
//! reads the running value plus constants (initializers or `Constant` nodes). The chain
//! is read as
//!
//! ```text
//! [normalisation] Dense (Activation Dense)* [output scaling]
//! ```
//!
//! where a Dense is `Gemm` or `MatMul` (+ `Add` of the bias), the normalisation is any
//! sequence of `Sub`/`Div`/`Mul`/`Add` by per-feature or scalar constants and
//! `ai.onnx.ml` `Scaler`, the output scaling any sequence of those by scalars, and
//! `Identity`, `Cast` (between FLOAT and DOUBLE), `Flatten` (axis 1) and `Reshape` (to
//! [-1, width] or [0, width]) may stand anywhere as no-ops. Everything else is refused.
//!
//! # Rounding
//! The common exports map exactly, so that an f64 network is imported bit for bit:
//! `Sub(mean)` then `Div(std)` gives `input_mean = mean`, `input_std = std`; `Mul(s)` then
//! `Add(m)` at the output gives `output_std = s`, `output_mean = m`; Gemm with alpha =
//! beta = 1 and MatMul give the weights as stored (transposed as needed). Other forms
//! are folded with a rounding per constant: `Scaler`'s scale (and `Mul` at the input)
//! becomes std = 1 / scale, Gemm's alpha and beta multiply B and C, an `Add` before a
//! `Mul` at the output is moved behind it. A negative scale at the input or output is
//! moved into the adjacent layer's weights by negation, which is exact.
//!
//! # Parts
//! `opset` checks the IR version and each operator's version under the model's opsets, `chain` follows the graph from input to
//! output node by node, `node` reads each operator, `tensors` reads the constants,
//! `layers` assembles dense layers and collects the scalings, `fold` folds the
//! scalings into the normalisation and checks the result (`network`).

mod chain;
mod fold;
mod layers;
pub mod network;
mod node;
pub mod opset;
mod tensors;

pub use network::{Activation, DenseLayer, OnnxNetwork, Precision};
pub use opset::{CheckedOpsets, OperatorHistory, CHECKED_OPSETS, IR_VERSIONS, OPERATORS};

use super::error::OnnxError;
use super::model::ModelProto;
use chain::Converter;

/// The ai.onnx operators that carry state from one evaluation (or sequence element) to
/// the next: a graph with one is a law with memory, whatever else it holds.
const RECURRENT_OPERATORS: [&str; 5] = ["RNN", "GRU", "LSTM", "Loop", "Scan"];

/// Converts a decoded model; `source_name` appears in errors.
pub fn convert(model: &ModelProto, source_name: &str) -> Result<OnnxNetwork, OnnxError> {
    let graph = opset::checked_graph(model, source_name)?;
    // Before the chain is followed: a recurrent graph has several outputs and state
    // inputs, which the chain would refuse for a reason that hides the real one.
    if let Some((index, node)) = graph.node.iter().enumerate().find(|(_, node)| {
        opset::domain_of(&node.domain) == Some(false)
            && RECURRENT_OPERATORS.contains(&node.op_type.as_str())
    }) {
        return Err(OnnxError::Recurrent {
            source_name: source_name.to_string(),
            node: if node.name.is_empty() {
                format!("#{index}")
            } else {
                format!("'{}'", node.name)
            },
            op_type: node.op_type.clone(),
        });
    }
    let producer = format!("{} {}", model.producer_name, model.producer_version)
        .trim()
        .to_string();
    Converter::new(graph, source_name)?.run(producer, model.metadata_props.clone())
}
