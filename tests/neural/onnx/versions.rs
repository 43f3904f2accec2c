//! IR versions and opsets: missing opsets are refused, newer ones import as IR 11 and
//! opset 23, operators whose version means something else are refused by name.

use super::*;

#[test]
fn missing_opsets_are_refused() {
    let good = export(&small(), Exporter::Skl, true);
    let mut onnx = good.clone();
    onnx.opsets.retain(|(d, _)| d.is_empty());
    let message = refused(&onnx);
    assert!(message.contains("imports no ai.onnx.ml opset"), "{message}");
    let mut onnx = good.clone();
    onnx.opsets.retain(|(d, _)| !d.is_empty());
    assert!(refused(&onnx).contains("imports no ai.onnx opset"));
    let mut onnx = good;
    onnx.opsets[0].1 = 0;
    let message = refused(&onnx);
    assert!(
        message.contains("ai.onnx opset 0, which does not exist"),
        "{message}"
    );
}

/// `model` as the graph `onnx.helper` writes for dense layers alone: Gemm (transB = 1)
/// and the activation, nothing else (the torch form without its scalings).
fn gemm_and_activation_only(model: &NeuralModel) -> Onnx {
    let mut onnx = export(model, Exporter::Torch, false);
    onnx.nodes
        .retain(|n| n.op_type == "Gemm" || n.name.starts_with("act"));
    onnx.initializers
        .retain(|t| t.name.starts_with('W') || t.name.starts_with('b'));
    onnx.nodes[0].inputs[0] = "input".into();
    let last = onnx.nodes.len() - 1;
    onnx.nodes[last].outputs[0] = "force".into();
    onnx
}

/// IR 12 to 14 added data types only, and opsets 24 to 28 changed none of the operators
/// the exports use except for data types and float8-only attributes (the schema history
/// in `convert::opset`): the same graph written at any of them imports as the one written
/// at IR 11 / opset 23, bit for bit, in every form and precision.
#[test]
fn newer_ir_versions_and_opsets_import_as_ir_11_opset_23() {
    let model = small();
    let mut forms: Vec<(String, Onnx)> = Vec::new();
    for exporter in [Exporter::Torch, Exporter::Skl] {
        for single in [false, true] {
            forms.push((
                format!("{exporter:?} {}", if single { "f32" } else { "f64" }),
                export(&model, exporter, single),
            ));
        }
    }
    forms.push(("Gemm + Tanh".into(), gemm_and_activation_only(&model)));
    for (what, form) in forms {
        let mut base = form.clone();
        base.ir_version = 11;
        base.opsets[0].1 = 23;
        let reference = import(&base).unwrap_or_else(|e| panic!("{what}: {e}"));
        for ir_version in 12..=14 {
            for opset in 24..=28 {
                let mut newer = form.clone();
                newer.ir_version = ir_version;
                newer.opsets[0].1 = opset;
                let what = format!("{what}, IR {ir_version}, opset {opset}");
                let imported = import(&newer).unwrap_or_else(|e| panic!("{what}: {e}"));
                assert_same_network(&imported, &reference, &what);
                let (worst, identical) = compare(&imported, &reference);
                assert!(identical, "{what}: differs by up to {worst:e} N");
            }
        }
    }
}

/// An operator is refused by name where its version means something else than the
/// converter reads: Gemm before 7 (C broadcasts only with the `broadcast` attribute),
/// Sub before 7, an opset newer than the definitions checked (any operator might have
/// changed), and the same for ai.onnx.ml's Scaler; and an IR version newer than 14.
#[test]
fn operators_whose_version_means_something_else_are_refused_by_name() {
    let gemm = gemm_and_activation_only(&small());
    let mut old = gemm.clone();
    old.opsets[0].1 = 6;
    let message = refused(&old);
    assert!(
        message.contains("node 'gemm0' (Gemm) under ai.onnx opset 6")
            && message.contains("Gemm version 6")
            && message.contains("`broadcast`"),
        "{message}"
    );
    // Tanh and MatMul mean the same since version 1: the same graph with MatMul + Add
    // passes the operator check and is refused for its Add only.
    let mut skl = export(&small(), Exporter::Skl, false);
    skl.opsets[0].1 = 6;
    let message = refused(&skl);
    assert!(
        message.contains("node 'sub' (Sub)") && message.contains("Sub version 6"),
        "{message}"
    );
    let mut future = gemm.clone();
    future.opsets[0].1 = 29;
    let message = refused(&future);
    assert!(
        message.contains("node 'gemm0' (Gemm) under ai.onnx opset 29")
            && message.contains("newer than 28")
            && message.contains("Gemm version 13 is the newest"),
        "{message}"
    );
    let mut scaler = export(&small(), Exporter::Skl, true);
    scaler.opsets[1].1 = 6;
    let message = refused(&scaler);
    assert!(
        message.contains("node 'scaler' (Scaler) under ai.onnx.ml opset 6"),
        "{message}"
    );
    let mut ir = gemm;
    ir.ir_version = 15;
    let message = refused(&ir);
    assert!(
        message.contains("IR version 15") && message.contains("3 to 14"),
        "{message}"
    );
}

/// Cast's `round_mode` (opset 24) acts on float8 targets only: a cast to DOUBLE that
/// carries it means the plain cast and is read as one.
#[test]
fn a_cast_with_round_mode_is_read_as_the_plain_cast() {
    let model = small();
    let plain = gemm_and_activation_only(&model);
    let mut cast = plain.clone();
    cast.opsets[0].1 = 24;
    let last = cast.nodes.len() - 1;
    cast.nodes[last].outputs[0] = "uncast".into();
    let mut node = Node::new("Cast", "cast", &["uncast"], "force")
        .with(Attribute::Int("to".into(), i64::from(DOUBLE)));
    node.attributes
        .push(Attribute::Str("round_mode".into(), "up".into()));
    cast.nodes.push(node);
    let reference = import(&plain).unwrap();
    let imported = import(&cast).unwrap_or_else(|e| panic!("{e}"));
    assert_same_network(&imported, &reference, "Cast with round_mode");
}
