//! Malformed graphs and networks are refused naming their culprit (truncated files,
//! cycles, dangling and extra inputs, bad tensors, unknown operators, overflow), and the
//! fuzz seeds import or are refused.

use super::*;

/// A prefix of a file cut inside a field is refused as such (the message names the
/// byte); one cut at a field boundary is a valid shorter message, so every prefix that
/// lacks part of the graph, the opsets or the features' metadata (all written before
/// the optional target and variant keys) must be refused, and none may panic.
#[test]
fn truncated_files_are_refused() {
    let onnx = export(&small(), Exporter::Torch, false);
    let bytes = onnx.encode();
    let mut required = onnx.clone();
    required.metadata.truncate(1);
    let required = required.encode().len();
    assert!(required < bytes.len());
    let mut wire = 0;
    for n in 0..bytes.len() {
        match import_onnx(&bytes[..n], &OnnxImport::named("cut.onnx")) {
            Ok(_) if n < required => panic!("a {n}-byte prefix of {} was accepted", bytes.len()),
            Err(OnnxImportError::Read(OnnxError::Wire { .. })) => wire += 1,
            _ => {}
        }
    }
    assert!(wire > bytes.len() / 2, "{wire} of {}", bytes.len());
    let message = import_onnx(&bytes[..bytes.len() / 2], &OnnxImport::named("cut.onnx"))
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("cut.onnx: not a valid ONNX file") && message.contains("byte"),
        "{message}"
    );
}

#[test]
fn a_cycle_is_refused_naming_the_nodes() {
    let mut onnx = export(&small(), Exporter::Torch, false);
    // gemm0 reads the output of act1, which comes after it.
    onnx.node("gemm0").inputs[0] = "a1".into();
    let message = refused(&onnx);
    assert!(
        message.contains("'gemm0' (Gemm) reads 'a1'")
            && message.contains("'act1' (Tanh)")
            && message.contains("cycle"),
        "{message}"
    );
}

#[test]
fn a_dangling_input_is_refused() {
    let mut onnx = export(&small(), Exporter::Torch, false);
    onnx.node("gemm1").inputs[1] = "W9".into();
    let message = refused(&onnx);
    assert!(message.contains("'gemm1' (Gemm) reads 'W9'"), "{message}");
}

#[test]
fn a_second_graph_input_is_refused() {
    let mut onnx = export(&small(), Exporter::Torch, false);
    onnx.inputs.push(Value {
        name: "temperature".into(),
        elem_type: DOUBLE,
        width: Some(1),
    });
    let message = refused(&onnx);
    assert!(
        message.contains("2 inputs") && message.contains("temperature"),
        "{message}"
    );
}

#[test]
fn a_nan_weight_is_refused_naming_the_tensor() {
    for (exporter, single) in [(Exporter::Torch, true), (Exporter::Skl, false)] {
        let mut onnx = export(&small(), exporter, single);
        match &mut onnx.initializer("W1").data {
            Data::F32(v) => v[3] = f32::NAN,
            Data::F64(v) => v[3] = f64::INFINITY,
            Data::I64(_) => unreachable!(),
        }
        let message = refused(&onnx);
        assert!(message.contains("tensor 'W1' element 3"), "{message}");
    }
}

#[test]
fn an_unknown_operator_is_refused_by_node_and_type() {
    let mut onnx = export(&small(), Exporter::Torch, false);
    onnx.node("act1").op_type = "Elu".into();
    let message = refused(&onnx);
    assert!(
        message.contains("node 'act1' (Elu)") && message.contains("'Elu' of domain 'ai.onnx'"),
        "{message}"
    );
}

#[test]
fn a_wrong_dtype_is_refused_by_name() {
    let mut onnx = export(&small(), Exporter::Torch, true);
    onnx.initializer("W0").data_type = Some(FLOAT16);
    let message = refused(&onnx);
    assert!(
        message.contains("tensor 'W0' has data type FLOAT16 (10)"),
        "{message}"
    );
    let mut onnx = export(&small(), Exporter::Torch, true);
    onnx.inputs[0].elem_type = 6;
    let message = refused(&onnx);
    assert!(
        message.contains("graph input 'input' has data type INT32 (6)"),
        "{message}"
    );
}

