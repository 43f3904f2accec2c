//! The one error type of the neural friction law: networks, weights files, inference.
//! (Training data and training have their own, `stickslip_train::TrainError`.)

use crate::files::{InputFileError, OutputFileError};
use std::path::{Path, PathBuf};

/// Everything that can go wrong in `neural`. Every variant names what was being read or
/// checked, so the message alone tells the user what to fix; nothing in `neural` panics
/// on bad input.
#[derive(Debug, thiserror::Error)]
pub enum NeuralError {
    /// A weights file that cannot be read (missing, a directory, a device, empty, too
    /// large, not UTF-8): `crate::files` names the path and the reason.
    /// (Boxed, as `Output`, to keep `NeuralError` small: it travels in many results.)
    #[error(transparent)]
    File(Box<InputFileError>),

    /// A weights file that could not be written; nothing was put in its place.
    #[error(transparent)]
    Output(Box<OutputFileError>),

    /// A weights file that parsed but whose network cannot serve, for a reason that does
    /// not name the file (the law's own checks): the path, once.
    #[error("weights file {}: {source}", path.display())]
    InFile {
        path: PathBuf,
        source: Box<NeuralError>,
    },

    /// A weights file is not valid JSON or does not have the expected fields
    /// (truncated files end up here; serde_json reports line and column).
    #[error("weights file {source_name}: not a valid model description: {message}")]
    Json {
        source_name: String,
        message: String,
    },

    /// The file is JSON but not one of ours.
    #[error("weights file {source_name}: format is '{found}', expected '{expected}'")]
    Format {
        source_name: String,
        found: String,
        expected: &'static str,
    },

    /// The file is ours but written by an incompatible version.
    #[error("weights file {source_name}: format version {found} is not supported (this build reads version {supported})")]
    Version {
        source_name: String,
        found: u32,
        supported: u32,
    },

    /// Layer sizes, weight matrices, feature lists or statistics disagree.
    #[error("weights file {source_name}: inconsistent model: {message}")]
    Shape {
        source_name: String,
        message: String,
    },

    /// A number in the model is NaN or infinite (`field` says which one).
    #[error("weights file {source_name}: {field} is not a finite number")]
    NonFinite { source_name: String, field: String },

    /// `evaluate` got a different number of inputs than the model has features.
    #[error("the model expects {expected} input(s) ({names}), got {got}")]
    FeatureCount {
        expected: usize,
        got: usize,
        names: String,
    },

    /// An input to `evaluate` is NaN or infinite.
    #[error("input '{feature}' is {value}, which is not a finite number")]
    NonFiniteInput { feature: String, value: f64 },

    /// The model cannot act as a friction law of the beam (`FrictionLaw`).
    #[error("this model cannot be used as the beam's friction law: {0}")]
    NotAFrictionLaw(String),

    /// An inference option (`friction.inference`) cannot serve this model.
    #[error("friction.inference = {inference}: {reason}")]
    Inference {
        inference: &'static str,
        reason: String,
    },

    /// A network's layer sizes or a fixed feature value are unusable.
    #[error("{0}")]
    InvalidInput(String),

    /// An ONNX file given where weights are read (`NeuralLaw::from_file`) could not be
    /// imported; the reason names the node, tensor or metadata key at fault. It is an
    /// `onnx::OnnxImportError` (downcast to read it), held as a trait object because
    /// `OnnxImportError` holds a `NeuralError` and its module depends on this one.
    #[error("{0}")]
    Onnx(Box<dyn std::error::Error + Send + Sync>),

    /// A MATLAB MAT-file was given where weights are read. It is converted once, by the
    /// Python package (docs/command-line.md, "A MATLAB fitrnet network").
    #[error(
        "weights file {}: a MATLAB .mat file (a fitrnet network?), which is converted \
         once by the Python package python-checks, not read here: run `python -m \
         stickslip_checks.import_fitrnet {} --out NETWORK.onnx` and give the .onnx file \
         (docs/command-line.md, \"A MATLAB fitrnet network\")",
        path.display(),
        path.display()
    )]
    Matlab { path: PathBuf },
}

impl From<InputFileError> for NeuralError {
    fn from(error: InputFileError) -> Self {
        NeuralError::File(Box::new(error))
    }
}

impl From<OutputFileError> for NeuralError {
    fn from(error: OutputFileError) -> Self {
        NeuralError::Output(Box::new(error))
    }
}

impl NeuralError {
    /// Whether the message names the file it is about (every error of reading a file
    /// does; those of the law's checks and of evaluation do not).
    fn names_its_file(&self) -> bool {
        match self {
            NeuralError::File(_)
            | NeuralError::Output(_)
            | NeuralError::InFile { .. }
            | NeuralError::Json { .. }
            | NeuralError::Format { .. }
            | NeuralError::Version { .. }
            | NeuralError::Shape { .. }
            | NeuralError::NonFinite { .. }
            | NeuralError::Onnx(_)
            | NeuralError::Matlab { .. } => true,
            NeuralError::FeatureCount { .. }
            | NeuralError::NonFiniteInput { .. }
            | NeuralError::NotAFrictionLaw(_)
            | NeuralError::Inference { .. }
            | NeuralError::InvalidInput(_) => false,
        }
    }

    /// This error of reading `path`, naming it exactly once.
    pub fn in_file(self, path: &Path) -> NeuralError {
        if self.names_its_file() {
            self
        } else {
            NeuralError::InFile {
                path: path.to_path_buf(),
                source: Box::new(self),
            }
        }
    }
}
