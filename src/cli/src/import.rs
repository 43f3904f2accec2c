//! `stickslip import-network`: an ONNX network (scikit-learn via skl2onnx, PyTorch via
//! `torch.onnx.export`, Keras via tf2onnx) as our weights file, described by the file's
//! metadata or by flags, and optionally checked against the user's data.
//!
//! A MATLAB `.mat` file (`fitrnet`) is refused with the Python command that converts it
//! (`python -m stickslip_checks.import_fitrnet`): MATLAB stores the network as MCOS
//! opaque data, an undocumented format that the pip package mat-io reads (see
//! docs/decisions.md).
//!
//! The reader is `stickslip_formats::onnx` and the import `stickslip::neural::onnx`;
//! this module only maps flags to [`OnnxImport`], writes the model and measures it on a
//! CSV file.

use std::path::PathBuf;

use nalgebra::DMatrix;

use crate::error::CliError;
use stickslip::choice::Choice;
use stickslip::files::WEIGHTS_FILE;
use stickslip::neural::onnx::{describe, FeatureInfo, OnnxImport, TargetInfo};
use stickslip::neural::{FeatureRole, NeuralError, NeuralLaw, NeuralModel, Variant};
use stickslip_formats::onnx::{read_onnx, OnnxNetwork, Precision};
use stickslip_formats::sniff::WeightsFileKind;
use stickslip_train::csv::{read_csv_file, ColumnSelection};
use stickslip_train::train::mse_and_r2;

/// `stickslip import-network`.
#[derive(clap::Args, Debug, Clone, PartialEq)]
pub struct ImportArgs {
    /// The ONNX file (a multilayer perceptron regressor, FLOAT or DOUBLE). A MATLAB
    /// `.mat` file is refused with the Python command that converts it.
    #[arg(value_name = "SOURCE.onnx")]
    pub source: PathBuf,
    /// Output weights file (JSON), readable wherever weights are (friction.weights, the
    /// FMUs' weights parameter).
    #[arg(long, value_name = "FILE.json")]
    pub out: PathBuf,
    /// One input column of the network, in column order; repeat once per column.
    /// ROLE: sliding_velocity, normal_force or other; UNIT may be empty; MIN and MAX are
    /// the training range (the law clamps inputs to it). Replaces the metadata key
    /// stickslip.features.
    #[arg(long = "feature", value_name = "NAME:ROLE:UNIT:MIN:MAX", value_parser = parse_feature)]
    pub features: Vec<FeatureInfo>,
    /// The network output: name, unit and range (range informational; 0:0 if unknown).
    /// Replaces stickslip.target; default friction_force in N.
    #[arg(long, value_name = "NAME:UNIT:MIN:MAX", value_parser = parse_target)]
    pub target: Option<TargetInfo>,
    /// plain: the output is the signed force; signed: the network takes |v| and gives
    /// the magnitude. Replaces stickslip.variant; default plain.
    #[arg(long, value_parser = crate::choice::parser::<Variant>())]
    pub variant: Option<Variant>,
    /// Evaluate the imported network on this CSV file (header `name[unit]`, as
    /// `train --data` reads): one column per feature and one for the target, named as
    /// the model names them. Prints MSE and R^2.
    #[arg(long, value_name = "FILE.csv")]
    pub check_data: Option<PathBuf>,
    /// A column of --check-data holding the exporting framework's own predictions:
    /// also prints the largest absolute and relative difference from them.
    #[arg(long, value_name = "NAME", requires = "check_data")]
    pub prediction_column: Option<String>,
}

/// `NAME:ROLE:UNIT:MIN:MAX`.
fn parse_feature(text: &str) -> Result<FeatureInfo, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let [name, role, unit, min, max] = parts[..] else {
        return Err(format!(
            "'{text}': expected NAME:ROLE:UNIT:MIN:MAX (5 fields separated by ':', UNIT may \
             be empty), got {} field(s)",
            parts.len()
        ));
    };
    let role = match role {
        "sliding_velocity" => FeatureRole::SlidingVelocity,
        "normal_force" => FeatureRole::NormalForce,
        "other" => FeatureRole::Other,
        _ => {
            return Err(format!(
                "'{text}': role '{role}' is not one of sliding_velocity, normal_force, other"
            ))
        }
    };
    Ok(FeatureInfo {
        name: field_name(name, text)?,
        unit: unit.to_string(),
        role,
        min: number(min, "MIN", text)?,
        max: number(max, "MAX", text)?,
    })
}

/// `NAME:UNIT:MIN:MAX`.
fn parse_target(text: &str) -> Result<TargetInfo, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let [name, unit, min, max] = parts[..] else {
        return Err(format!(
            "'{text}': expected NAME:UNIT:MIN:MAX (4 fields separated by ':'), got {} field(s)",
            parts.len()
        ));
    };
    Ok(TargetInfo {
        name: field_name(name, text)?,
        unit: unit.to_string(),
        min: number(min, "MIN", text)?,
        max: number(max, "MAX", text)?,
    })
}

fn field_name(name: &str, text: &str) -> Result<String, String> {
    if name.is_empty() {
        return Err(format!("'{text}': NAME is empty"));
    }
    Ok(name.to_string())
}

fn number(field: &str, what: &str, text: &str) -> Result<f64, String> {
    match field.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("'{text}': {what} '{field}' is not a finite number")),
    }
}

/// What `import-network` did, as it prints it (the tests read the numbers).
#[derive(Clone, Debug, PartialEq)]
pub struct ImportReport {
    pub model: NeuralModel,
    pub precision: Precision,
    pub producer: String,
    pub check: Option<DataCheck>,
}

