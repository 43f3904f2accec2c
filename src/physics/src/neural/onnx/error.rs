//! `OnnxImportError`: why an ONNX file did not become a `NeuralModel`, naming the
//! culprit.

use super::super::error::NeuralError;
use stickslip_formats::onnx::OnnxError;

/// Why an ONNX model could not be imported: the file could not be read into a dense
/// chain (`stickslip_formats::onnx`, whose message is kept word for word), or the chain
/// is not described or not bounded as a friction law needs.
#[derive(Debug, thiserror::Error)]
pub enum OnnxImportError {
    /// The reader's refusal (bytes, graph, operators, tensors, structure).
    #[error(transparent)]
    Read(#[from] OnnxError),

    /// Feature or target description (metadata or `OnnxImport`) missing or invalid.
    #[error("{source_name}: {message}")]
    Description {
        source_name: String,
        message: String,
    },

    /// The network can overflow f64 within the training range.
    #[error("{source_name}: the network's output is not bounded by a finite number over the training range (interval bound {bound:e}): weights too large")]
    Overflow { source_name: String, bound: f64 },

    /// The assembled model failed `NeuralModel::validate`.
    #[error("{0}")]
    Model(#[from] NeuralError),
}

/// An import failure as a neural error: a model that failed validation is that error
/// itself, anything else the import's reason (`NeuralError::Onnx`).
impl From<OnnxImportError> for NeuralError {
    fn from(error: OnnxImportError) -> Self {
        match error {
            OnnxImportError::Model(inner) => inner,
            other => NeuralError::Onnx(Box::new(other)),
        }
    }
}

/// The reader's refusal as a neural error, held as an [`OnnxImportError`] like every
/// other import failure (so that one downcast reads them all).
impl From<OnnxError> for NeuralError {
    fn from(error: OnnxError) -> Self {
        OnnxImportError::Read(error).into()
    }
}
