//! The learned state law's weights file: self-describing JSON, versioned, with what the
//! law was trained on. Format `stickslip-state-friction`, version 1:
//!
//! ```text
//! { "format": "stickslip-state-friction", "version": 1,
//!   "law": { reference_coefficient, reference_velocity, direct_effect,
//!            evolution_effect, characteristic_slip,         // mu_0, V_0 m/s, a, b, D_c m
//!            state_evolution },                             // "aging" | "slip"
//!   "state": "psi = ln(theta V_0 / D_c), aging law, ...",   // words, for the reader
//!   "correction": null | { inputs: [state, normal_force], hidden_weights, ... },
//!   "ranges": { sliding_velocity: [min, max] m/s, normal_force: [min, max] N },
//!   "training": { data, series, samples, noise_std, lambda, iterations, ... },
//!   "metrics": { rms_error_train, rms_error_test } }         // N
//! ```
//!
//! `law.state_evolution` came with the slip law; a file without it is aging (the files
//! written before it, such as the shipped one, read unchanged), and a build from before
//! it refuses a file that has it as an unknown field rather than misreading it, so the
//! version stayed 1. A value other than "aging" or "slip" is refused with its line.
//!
//! Loading checks format and version first (so a foreign or newer file says so), then
//! every field, that every number is finite and that the parameters are in their
//! domains (a > 0, D_c > 0, V_0 > 0, the correction's shapes and scales), and returns a
//! `NeuralError` naming the field; it never panics.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::correction::Correction;
use super::evolution::StateEvolution;
use super::law::{LearnedStateLaw, StateLawParameters};
use crate::neural::file_checks::{
    check_header, finite, json_error, read_text, to_pretty_json, write_text,
};
use crate::neural::weights::StopReason;
use crate::neural::NeuralError;

/// Value of the file's `format` field.
pub const STATE_FORMAT_NAME: &str = "stickslip-state-friction";
/// Value of the file's `version` field that this build reads and writes.
pub const STATE_FORMAT_VERSION: u32 = 1;

/// What the state is, written into every file of the aging law for a reader without
/// this code.
pub const STATE_DEFINITION: &str = "psi = ln(theta V_0 / D_c); d theta/dt = 1 - |v| theta / D_c (aging law), stepped exactly for the speed at the step's end";
/// The same for the slip law.
pub const SLIP_STATE_DEFINITION: &str = "psi = ln(theta V_0 / D_c); d theta/dt = -(|v| theta / D_c) ln(|v| theta / D_c) (slip law; frozen at v = 0), stepped exactly for the speed at the step's end";

/// The words of the `state` field for `evolution`.
pub fn state_definition(evolution: StateEvolution) -> &'static str {
    match evolution {
        StateEvolution::Aging => STATE_DEFINITION,
        StateEvolution::Slip => SLIP_STATE_DEFINITION,
    }
}

/// The data ranges the law was trained on (inputs beyond them extrapolate).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrainingRanges {
    /// [min, max] of the sliding velocity (m/s).
    pub sliding_velocity: [f64; 2],
    /// [min, max] of the normal force (N).
    pub normal_force: [f64; 2],
}

/// How the law was trained.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateTrainingInfo {
    /// What the data were: the generating law and protocol, or the CSV file's name.
    pub data: String,
    /// Time series (velocity histories) used for training, and held out for testing.
    pub train_series: usize,
    pub test_series: usize,
    /// Samples over all training series.
    pub samples: usize,
    /// The additive force noise of synthetic data (N); 0 for measured data.
    pub noise_std: f64,
    pub seed: u64,
    /// Penalty on the correction's weights (lambda/2 ||w||^2 added to the mean squared
    /// error in N^2).
    pub lambda: f64,
    /// Words for the minimised objective.
    pub loss: String,
    pub iterations: usize,
    pub evaluations: usize,
    pub stop_reason: StopReason,
}

/// Root-mean-square force error (N) of the simulated series.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateMetrics {
    pub rms_error_train: f64,
    pub rms_error_test: f64,
}

/// The whole file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateLawFile {
    pub format: String,
    pub version: u32,
    pub law: StateLawParameters,
    pub state: String,
    pub correction: Option<Correction>,
    pub ranges: TrainingRanges,
    pub training: StateTrainingInfo,
    pub metrics: StateMetrics,
}

impl StateLawFile {
    /// A file for `law` with the given metadata (format and version of this build).
    pub fn new(
        law: &LearnedStateLaw,
        ranges: TrainingRanges,
        training: StateTrainingInfo,
        metrics: StateMetrics,
    ) -> Self {
        StateLawFile {
            format: STATE_FORMAT_NAME.into(),
            version: STATE_FORMAT_VERSION,
            law: law.parameters.clone(),
            state: state_definition(law.parameters.state_evolution).into(),
            correction: law.correction.clone(),
            ranges,
            training,
            metrics,
        }
    }

    /// The law the file holds.
    pub fn law(&self) -> LearnedStateLaw {
        LearnedStateLaw {
            parameters: self.law.clone(),
            correction: self.correction.clone(),
        }
    }

    /// Pretty JSON with a final newline (shortest round-trip numbers).
    pub fn to_json(&self) -> Result<String, NeuralError> {
        to_pretty_json(self)
    }

