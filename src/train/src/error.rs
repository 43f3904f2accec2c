//! The trainer's one error type: data (synthetic or CSV), settings, training.

use stickslip::files::{InputFileError, OutputFileError};
use stickslip::neural::NeuralError;

/// Everything that can go wrong in training. Every variant names what was being read or
/// checked, so the message alone tells the user what to fix; nothing in the trainer
/// panics on bad input. Errors of the network and the weights files come from the
/// physics crate's [`NeuralError`] and keep their message.
#[derive(Debug, thiserror::Error)]
pub enum TrainError {
    /// A data or records file that cannot be read (`stickslip::files` names the path and
    /// the reason).
    #[error(transparent)]
    File(#[from] InputFileError),

    /// An output file that could not be written; nothing was put in its place.
    #[error(transparent)]
    Output(#[from] OutputFileError),

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
    fn a_missing_file_is_named_once() {
        let e =
            read_csv_file(std::path::Path::new("/nonexistent/m.csv"), &selection()).unwrap_err();
        assert_eq!(e.to_string(), "data file /nonexistent/m.csv: no such file");
        assert!(
            matches!(
                &e,
                TrainError::File(f) if matches!(f.problem, stickslip::files::InputProblem::Missing)
            ),
            "{e:?}"
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
