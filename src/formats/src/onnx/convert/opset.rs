//! The IR version and the operator versions a model must have for its operators to mean
//! what the converter reads them as.
//!
//! A model is judged by the operators it uses, not by its opset number alone: each node's
//! operator resolves, under the opset the model imports, to the operator version in force
//! (the newest since-version at or below the opset, as ONNX defines it), and that version
//! must be one whose meaning for FLOAT and DOUBLE [batch, features] values, with the
//! attributes the converter allows, is the one the converter implements.
//!
//! The since-versions in [`OPERATORS`] are those of onnx 1.23.2's schema history
//! (`onnx.defs.get_all_schemas_with_history()`, ai.onnx up to opset 28, ai.onnx.ml up to
//! 5), the source of truth for what each operator version is. Between the accepted
//! versions the schemas differ only by added data types (bfloat16, integers, float8,
//! int4, float4, float8e8m0, int2, float6: all refused by the data type check) and by
//! attributes the converter checks itself (Reshape's `allowzero` from 14, Cast's
//! `saturate` from 19 and `round_mode` from 24, which act on float8 targets only, and
//! Constant's `sparse_value` and `value_*` from 11 and 12, refused). A model importing an
//! opset newer than the one checked is refused naming each operator it uses, since a
//! later version of it may mean something else.

use super::super::error::OnnxError;
use super::super::model::{node_label, GraphProto, ModelProto};

/// IR versions accepted: from 3 (opset imports, on which the operators' meaning depends)
/// to 14 (onnx 1.23). IR 12 to 14 added data types only (FLOAT8E8M0; UINT2 and INT2;
/// FLOAT6E2M3 and FLOAT6E3M2) and TypeProto.Opaque outside ONNX-ML builds; the messages
/// and fields this reader decodes are the same, and the data types are refused by name.
pub const IR_VERSIONS: (i64, i64) = (3, 14);
/// The newest opset of each domain whose operator definitions this reader was checked
/// against: `ai.onnx` 28 and `ai.onnx.ml` 5 (onnx 1.23.2).
pub const CHECKED_OPSETS: CheckedOpsets = CheckedOpsets { default: 28, ml: 5 };

/// The newest opset per domain that [`OPERATORS`] covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CheckedOpsets {
    pub default: i64,
    pub ml: i64,
}

/// One operator's definitions: every since-version in the checked opsets, and the first
/// one whose meaning the converter implements (an older one is refused, `older` says why).
#[derive(Clone, Copy, Debug)]
pub struct OperatorHistory {
    pub op_type: &'static str,
    /// `ai.onnx.ml` rather than the default domain.
    pub ml: bool,
    /// Since-versions, ascending (onnx 1.23.2's schema history).
    pub since: &'static [i64],
    pub accepted_from: i64,
    /// Why the versions before `accepted_from` are not read (empty when all are).
    pub older: &'static str,
}

const ELEMENTWISE_BEFORE_7: &str = "before version 7 it broadcasts only with the \
`broadcast` and `axis` attributes (from 7: numpy broadcasting, which the converter implements)";

