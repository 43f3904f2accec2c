//! The trainer's one error type: data (synthetic or CSV), settings, training.

use std::path::PathBuf;
use stickslip::neural::NeuralError;

/// Everything that can go wrong in training. Every variant names what was being read or
/// checked, so the message alone tells the user what to fix; nothing in the trainer
/// panics on bad input. Errors of the network and the weights files come from the
/// physics crate's [`NeuralError`] and keep their message.
#[derive(Debug, thiserror::Error)]
pub enum TrainError {
    /// A file could not be read or written.
    #[error("{action} '{path}': {source}")]
    Io {
        action: &'static str,
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },

    /// A CSV file is malformed; `line` is 1-based as shown by an editor.
    #[error("{source_name}, line {line}: {message}")]
    Csv {
        source_name: String,
        line: usize,
        message: String,
    },

    /// Training data or settings are unusable (too few samples, bad option values...).
    #[error("{0}")]
    InvalidInput(String),

    /// A distribution of the synthetic data could not be built from its settings.
    #[error("{quantity} distribution: {source}")]
    Distribution {
        quantity: &'static str,
        #[source]
        source: rand_distr::NormalError,
    },

    /// The optimiser produced a non-finite loss at its starting point, or a fold of the
    /// search was not trained.
    #[error("training failed: {0}")]
    Training(String),

    /// The network, the model or its weights file.
    #[error(transparent)]
    Neural(#[from] NeuralError),
}

impl TrainError {
    pub fn io(action: &'static str, path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        TrainError::Io {
            action,
            path: path.into(),
            source,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::csv::{parse_csv, read_csv_file, ColumnSelection};
    use std::error::Error;
    use stickslip::neural::network::Network;
    use stickslip::neural::Activation;

    fn selection() -> ColumnSelection {
        ColumnSelection {
            features: vec!["v".into(), "Fn".into()],
            target: "F".into(),
            sliding_velocity: None,
            normal_force: None,
        }
    }

    #[test]
    fn a_missing_file_names_the_path_and_keeps_the_io_error() {
        let e =
            read_csv_file(std::path::Path::new("/nonexistent/m.csv"), &selection()).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("cannot read '/nonexistent/m.csv': "),
            "{e}"
        );
        let io = e.source().and_then(|s| s.downcast_ref::<std::io::Error>());
        assert_eq!(
            io.map(std::io::Error::kind),
            Some(std::io::ErrorKind::NotFound)
        );
    }

    #[test]
    fn a_malformed_line_is_named() {
        let e = parse_csv("v,Fn,F\n0.1,100,20\n0.2,100\n", "m.csv", &selection()).unwrap_err();
        assert!(matches!(e, TrainError::Csv { line: 3, .. }), "{e:?}");
        assert_eq!(
            e.to_string(),
            "m.csv, line 3: 2 field(s), but the header has 3 columns"
        );
    }

    #[test]
    fn network_errors_keep_their_message() {
        let neural = Network::new(&[2], Activation::Tanh).unwrap_err();
        let message = neural.to_string();
        let e = TrainError::from(neural);
        assert!(matches!(
            e,
            TrainError::Neural(NeuralError::InvalidInput(_))
        ));
        assert_eq!(e.to_string(), message);
        let e = TrainError::Distribution {
            quantity: "noise",
            source: rand_distr::NormalError::BadVariance,
        };
        assert_eq!(
            e.to_string(),
            "noise distribution: variation parameter is non-finite in (log)normal distribution"
        );
        assert!(e.source().is_some());
    }
}