/// The imported network on the user's data.
#[derive(Clone, Debug, PartialEq)]
pub struct DataCheck {
    pub samples: usize,
    pub mse: f64,
    pub r2: f64,
    /// Against the framework's predictions, when a column of them was named.
    pub agreement: Option<Agreement>,
}

/// Ours against the exporting framework's predictions p, over all rows.
#[derive(Clone, Debug, PartialEq)]
pub struct Agreement {
    /// max |ours - p| (target units).
    pub max_abs: f64,
    /// max |ours - p| / max |p|: relative to the largest predicted magnitude, because
    /// a friction force passes through zero (at v = 0), where a pointwise relative
    /// difference has no meaning.
    pub max_rel: f64,
}

/// Runs `import-network`: imports, checks `--check-data`, then writes `--out` (so that
/// a network that fails its check leaves no weights file), prints a summary.
pub fn run_import(args: &ImportArgs) -> Result<ImportReport, CliError> {
    let mat_file = || CliError::MatFile {
        path: args.source.clone(),
        out: args.out.clone(),
    };
    if WeightsFileKind::by_extension(&args.source) == Some(WeightsFileKind::Matlab) {
        return Err(mat_file());
    }
    let bytes = WEIGHTS_FILE.read(&args.source)?;
    if WeightsFileKind::of(&args.source, &bytes) == WeightsFileKind::Matlab {
        return Err(mat_file());
    }
    let source_name = args.source.display().to_string();
    let options = OnnxImport {
        source_name: source_name.clone(),
        features: (!args.features.is_empty()).then(|| args.features.clone()),
        target: args.target.clone(),
        variant: args.variant,
    };
    let network: OnnxNetwork = read_onnx(&bytes, &source_name).map_err(NeuralError::from)?;
    let model = describe::neural_model(&network, &options).map_err(NeuralError::from)?;
    // The law's own checks (roles a beam can use are not required: a network may be
    // imported for NeuralFriction or for study).
    let law = NeuralLaw::new(model.clone()).map_err(|e| e.in_file(&args.source))?;
    let check = match &args.check_data {
        Some(path) => Some(check_data(&law, path, args.prediction_column.as_deref())?),
        None => None,
    };
    model.save(&args.out)?;
    let report = ImportReport {
        model,
        precision: network.precision,
        producer: network.producer.clone(),
        check,
    };
    print_report(args, &report);
    Ok(report)
}

/// MSE and R^2 of `law` on the CSV file, and the agreement with its prediction column.
fn check_data(
    law: &NeuralLaw,
    path: &std::path::Path,
    prediction: Option<&str>,
) -> Result<DataCheck, CliError> {
    let model = law.model();
    let mut features: Vec<String> = model.features.iter().map(|f| f.name.clone()).collect();
    // The prediction column is read as one more feature row, after the model's.
    features.extend(prediction.map(str::to_string));
    let selection = ColumnSelection {
        features,
        target: model.target.name.clone(),
        sliding_velocity: None,
        normal_force: None,
    };
    let data = read_csv_file(path, &selection)?;
    let n = model.features.len();
    let inputs: DMatrix<f64> = data.inputs.rows(0, n).into_owned();
    let ours = law.evaluate_batch(&inputs)?;
    let (mse, r2) = mse_and_r2(&ours, &data.targets);
    let agreement = prediction.map(|_| {
        let theirs = data.inputs.row(n);
        let scale = theirs.iter().fold(0.0_f64, |m, p| m.max(p.abs()));
        let max_abs = ours
            .iter()
            .zip(theirs.iter())
            .fold(0.0_f64, |m, (a, p)| m.max((a - p).abs()));
        Agreement {
            max_abs,
            max_rel: if scale > 0.0 {
                max_abs / scale
            } else {
                max_abs
            },
        }
    });
    Ok(DataCheck {
        samples: data.len(),
        mse,
        r2,
        agreement,
    })
}

fn print_report(args: &ImportArgs, report: &ImportReport) {
    let model = &report.model;
    let features: Vec<String> = model
        .features
        .iter()
        .map(|f| {
            let role = serde_json::to_value(f.role)
                .ok()
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_default();
            format!("{} [{}] {role} {}..{}", f.name, f.unit, f.min, f.max)
        })
        .collect();
    let sizes: Vec<String> = model.layer_sizes.iter().map(usize::to_string).collect();
    println!(
        "imported {} ({}, {} weights): layers {} {}, variant {}",
        args.source.display(),
        report.producer,
        match report.precision {
            Precision::F32 => "float32",
            Precision::F64 => "float64",
        },
        sizes.join("-"),
        model.activation.name(),
        model.variant.name(),
    );
    println!("features: {}", features.join("; "));
    println!("target: {} [{}]", model.target.name, model.target.unit);
    println!("wrote {}", args.out.display());
    if let (Some(check), Some(path)) = (&report.check, &args.check_data) {
        println!(
            "check on {} ({} samples): MSE = {:.6e}, R^2 = {:.9}",
            path.display(),
            check.samples,
            check.mse,
            check.r2
        );
        if let (Some(a), Some(column)) = (&check.agreement, &args.prediction_column) {
            println!(
                "against column {column}: largest |difference| = {:.3e} {}, largest \
                 relative difference (to the largest |prediction|) = {:.3e}",
                a.max_abs, model.target.unit, a.max_rel
            );
        }
    }
}