/// Every operator the converter reads, with its versions.
pub const OPERATORS: [OperatorHistory; 15] = [
    OperatorHistory {
        op_type: "Gemm",
        ml: false,
        since: &[1, 6, 7, 9, 11, 13],
        accepted_from: 7,
        older: "before version 7 C is added without broadcasting unless the `broadcast` \
                attribute is set (from 7: C broadcasts)",
    },
    OperatorHistory {
        op_type: "MatMul",
        ml: false,
        since: &[1, 9, 13],
        accepted_from: 1,
        older: "",
    },
    OperatorHistory {
        op_type: "Add",
        ml: false,
        since: &[1, 6, 7, 13, 14],
        accepted_from: 7,
        older: ELEMENTWISE_BEFORE_7,
    },
    OperatorHistory {
        op_type: "Sub",
        ml: false,
        since: &[1, 6, 7, 13, 14],
        accepted_from: 7,
        older: ELEMENTWISE_BEFORE_7,
    },
    OperatorHistory {
        op_type: "Mul",
        ml: false,
        since: &[1, 6, 7, 13, 14],
        accepted_from: 7,
        older: ELEMENTWISE_BEFORE_7,
    },
    OperatorHistory {
        op_type: "Div",
        ml: false,
        since: &[1, 6, 7, 13, 14],
        accepted_from: 7,
        older: ELEMENTWISE_BEFORE_7,
    },
    // Version 1 of the activations has `consumed_inputs`, a legacy memory hint that does
    // not change the values; the converter allows no attribute on them, so a file that
    // sets it is refused by the attribute check.
    OperatorHistory {
        op_type: "Tanh",
        ml: false,
        since: &[1, 6, 13],
        accepted_from: 1,
        older: "",
    },
    OperatorHistory {
        op_type: "Relu",
        ml: false,
        since: &[1, 6, 13, 14],
        accepted_from: 1,
        older: "",
    },
    OperatorHistory {
        op_type: "Sigmoid",
        ml: false,
        since: &[1, 6, 13],
        accepted_from: 1,
        older: "",
    },
    OperatorHistory {
        op_type: "Identity",
        ml: false,
        since: &[1, 13, 14, 16, 19, 21, 23, 24, 25],
        accepted_from: 1,
        older: "",
    },
    OperatorHistory {
        op_type: "Cast",
        ml: false,
        since: &[1, 6, 9, 13, 19, 21, 23, 24, 25, 28],
        accepted_from: 6,
        older: "version 1 names the target type by a string (from 6: the data type number \
                the converter reads)",
    },
    OperatorHistory {
        op_type: "Flatten",
        ml: false,
        since: &[1, 9, 11, 13, 21, 23, 24, 25],
        accepted_from: 1,
        older: "",
    },
    OperatorHistory {
        op_type: "Reshape",
        ml: false,
        since: &[1, 5, 13, 14, 19, 21, 23, 24, 25],
        accepted_from: 5,
        older: "version 1 takes the shape as an attribute (from 5: as the second input, \
                which the converter reads)",
    },
    OperatorHistory {
        op_type: "Constant",
        ml: false,
        since: &[1, 9, 11, 12, 13, 19, 21, 23, 24, 25],
        accepted_from: 1,
        older: "",
    },
    OperatorHistory {
        op_type: "Scaler",
        ml: true,
        since: &[1],
        accepted_from: 1,
        older: "",
    },
];

impl OperatorHistory {
    /// Why this operator cannot be read under `opset` of its domain, if it cannot.
    fn refusal(&self, opset: i64) -> Option<String> {
        let checked = if self.ml {
            CHECKED_OPSETS.ml
        } else {
            CHECKED_OPSETS.default
        };
        let newest = *self.since.last()?;
        if opset > checked {
            return Some(format!(
                "the opset is newer than {checked} (onnx 1.23), the newest this reader's \
                 operator definitions were checked against; {} version {newest} is the newest \
                 known here, and a version after it may mean something else",
                self.op_type
            ));
        }
        match self.since.iter().rev().find(|&&v| v <= opset) {
            None => Some(format!("the opset defines no {}", self.op_type)),
            Some(&version) if version < self.accepted_from => Some(format!(
                "it is {} version {version}, and {}; accepted: version {} and later (opset {} \
                 to {checked})",
                self.op_type, self.older, self.accepted_from, self.accepted_from
            )),
            Some(_) => None,
        }
    }
}

pub(super) fn domain_of(domain: &str) -> Option<bool> {
    // Some(false): the default opset; Some(true): ai.onnx.ml.
    match domain {
        "" | "ai.onnx" => Some(false),
        "ai.onnx.ml" => Some(true),
        _ => None,
    }
}