    pub fn save(&self, path: &Path) -> Result<(), NeuralError> {
        self.validate(&path.display().to_string())?;
        write_text(path, &self.to_json()?)
    }

    pub fn load(path: &Path) -> Result<StateLawFile, NeuralError> {
        Self::from_json(&read_text(path)?, &path.display().to_string())
    }

    /// Whether `text` claims to be a state-law file (its `format` field), so that a
    /// reader of weights can tell it from a memoryless network's.
    pub fn is_state_law(text: &str) -> bool {
        serde_json::from_str::<serde_json::Value>(text)
            .ok()
            .and_then(|v| {
                v.get("format")
                    .and_then(|f| f.as_str())
                    .map(|f| f == STATE_FORMAT_NAME)
            })
            .unwrap_or(false)
    }

    /// Parses and checks a file's text; `source_name` appears in errors.
    pub fn from_json(text: &str, source_name: &str) -> Result<StateLawFile, NeuralError> {
        check_header(text, source_name, STATE_FORMAT_NAME, STATE_FORMAT_VERSION)?;
        // Parsed from the text (not a Value) so that errors carry line and column.
        let file: StateLawFile =
            serde_json::from_str(text).map_err(|e| json_error(source_name, e))?;
        file.validate(source_name)?;
        Ok(file)
    }

    /// Every number finite, every parameter in its domain, the correction's shapes.
    pub fn validate(&self, source_name: &str) -> Result<(), NeuralError> {
        check_law(&self.law, source_name)?;
        for (name, [lo, hi]) in [
            ("sliding_velocity", self.ranges.sliding_velocity),
            ("normal_force", self.ranges.normal_force),
        ] {
            finite(source_name, format!("ranges.{name}[0]"), lo)?;
            finite(source_name, format!("ranges.{name}[1]"), hi)?;
            if lo > hi {
                return Err(shape_error(
                    source_name,
                    format!("ranges.{name}: min {lo} > max {hi}"),
                ));
            }
        }
        if let Some(net) = &self.correction {
            check_correction(net, source_name)?;
        }
        for (name, v) in [
            ("training.noise_std", self.training.noise_std),
            ("training.lambda", self.training.lambda),
            ("metrics.rms_error_train", self.metrics.rms_error_train),
            ("metrics.rms_error_test", self.metrics.rms_error_test),
        ] {
            finite(source_name, name.to_string(), v)?;
        }
        Ok(())
    }
}

fn shape_error(source_name: &str, message: String) -> NeuralError {
    NeuralError::Shape {
        source_name: source_name.to_string(),
        message,
    }
}

/// The structured law's parameters: finite, V_0, a and D_c positive, and inside the
/// analytical law's range.
fn check_law(p: &StateLawParameters, source_name: &str) -> Result<(), NeuralError> {
    for (name, v, positive) in [
        ("reference_coefficient", p.reference_coefficient, false),
        ("reference_velocity", p.reference_velocity, true),
        ("direct_effect", p.direct_effect, true),
        ("evolution_effect", p.evolution_effect, false),
        ("characteristic_slip", p.characteristic_slip, true),
    ] {
        finite(source_name, format!("law.{name}"), v)?;
        if positive && v <= 0.0 {
            return Err(shape_error(
                source_name,
                format!("law.{name} must be positive, got {v}"),
            ));
        }
    }
    // The analytical law's range (at psi = 0, without the correction's share of
    // Omega): a law steeper at rest would be capped (`regularised`), its force no
    // longer the law's.
    if let Some(problem) = crate::friction::rate_and_state::regularisation_problem(
        p.direct_effect,
        p.reference_coefficient,
        p.reference_velocity,
        ["law.direct_effect", "law.reference_velocity"],
    ) {
        return Err(shape_error(source_name, problem.to_string()));
    }
    Ok(())
}

/// The correction network: one hidden weight row, bias and output weight per unit,
/// every number finite, each input's scale with std > 0 and min <= max.
fn check_correction(net: &Correction, source_name: &str) -> Result<(), NeuralError> {
    let finite = |field: String, v: f64| finite(source_name, field, v);
    let h = net.output_weights.len();
    if net.hidden_weights.len() != h || net.hidden_biases.len() != h {
        return Err(shape_error(
            source_name,
            format!(
                "correction: {} hidden weight rows, {} hidden biases and {h} output weights, expected equal counts",
                net.hidden_weights.len(),
                net.hidden_biases.len()
            ),
        ));
    }
    for (k, row) in net.hidden_weights.iter().enumerate() {
        finite(format!("correction.hidden_weights[{k}][0]"), row[0])?;
        finite(format!("correction.hidden_weights[{k}][1]"), row[1])?;
        finite(
            format!("correction.hidden_biases[{k}]"),
            net.hidden_biases[k],
        )?;
        finite(
            format!("correction.output_weights[{k}]"),
            net.output_weights[k],
        )?;
    }
    for (i, input) in net.inputs.iter().enumerate() {
        for (what, v) in [
            ("mean", input.mean),
            ("std", input.std),
            ("min", input.min),
            ("max", input.max),
        ] {
            finite(format!("correction.inputs[{i}].{what}"), v)?;
        }
        if input.std <= 0.0 || input.min > input.max {
            return Err(shape_error(
                source_name,
                format!(
                    "correction.inputs[{i}] ('{}'): std must be positive and min <= max",
                    input.name
                ),
            ));
        }
    }
    Ok(())
}