#[test]
fn a_shape_mismatch_is_refused_with_both_shapes() {
    let mut onnx = export(&small(), Exporter::Torch, false);
    // Layer 2 is 4 -> 3, stored [3, 4] for transB = 1; claim [4, 3].
    onnx.initializer("W1").dims = vec![4, 3];
    let message = refused(&onnx);
    assert!(
        message.contains("'gemm1' (Gemm)")
            && message.contains("[batch, 4]")
            && message.contains("[4, 3] (transposed)"),
        "{message}"
    );
    let mut onnx = export(&small(), Exporter::Torch, false);
    onnx.initializer("W1").dims = vec![3, 5];
    assert!(refused(&onnx).contains("dims [3, 5] (15 elements) but holds 12 values"));
}

#[test]
fn unsupported_attributes_and_structures_are_refused_with_reasons() {
    let mut onnx = export(&small(), Exporter::Torch, false);
    onnx.node("gemm0")
        .attributes
        .push(Attribute::Int("transA".into(), 1));
    assert!(refused(&onnx).contains("attribute 'transA': transA = 1"));

    let mut onnx = export(&small(), Exporter::Torch, false);
    onnx.node("act1").op_type = "Relu".into();
    let message = refused(&onnx);
    assert!(
        message.contains("Tanh ('act0' (Tanh)) and Relu ('act1' (Relu))")
            && message.contains("one activation for all hidden layers"),
        "{message}"
    );

    let mut onnx = export(&small(), Exporter::Torch, false);
    onnx.nodes
        .push(Node::new("Sigmoid", "squash", &["force"], "squashed"));
    onnx.outputs[0].name = "squashed".into();
    let message = refused(&onnx);
    assert!(
        message.contains("activation 'squash' (Sigmoid) follows a scaling"),
        "{message}"
    );

    let mut onnx = export(&small(), Exporter::Torch, false);
    onnx.nodes
        .retain(|n| n.name != "unscale" && n.name != "shift");
    onnx.nodes
        .push(Node::new("Sigmoid", "squash", &["z2"], "force"));
    let message = refused(&onnx);
    assert!(
        message.contains("output layer ends with activation 'squash' (Sigmoid)"),
        "{message}"
    );
}

/// Finite weights that overflow f64 within the training range are refused, so that an
/// accepted model always evaluates to finite forces.
#[test]
fn an_overflowing_network_is_refused() {
    let mut model = small();
    model.layers[0].weights[0][0] = 1e200;
    model.layers[2].weights[0][0] = 1e200;
    model.layers[1].weights[0][0] = 1e200;
    model.activation = stickslip::neural::Activation::Relu;
    let message = refused(&export(&model, Exporter::Torch, false));
    assert!(message.contains("not bounded"), "{message}");
}

/// The fuzz target's seeds import (with generic features where they lack metadata);
/// with STICKSLIP_ONNX_SEEDS set to a folder they are written there (fuzz/seeds.rs
/// writes the same into fuzz/corpus/onnx).
#[test]
fn fuzz_seeds_import() {
    for (name, bytes) in stickslip_tests::onnx::fuzz_seeds() {
        let network = read_onnx(&bytes, &name).unwrap_or_else(|e| panic!("{e}"));
        let options = OnnxImport {
            features: network.metadata.is_empty().then(|| {
                (0..2)
                    .map(|k| FeatureInfo::other(format!("x{k}"), -1.0, 1.0))
                    .collect()
            }),
            ..OnnxImport::named(name.as_str())
        };
        import_onnx(&bytes, &options).unwrap_or_else(|e| panic!("{e}"));
        assert!(bytes.len() < 2048, "{name}: {} bytes", bytes.len());
        if let Some(dir) = std::env::var_os("STICKSLIP_ONNX_SEEDS") {
            std::fs::write(
                std::path::Path::new(&dir).join(format!("seed-{name}")),
                &bytes,
            )
            .unwrap();
        }
    }
}