/// The model's graph, once its IR version, its opset imports and the version of every
/// operator it uses are accepted.
pub(super) fn checked_graph<'m>(
    model: &'m ModelProto,
    source_name: &str,
) -> Result<&'m GraphProto, OnnxError> {
    let (min, max) = IR_VERSIONS;
    if !(min..=max).contains(&model.ir_version) {
        return Err(OnnxError::IrVersion {
            source_name: source_name.to_string(),
            found: model.ir_version,
            min,
            max,
        });
    }
    let default_opset = default_opset(model, source_name)?;
    let graph = model.graph.as_ref().ok_or_else(|| OnnxError::Graph {
        source_name: source_name.to_string(),
        message: "the model has no graph".into(),
    })?;
    let ml_opset = ml_opset(model, graph, source_name)?;
    check_operator_versions(graph, default_opset, ml_opset, source_name)?;
    Ok(graph)
}

/// The newest opset the model imports of the default domain (`ml` false) or of
/// `ai.onnx.ml` (`ml` true).
fn imported_opset(model: &ModelProto, ml: bool) -> Option<i64> {
    model
        .opset_import
        .iter()
        .filter(|o| domain_of(&o.domain) == Some(ml))
        .map(|o| o.version)
        .max()
}

fn opset_error(source_name: &str, problem: String) -> OnnxError {
    OnnxError::Opset {
        source_name: source_name.to_string(),
        problem,
        accepted: format!(
            "each operator is judged by the version its opset gives it; opsets up to ai.onnx {} \
             and ai.onnx.ml {} are checked",
            CHECKED_OPSETS.default, CHECKED_OPSETS.ml
        ),
    }
}

/// The ai.onnx opset, which every model must import.
fn default_opset(model: &ModelProto, source_name: &str) -> Result<i64, OnnxError> {
    match imported_opset(model, false) {
        None => Err(opset_error(
            source_name,
            "the model imports no ai.onnx opset".into(),
        )),
        Some(v) if v < 1 => Err(opset_error(
            source_name,
            format!("the model imports ai.onnx opset {v}, which does not exist"),
        )),
        Some(v) => Ok(v),
    }
}

/// The ai.onnx.ml opset, required when the graph uses one of its operators (0 when
/// absent and unused).
fn ml_opset(model: &ModelProto, graph: &GraphProto, source_name: &str) -> Result<i64, OnnxError> {
    let uses_ml = graph
        .node
        .iter()
        .any(|n| domain_of(&n.domain) == Some(true));
    match imported_opset(model, true) {
        None if uses_ml => Err(opset_error(
            source_name,
            "the graph uses ai.onnx.ml operators but imports no ai.onnx.ml opset".into(),
        )),
        Some(v) if uses_ml && v < 1 => Err(opset_error(
            source_name,
            format!("the model imports ai.onnx.ml opset {v}, which does not exist"),
        )),
        found => Ok(found.unwrap_or(0)),
    }
}

/// Every node whose operator is in [`OPERATORS`] is of a version, under the opset of
/// its domain, that the converter reads.
fn check_operator_versions(
    graph: &GraphProto,
    default_opset: i64,
    ml_opset: i64,
    source_name: &str,
) -> Result<(), OnnxError> {
    for (index, node) in graph.node.iter().enumerate() {
        // Operators outside the table (and other domains) are refused by name when the
        // chain reaches them, with the list of those supported.
        let Some(ml) = domain_of(&node.domain) else {
            continue;
        };
        let Some(history) = OPERATORS
            .iter()
            .find(|h| h.ml == ml && h.op_type == node.op_type)
        else {
            continue;
        };
        let (domain, version) = if ml {
            ("ai.onnx.ml", ml_opset)
        } else {
            ("ai.onnx", default_opset)
        };
        if let Some(reason) = history.refusal(version) {
            return Err(OnnxError::OperatorVersion {
                source_name: source_name.to_string(),
                node: node_label(index, node),
                domain,
                opset: version,
                reason,
            });
        }
    }
    Ok(())
}
