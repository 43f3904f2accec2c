//! The command line's one error type: its own cases (flags that do not go together, flag
//! values, output files) and the errors of the physics and the trainer, whose messages
//! it passes on unchanged. `main` prints it as `error: {e}`.

use std::path::PathBuf;
use stickslip::auto::AutoError;
use stickslip::files::{InputFileError, OutputFileError};
use stickslip::neural::NeuralError;
use stickslip::run::RunError;
use stickslip::scene::SceneError;
use stickslip::structure::ModelError;
use stickslip::study::{Failed, StudyError};
use stickslip_train::TrainError;

/// Why a command failed.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    #[error("--tolerance applies to --fidelity auto only")]
    ToleranceWithoutAuto,
    /// A flag whose value `fidelity = auto` chooses.
    #[error("{flag} is chosen by {by}; leave it out")]
    ChosenByAuto {
        flag: &'static str,
        by: &'static str,
    },
    /// `--damping-ratio` is negative or not finite.
    #[error("--damping-ratio = {0}; it must be finite and >= 0")]
    DampingRatio(f64),
    /// `--rayleigh-ratio` is negative or not finite.
    #[error("--rayleigh-ratio = {0}; it must be finite and >= 0")]
    RayleighRatio(f64),
    /// `static --convergence` (or `--out`) of a scene with a `[structure]`.
    #[error("static --convergence (and its --out) is the built-in beam's mesh study; a [structure] has its own mesh: run `stickslip static --scene FILE` for its contact deflection and sensors, or `stickslip estimates --scene FILE` for its modes and contact compliance")]
    ConvergenceWithStructure,
    /// `--load` (N) is zero or not finite.
    #[error("--load = {0}; it must be finite and non-zero")]
    Load(f64),
    /// `study` was given no resolution or no time step.
    #[error("the grid is empty: give at least one resolution and one time step")]
    EmptyGrid,
    #[error("--features and --target select columns of --data; give --data FILE.csv")]
    ColumnsWithoutData,
    #[error("--data needs --target NAME (the force column)")]
    DataWithoutTarget,
    #[error("--data needs --features A,B,... (the input columns)")]
    DataWithoutFeatures,
    /// A `[structure]` sensor whose CSV column would repeat one `simulate --out` writes.
    #[error("structure.sensors: the sensor output {0} is also a column of the CSV that --out writes (t, tip_deflection, tip_velocity, friction_force, stick and the law's state); rename the sensor")]
    SensorNamesAColumn(String),

    /// An output file: nothing was put in its place (`stickslip::files`). Checked before
    /// training too, so that minutes of training are not lost at the end.
    #[error(transparent)]
    Output(#[from] OutputFileError),
    /// An output folder of `study` or `train --export-data` that could not be created.
    #[error("cannot create the folder {}: {source}", path.display())]
    Folder {
        path: PathBuf,
        source: std::io::Error,
    },
    /// `export-fmu` (its messages name the flag or file).
    #[error(transparent)]
    Export(#[from] fmu_build::export::ExportError),
    /// An input file (`stickslip::files` names the path and the reason).
    #[error(transparent)]
    File(#[from] InputFileError),
    /// A step after some outputs were written, complete, on purpose (`study`'s table and
    /// fronts before `--verify-auto`): says which, so that no one takes them for a
    /// failed run's leftovers.
    #[error("{source} (written before it failed, complete: {})", .written.join(", "))]
    AfterWritten {
        written: Vec<String>,
        source: Box<CliError>,
    },
    /// A summary, report or table that could not be put into JSON.
    #[error("{path}: {source}")]
    Json {
        path: PathBuf,
        source: serde_json::Error,
    },

    /// `import-network` was given a MATLAB .mat file: the Python package converts it
    /// (MCOS opaque data, undocumented; see docs/decisions.md).
    #[error(
        "{}: a MATLAB .mat file (a fitrnet RegressionNeuralNetwork) is converted by the \
         Python package python-checks, not by this command (MATLAB stores the network as \
         MCOS opaque data, an undocumented format that the pip package mat-io reads). Run \
         (after `bash scripts/python-env.sh`, which creates .venv):\n  .venv/bin/python -m \
         stickslip_checks.import_fitrnet {} --out {} --weights-out {}\nwhich writes the \
         network as ONNX and runs `stickslip import-network` on it",
        path.display(),
        path.display(),
        out.with_extension("onnx").display(),
        out.display()
    )]
    MatFile { path: PathBuf, out: PathBuf },
    /// `study` could not run: a law refused, or a law's reference run failed, so that
    /// nothing of that law can be compared with it. (Boxed to keep `Result<(),
    /// CliError>` small.)
    #[error(transparent)]
    Study(Box<StudyError>),
    /// `study --write-front` writes the scene law's front, which `--laws` leaves out.
    #[error("--write-front writes the front of the scene's law ({law}), which --laws leaves out")]
    WriteFrontWithoutSceneLaw { law: String },
    /// The reference run of a `study --verify-auto` scene failed.
    #[error("{scene}: the reference failed: {}", .source.reason)]
    VerificationReference {
        scene: &'static str,
        source: Box<Failed>,
    },

    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Auto(#[from] AutoError),
    #[error(transparent)]
    Model(#[from] ModelError),
    #[error(transparent)]
    Run(#[from] RunError),
    /// Writing the trained model's weights file; reading and importing an ONNX network.
    #[error(transparent)]
    Neural(#[from] NeuralError),
    #[error(transparent)]
    Train(#[from] TrainError),
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Files kept on purpose are listed after the reason, so that no one takes them for
    /// a failed run's leftovers (`study --verify-auto`).
    #[test]
    fn a_failure_after_writing_lists_what_was_written() {
        let error = CliError::AfterWritten {
            written: vec!["out/study.csv".into(), "out/front.json".into()],
            source: Box::new(CliError::EmptyGrid),
        };
        assert_eq!(
            error.to_string(),
            "the grid is empty: give at least one resolution and one time step \
             (written before it failed, complete: out/study.csv, out/front.json)"
        );
    }
}
