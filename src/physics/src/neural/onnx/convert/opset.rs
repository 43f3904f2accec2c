//! The IR and opset versions a model must declare for its operators to mean what the
//! converter reads them as.

use super::super::error::OnnxError;
use super::super::model::{GraphProto, ModelProto};

/// IR versions accepted: from 3 (opset imports, on which the operators' meaning depends)
/// to 11 (ONNX 1.18); the messages read here did not change in between.
pub const IR_VERSIONS: (i64, i64) = (3, 11);
/// Versions of the default (`ai.onnx`) opset accepted: from 7, where Add/Sub/Mul/Div
/// broadcast like numpy without the older `broadcast`/`axis` attributes and Gemm's C
/// broadcasts, to 23, the newest whose operator definitions this reader was checked
/// against (later versions of these operators only added data types so far, but a
/// future one may change their meaning).
pub const DEFAULT_OPSETS: (i64, i64) = (7, 23);
/// Versions of `ai.onnx.ml` accepted (for `Scaler`, defined in version 1 and unchanged).
pub const ML_OPSETS: (i64, i64) = (1, 5);

pub(super) fn domain_of(domain: &str) -> Option<bool> {
    // Some(false): the default opset; Some(true): ai.onnx.ml.
    match domain {
        "" | "ai.onnx" => Some(false),
        "ai.onnx.ml" => Some(true),
        _ => None,
    }
}

/// The model's graph, once its IR version and opsets are accepted.
pub(super) fn checked_graph<'m>(
    model: &'m ModelProto,
    source_name: &str,
) -> Result<&'m GraphProto, OnnxError> {
    let source = || source_name.to_string();
    let (min, max) = IR_VERSIONS;
    if !(min..=max).contains(&model.ir_version) {
        return Err(OnnxError::IrVersion {
            source_name: source(),
            found: model.ir_version,
            min,
            max,
        });
    }
    let opset = |ml: bool| {
        model
            .opset_import
            .iter()
            .filter(|o| domain_of(&o.domain) == Some(ml))
            .map(|o| o.version)
            .max()
    };
    let accepted = format!(
        "ai.onnx {} to {} (from 7 the elementwise operators broadcast like numpy; newer \
         versions are not checked), ai.onnx.ml {} to {} (Scaler)",
        DEFAULT_OPSETS.0, DEFAULT_OPSETS.1, ML_OPSETS.0, ML_OPSETS.1
    );
    let opset_error = |problem: String| OnnxError::Opset {
        source_name: source(),
        problem,
        accepted: accepted.clone(),
    };
    match opset(false) {
        None => return Err(opset_error("the model imports no ai.onnx opset".into())),
        Some(v) if !(DEFAULT_OPSETS.0..=DEFAULT_OPSETS.1).contains(&v) => {
            return Err(opset_error(format!("the model imports ai.onnx opset {v}")))
        }
        _ => {}
    }
    let graph = model.graph.as_ref().ok_or_else(|| OnnxError::Graph {
        source_name: source(),
        message: "the model has no graph".into(),
    })?;
    if graph
        .node
        .iter()
        .any(|n| domain_of(&n.domain) == Some(true))
    {
        match opset(true) {
            None => {
                return Err(opset_error(
                    "the graph uses ai.onnx.ml operators but imports no ai.onnx.ml opset".into(),
                ))
            }
            Some(v) if !(ML_OPSETS.0..=ML_OPSETS.1).contains(&v) => {
                return Err(opset_error(format!(
                    "the model imports ai.onnx.ml opset {v}"
                )))
            }
            _ => {}
        }
    }
    Ok(graph)
}
