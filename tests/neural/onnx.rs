//! ONNX import (issue 23): networks exported as PyTorch and skl2onnx write them (by the
//! test encoder `stickslip_tests::onnx`) are imported and evaluate as the network they
//! came from; every refusal names its culprit.

use std::sync::Arc;
use stickslip::law_source::{LawSource, NetworkOrigin};
use stickslip::neural::onnx::{
    import_onnx, read_onnx, FeatureInfo, OnnxError, OnnxImport, Precision,
};
use stickslip::neural::weights::LayerWeights;
use stickslip::neural::{FeatureRole, NeuralLaw, NeuralModel};
use stickslip::scene::{FrictionLawKind, Inference, Scene};
use stickslip_tests::onnx::{
    export, Attribute, Data, Exporter, Node, Onnx, Value, DOUBLE, FLOAT16,
};

fn paper(signed: bool) -> NeuralModel {
    let law = if signed {
        NeuralLaw::paper_signed()
    } else {
        NeuralLaw::paper_default()
    };
    law.unwrap().model().clone()
}

fn import(onnx: &Onnx) -> Result<NeuralModel, OnnxError> {
    import_onnx(&onnx.encode(), &OnnxImport::named("test.onnx"))
}

/// A 80 x 50 grid over the (v, F_n) box widened by 10 % on each side (4000 points, some
/// clamped), as the law is evaluated.
fn points(model: &NeuralModel) -> Vec<[f64; 2]> {
    assert_eq!(model.features.len(), 2);
    let axis = |k: usize, n: usize| -> Vec<f64> {
        let (lo, hi) = (model.features[k].min, model.features[k].max);
        let pad = 0.1 * (hi - lo);
        (0..n)
            .map(|i| lo - pad + (hi - lo + 2.0 * pad) * i as f64 / (n - 1) as f64)
            .collect()
    };
    let (a, b) = (axis(0, 80), axis(1, 50));
    a.iter()
        .flat_map(|&x| b.iter().map(move |&y| [x, y]))
        .collect()
}

/// Largest |F_a - F_b| over `points`, and whether all are bit-identical.
fn compare(a: &NeuralModel, b: &NeuralModel) -> (f64, bool) {
    let mut la = NeuralLaw::new(a.clone()).unwrap();
    let mut lb = NeuralLaw::new(b.clone()).unwrap();
    let mut worst: f64 = 0.0;
    let mut identical = true;
    for p in points(a) {
        let (fa, fb) = (la.evaluate(&p).unwrap(), lb.evaluate(&p).unwrap());
        identical &= fa.to_bits() == fb.to_bits();
        worst = worst.max((fa - fb).abs());
    }
    (worst, identical)
}

/// The parts of a model an import must reproduce (training notes are not in ONNX).
fn assert_same_network(imported: &NeuralModel, expected: &NeuralModel, what: &str) {
    assert_eq!(imported.variant, expected.variant, "{what}");
    assert_eq!(imported.activation, expected.activation, "{what}");
    assert_eq!(imported.layer_sizes, expected.layer_sizes, "{what}");
    assert_eq!(imported.features, expected.features, "{what}");
    assert_eq!(imported.target, expected.target, "{what}");
    assert_eq!(imported.layers, expected.layers, "{what}");
}

/// f64 exports in the common forms map one to one onto the model (Sub/Div -> mean/std,
/// Gemm or MatMul + Add -> weights as stored, Mul/Add -> output std/mean), so the
/// imported model is the same numbers and every evaluation is bit-identical, for both
/// shipped models (plain and signed).
#[test]
fn f64_exports_import_bit_for_bit() {
    for signed in [false, true] {
        let model = paper(signed);
        for exporter in [Exporter::Torch, Exporter::Skl] {
            let what = format!("{exporter:?} f64, signed {signed}");
            let onnx = export(&model, exporter, false);
            let network = read_onnx(&onnx.encode(), "test.onnx").unwrap();
            assert_eq!(network.precision, Precision::F64, "{what}");
            let imported = import(&onnx).unwrap_or_else(|e| panic!("{what}: {e}"));
            assert_same_network(&imported, &model, &what);
            let (worst, identical) = compare(&imported, &model);
            assert!(identical, "{what}: differs by up to {worst:e} N");
        }
    }
}

