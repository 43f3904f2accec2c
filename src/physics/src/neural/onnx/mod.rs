//! Importing a friction network from ONNX (issue 23): the dense chain that
//! `stickslip_formats::onnx::read_onnx` reads from the file (PyTorch, Keras,
//! scikit-learn exports; what is accepted and refused is documented there) becomes our
//! [`NeuralModel`], with feature names, roles and training ranges from the file's
//! metadata or the caller's [`OnnxImport`]; `NeuralLaw::new` takes it from there.
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
//! The imported model evaluates in f64: a DOUBLE graph in the common forms bit for bit,
//! a FLOAT graph as exactly the f32-rounded network (`OnnxNetwork::precision` says
//! which); `NeuralLaw::in_f32` evaluates in f32 when that is wanted.
//!
//! # Safety
//! The reader never panics and allocates in proportion to the input; an accepted
//! model's output is bounded over its training range by interval arithmetic (else
//! [`OnnxImportError::Overflow`]), so it evaluates to finite numbers on finite inputs
//! (inputs are clamped to the range).

pub mod describe;
mod error;

pub use describe::{FeatureInfo, OnnxImport, TargetInfo, FEATURES_KEY, TARGET_KEY, VARIANT_KEY};
pub use error::OnnxImportError;

use super::weights::NeuralModel;
use stickslip_formats::onnx::read_onnx;

/// The bytes of an ONNX file as our checked `NeuralModel`, described by `options` and
/// the file's metadata (`options.source_name` appears in errors).
pub fn import_onnx(bytes: &[u8], options: &OnnxImport) -> Result<NeuralModel, OnnxImportError> {
    let network = read_onnx(bytes, &options.source_name)?;
    describe::neural_model(&network, options)
}

/// Reads an ONNX file and imports it (`options.source_name` is replaced by the path
/// when empty).
pub fn load_onnx(
    path: &std::path::Path,
    options: &OnnxImport,
) -> Result<NeuralModel, OnnxImportError> {
    let bytes = crate::files::WEIGHTS_FILE
        .read(path)
        .map_err(|e| OnnxImportError::Model(e.into()))?;
    let mut options = options.clone();
    if options.source_name.is_empty() {
        options.source_name = path.display().to_string();
    }
    import_onnx(&bytes, &options)
}
