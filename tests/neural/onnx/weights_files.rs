//! ONNX files as weights files: the features from metadata or options, every inference
//! of the beam, a scene that reads them, MATLAB files and recurrent networks named.

use super::*;

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
    // The ONNX reason is kept as the `OnnxImportError` it is.
    match NeuralLaw::from_file(&bare) {
        Err(stickslip::neural::NeuralError::Onnx(e)) => assert!(
            matches!(
                e.downcast_ref::<OnnxImportError>(),
                Some(OnnxImportError::Description { .. })
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