/// `model` with every number an f32 export holds rounded to f32, as the importer must
/// read it back: weights, biases, means and output scaling rounded; the std rounded, or
/// for skl2onnx's Scaler 1 / f32(1 / std) (it stores the scale).
fn rounded(model: &NeuralModel, scaler: bool) -> NeuralModel {
    let r = |x: f64| x as f32 as f64;
    let mut m = model.clone();
    for f in &mut m.features {
        f.input_mean = r(f.input_mean);
        f.input_std = if scaler {
            1.0 / r(1.0 / f.input_std)
        } else {
            r(f.input_std)
        };
    }
    m.target.output_mean = r(m.target.output_mean);
    m.target.output_std = r(m.target.output_std);
    for layer in &mut m.layers {
        layer.weights.iter_mut().flatten().for_each(|w| *w = r(*w));
        layer.biases.iter_mut().for_each(|b| *b = r(*b));
    }
    m
}

/// f32 exports: FLOAT widens to f64 exactly, so the import is exactly the f32-rounded
/// network (bit-identical evaluations). Against the f64 original it differs by the
/// weights' rounding, relative 2^-24 = 6e-8 each, which moves the force by about 6e-8
/// times the output's condition (sum over paths of |weight products| times the
/// activations, relative to the force). Measured for the shipped 3 x 100 tanh networks:
/// 1e-6 to 2.2e-6 N on forces up to 55 N, i.e. 4e-8 relative (condition ~1); bounded by
/// 1e-6 of the largest force (a condition of 16 would still pass, a lost bit in the
/// import would not: that is 1e-7 relative per weight and adds up over 100 units).
#[test]
fn f32_exports_import_the_rounded_network() {
    for signed in [false, true] {
        let model = paper(signed);
        let largest = points(&model)
            .iter()
            .map(|p| {
                NeuralLaw::new(model.clone())
                    .unwrap()
                    .evaluate(p)
                    .unwrap()
                    .abs()
            })
            .fold(0.0, f64::max);
        for exporter in [Exporter::Torch, Exporter::Skl] {
            let what = format!("{exporter:?} f32, signed {signed}");
            let onnx = export(&model, exporter, true);
            let network = read_onnx(&onnx.encode(), "test.onnx").unwrap();
            assert_eq!(network.precision, Precision::F32, "{what}");
            let imported = import(&onnx).unwrap_or_else(|e| panic!("{what}: {e}"));
            let reference = rounded(&model, exporter == Exporter::Skl);
            assert_same_network(&imported, &reference, &what);
            let (_, identical) = compare(&imported, &reference);
            assert!(identical, "{what}");
            let (worst, _) = compare(&imported, &model);
            println!("{what}: largest deviation from f64 {worst:.3e} N of {largest:.1} N");
            assert!(worst <= 1e-6 * largest, "{what}: {worst:e} N");
            assert!(worst > 0.0, "{what}: f32 rounding must show");
        }
    }
}

/// A small network [2, 4, 3, 1] tanh with fixed weights, for the refusals.
fn small() -> NeuralModel {
    let mut model = paper(false);
    let sizes = [2usize, 4, 3, 1];
    let mut seed = 1u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    };
    model.layer_sizes = sizes.to_vec();
    model.layers = sizes
        .windows(2)
        .map(|p| LayerWeights {
            weights: (0..p[1])
                .map(|_| (0..p[0]).map(|_| next()).collect())
                .collect(),
            biases: (0..p[1]).map(|_| next()).collect(),
        })
        .collect();
    model
}

