//! Importing a friction network from ONNX (issue 23), in pure Rust: a protobuf reader of
//! the ONNX schema (`wire`, `model`) and a graph-to-layers converter (`convert`), no
//! runtime library.
//!
//! [`read_onnx`] turns the bytes of a `.onnx` file into an [`OnnxNetwork`] (layers,
//! normalisation, output scaling); [`import_onnx`] goes on to our [`NeuralModel`], with
//! feature names, roles and training ranges from the file's metadata or the caller's
//! [`OnnxImport`]; `NeuralLaw::new` takes it from there.
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
//! # Metadata keys
//! ONNX holds the computation but not what the inputs are nor the range they were
//! trained on, which the law needs (it clamps inputs to that range). They are read
//! from `metadata_props` (an exporter sets them, e.g. `onnx_model.metadata_props`), each
//! replaced by the caller's [`OnnxImport`] field when that is set:
//! - `stickslip.features`: JSON array, one object per input column in order,
//!   `{"name": "v", "unit": "m/s", "role": "sliding_velocity", "min": -0.4, "max": 0.4}`
//!   (role: `sliding_velocity`, `normal_force` or `other`; unit optional). Required.
//! - `stickslip.target`: JSON `{"name": "F_f", "unit": "N", "min": -50, "max": 50}`
//!   (unit, min, max optional); default friction_force in N.
//! - `stickslip.variant`: `plain` (default: the output is the signed force) or `signed`
//!   (the network takes |v| and gives the magnitude; see `Variant`).
//!
//! Training notes and metrics have no ONNX counterpart; the model's `training` says it
//! was imported (file and producer), its counts and metrics are 0 (see
//! [`describe::neural_model`]).
//!
//! # Precision
//! The imported model evaluates in f64. A DOUBLE graph in the common forms is imported
//! bit for bit (the same numbers as the network it was exported from). A FLOAT graph's
//! weights are widened exactly, so the model is exactly the f32-rounded network,
//! evaluated in f64; it differs from an f32 runtime by that runtime's own rounding (a
//! few 1e-7 relative). [`OnnxNetwork::precision`] says which; `NeuralLaw::in_f32`
//! evaluates in f32 when that is wanted.
//!
//! # Safety of the reader
//! The reader never panics and allocates in proportion to the input (see `wire`); an
//! accepted model's output is bounded over its training range by interval arithmetic
//! (else [`OnnxError::Overflow`]), so it evaluates to finite numbers on finite inputs
//! (inputs are clamped to the range).

pub mod convert;
pub mod describe;
mod error;
pub mod model;
pub mod wire;

pub use convert::{OnnxNetwork, Precision};
pub use describe::{FeatureInfo, OnnxImport, TargetInfo, FEATURES_KEY, TARGET_KEY, VARIANT_KEY};
pub use error::OnnxError;

use super::weights::NeuralModel;
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

/// The bytes of an ONNX file as our checked `NeuralModel`, described by `options` and
/// the file's metadata (`options.source_name` appears in errors).
pub fn import_onnx(bytes: &[u8], options: &OnnxImport) -> Result<NeuralModel, OnnxError> {
    let network = read_onnx(bytes, &options.source_name)?;
    describe::neural_model(&network, options)
}

/// Reads an ONNX file and imports it (`options.source_name` is replaced by the path
/// when empty).
pub fn load_onnx(path: &std::path::Path, options: &OnnxImport) -> Result<NeuralModel, OnnxError> {
    let bytes = crate::files::WEIGHTS_FILE
        .read(path)
        .map_err(|e| OnnxError::Model(e.into()))?;
    let mut options = options.clone();
    if options.source_name.is_empty() {
        options.source_name = path.display().to_string();
    }
    import_onnx(&bytes, &options)
}
