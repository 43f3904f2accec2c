//! Reading a network from ONNX (issue 23), in pure Rust: a protobuf reader of the ONNX
//! schema (`wire`, `model`) and a graph-to-layers converter (`convert`), no runtime
//! library.
//!
//! [`read_onnx`] turns the bytes of a `.onnx` file into an [`OnnxNetwork`]: input
//! normalisation, dense layers with one hidden activation, output scaling, the graph's
//! input and output names, its producer and `metadata_props`. What the inputs are and
//! the range they were trained on is not ONNX's to say: the physics reads that from the
//! metadata (`stickslip::neural::onnx`).
//!
//! # What is accepted
//! A multilayer perceptron regressor as `torch.onnx.export` writes one (Gemm with
//! transB = 1), as Keras via tf2onnx (MatMul + Add) and as skl2onnx (`Scaler` in f32 or
//! `Sub`/`Div` in f64, MatMul + Add, an activation), in FLOAT or DOUBLE: one graph input
//! [batch, features], one output [batch, 1], and between them one chain of nodes (see
//! `convert` for the operators and their order). IR versions 3 to 14; each operator is
//! judged by the version the model's opset gives it (`convert::OPERATORS`: Add, Sub, Mul,
//! Div and Gemm from version 7, where they broadcast like numpy; opsets up to `ai.onnx` 28
//! and `ai.onnx.ml` 5, onnx 1.23, checked; `convert::opset` says why). Everything else is refused with an [`OnnxError`] naming the node (name and
//! operator type), attribute, tensor, data type, shapes, or operator version and opset at fault.
//!
//! # Precision
//! A DOUBLE graph in the common forms is read bit for bit (the same numbers as the
//! network it was exported from). A FLOAT graph's weights are widened exactly, so the
//! network is exactly the f32-rounded one, in f64; evaluated in f64 it differs from an
//! f32 runtime by that runtime's own rounding (a few 1e-7 relative).
//! [`OnnxNetwork::precision`] says which.
//!
//! # Safety of the reader
//! The reader never panics and allocates in proportion to the input (see `wire`).

pub mod convert;
mod error;
pub mod model;
pub mod wire;

pub use convert::{Activation, DenseLayer, OnnxNetwork, Precision};
pub use error::OnnxError;

use model::ModelProto;

/// Decodes and converts the bytes of an ONNX file; `source_name` appears in errors.
pub fn read_onnx(bytes: &[u8], source_name: &str) -> Result<OnnxNetwork, OnnxError> {
    let model = ModelProto::decode(bytes).map_err(|e| OnnxError::Wire {
        source_name: source_name.to_string(),
        context: e.context,
        reason: e.error.to_string(),
    })?;
    convert::convert(&model, source_name)
}