fn refused(onnx: &Onnx) -> String {
    match import(onnx) {
        Ok(_) => panic!("accepted: {onnx:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn small_network_imports_in_every_form() {
    let model = small();
    for exporter in [Exporter::Torch, Exporter::Skl] {
        let imported = import(&export(&model, exporter, false)).unwrap();
        assert_same_network(&imported, &model, &format!("{exporter:?}"));
    }
}

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
            Err(OnnxError::Wire { .. }) => wire += 1,
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

/// Without metadata the features must come from the options; options replace metadata.
#[test]
fn features_come_from_metadata_or_options() {
    let model = small();
    let mut onnx = export(&model, Exporter::Torch, false);
    onnx.metadata.clear();
    let bytes = onnx.encode();
    let message = import_onnx(&bytes, &OnnxImport::named("bare.onnx"))
        .unwrap_err()
        .to_string();
    assert!(message.contains("stickslip.features"), "{message}");
    let features = vec![
        FeatureInfo {
            name: "v".into(),
            unit: "m/s".into(),
            role: FeatureRole::SlidingVelocity,
            min: -1.0,
            max: 1.0,
        },
        FeatureInfo {
            name: "F_n".into(),
            unit: "N".into(),
            role: FeatureRole::NormalForce,
            min: 50.0,
            max: 150.0,
        },
    ];
    let options = OnnxImport {
        features: Some(features.clone()),
        ..OnnxImport::named("bare.onnx")
    };
    let imported = import_onnx(&bytes, &options).unwrap();
    assert_eq!(imported.features[1].name, "F_n");
    assert_eq!(imported.features[1].max, 150.0);
    assert_eq!(imported.layers, model.layers);
    assert!(NeuralLaw::new(imported)
        .unwrap()
        .into_friction_law()
        .is_ok());
    let options = OnnxImport {
        features: Some(features[..1].to_vec()),
        ..OnnxImport::named("bare.onnx")
    };
    let message = import_onnx(&bytes, &options).unwrap_err().to_string();
    assert!(message.contains("1 features are described but the network has 2 inputs"));
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

/// A scratch file of this test process.
fn scratch(name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = std::env::temp_dir().join(format!("stickslip-onnx-{}-{name}", std::process::id()));
    std::fs::write(&path, bytes).unwrap();
    path
}

/// Forces of `network` as the beam's law under `inference`, on a (v, F_n) grid inside
/// and around the training range (the table is built at F_n = 100 N and evaluated at
/// its normal force; the grid exercises clamping too).
fn beam_forces(network: NeuralLaw, inference: Inference) -> Vec<f64> {
    let source = LawSource::network(
        Arc::new(network),
        NetworkOrigin::Weights("test".into()),
        inference,
        100.0,
    );
    let mut law = source.law().unwrap();
    let model = paper(false);
    points(&model)
        .iter()
        .map(|&[v, f_n]| law.sliding_force(v, f_n))
        .collect()
}

/// An `.onnx` file is a weights file (issue 23): `NeuralLaw::from_file` reads it by
/// extension or by its first byte, features from its metadata, and it serves every
/// inference option. A DOUBLE export is the shipped network bit for bit, so exact, f32
/// and table give the same bits as the shipped JSON; a FLOAT export is the f32-rounded
/// network, so it gives the bits of that network's JSON (written and read back). The
/// two f32 paths agree exactly, which shows the options work on the imported network
/// itself rather than on a stand-in.
#[test]
fn onnx_files_are_weights_files_for_every_inference() {
    let shipped = paper(false);
    for single in [false, true] {
        let bytes = export(&shipped, Exporter::Torch, single).encode();
        let named = scratch(&format!("paper-{single}.onnx"), &bytes);
        // Found by the magic byte alone.
        let unnamed = scratch(&format!("paper-{single}.weights"), &bytes);
        let expected = if single {
            rounded(&shipped, false)
        } else {
            shipped.clone()
        };
        let json = std::env::temp_dir().join(format!(
            "stickslip-onnx-{}-paper-{single}.json",
            std::process::id()
        ));
        expected.save(&json).unwrap();
        for inference in [Inference::Exact, Inference::F32, Inference::Table] {
            let want = beam_forces(NeuralLaw::from_file(&json).unwrap(), inference);
            for path in [&named, &unnamed] {
                let law = NeuralLaw::from_file(path).unwrap();
                assert_eq!(law.model().layers, expected.layers, "{path:?}");
                let got = beam_forces(law, inference);
                let same = got
                    .iter()
                    .zip(&want)
                    .all(|(a, b)| a.to_bits() == b.to_bits());
                assert!(same, "{path:?} {inference:?}: not bit-identical");
            }
        }
        for path in [named, unnamed, json] {
            std::fs::remove_file(path).unwrap();
        }
    }
}

/// A scene's `friction.weights` takes an `.onnx` file; one without the features'
/// description is refused with the metadata key and the command-line flags that
/// supply it, and the reason reaches the scene's error.
#[test]
fn a_scene_reads_onnx_weights_and_names_what_is_missing() {
    let shipped = paper(false);
    let mut onnx = export(&shipped, Exporter::Skl, true);
    let good = scratch("scene.onnx", &onnx.encode());
    onnx.metadata.clear();
    let bare = scratch("bare.onnx", &onnx.encode());
    let scene = |path: &std::path::Path| {
        let mut scene = Scene::default();
        scene.friction.law = FrictionLawKind::Neural;
        scene.friction.weights = Some(path.display().to_string());
        scene.check().unwrap()
    };
    let source = LawSource::resolve(&scene(&good)).unwrap();
    let force = source.law().unwrap().sliding_force(0.1, 100.0);
    let mut shipped_law = NeuralLaw::new(shipped).unwrap();
    let want = shipped_law.evaluate(&[0.1, 100.0]).unwrap();
    // f32 weights: the 4e-8 relative of f32_exports_import_the_rounded_network.
    assert!(
        (force - want).abs() < 1e-6 * want.abs(),
        "{force} vs {want}"
    );

    let message = LawSource::resolve(&scene(&bare)).unwrap_err().to_string();
    for part in [
        "friction.weights",
        "bare.onnx",
        "stickslip.features",
        "import-network",
        "--feature NAME:ROLE:UNIT:MIN:MAX",
    ] {
        assert!(message.contains(part), "{part} missing from: {message}");
    }
    // The ONNX reason is kept as the `OnnxError` it is.
    match NeuralLaw::from_file(&bare) {
        Err(stickslip::neural::NeuralError::Onnx(e)) => assert!(
            matches!(
                e.downcast_ref::<OnnxError>(),
                Some(OnnxError::Description { .. })
            ),
            "{e:?}"
        ),
        other => panic!("{other:?}"),
    }
    for path in [good, bare] {
        std::fs::remove_file(path).unwrap();
    }
}

/// The paper authors' MATLAB network given where weights are read (the beam's
/// `friction.weights`, NeuralFriction's `weights`, `--weights`) is refused with the
/// command that converts it, found by its extension and, renamed, by its header; never
/// a JSON syntax error.
#[test]
fn a_matlab_file_as_weights_names_the_converter() {
    let authors = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../data/paper-authors/trained_regression_nn_friction_model.mat");
    let renamed = scratch("authors.weights", &std::fs::read(&authors).unwrap());
    for path in [authors.as_path(), renamed.as_path()] {
        let error = NeuralLaw::from_file(path).unwrap_err();
        assert!(
            matches!(error, stickslip::neural::NeuralError::Matlab { .. }),
            "{error:?}"
        );
        let mut scene = Scene::default();
        scene.friction.law = FrictionLawKind::Neural;
        scene.friction.weights = Some(path.display().to_string());
        let message = LawSource::resolve(&scene.check().unwrap())
            .unwrap_err()
            .to_string();
        for part in [
            "MATLAB",
            "stickslip_checks.import_fitrnet",
            "--out NETWORK.onnx",
        ] {
            assert!(message.contains(part), "{part} missing from: {message}");
        }
    }
    std::fs::remove_file(renamed).unwrap();
}

/// A recurrent cell anywhere in the graph is named as what it is, a network with state,
/// with the way to a law with memory, rather than as an unsupported operator or a
/// broken chain.
#[test]
fn a_recurrent_network_is_refused_as_a_law_with_state() {
    for op in ["GRU", "LSTM", "RNN", "Loop", "Scan"] {
        let mut onnx = export(&small(), Exporter::Torch, false);
        onnx.node("act1").op_type = op.into();
        let message = refused(&onnx);
        assert!(
            message.contains(&format!(
                "node 'act1': operator '{op}' makes a network with state"
            )) && message.contains("stickslip train-memory"),
            "{message}"
        );
    }
    // Elsewhere than ai.onnx the name means nothing to the import: an unknown operator.
    let mut onnx = export(&small(), Exporter::Torch, false);
    onnx.node("act1").op_type = "GRU".into();
    onnx.node("act1").domain = "com.example".into();
    assert!(!refused(&onnx).contains("with state"));
}
