//! An ONNX file, as `stickslip_formats::onnx::read_onnx` reads it and
//! `stickslip::neural::onnx` imports it
//! (issue 23: a network exported by PyTorch, Keras or scikit-learn).
//!
//! A file that converts is imported with its metadata, or, when that does not describe
//! it, with generic features (role other, range [-1, 1]); the model is then evaluated at
//! the edges of and far outside its training range, one sample at a time and in a
//! batch.
//!
//! Checked properties (a panic is a finding):
//! - nothing panics, whatever the bytes (the reader promises an `OnnxError`, the
//!   import an `OnnxImportError`);
//! - an imported model is a valid `NeuralLaw`;
//! - it evaluates every finite feature vector to a finite force (inputs are clamped to
//!   the training range and the importer bounds the output over it).

#![no_main]

use libfuzzer_sys::fuzz_target;
use nalgebra::DMatrix;
use stickslip::neural::onnx::{describe, FeatureInfo, OnnxImport};
use stickslip::neural::NeuralLaw;
use stickslip_formats::onnx::read_onnx;

fuzz_target!(|data: &[u8]| {
    let Ok(network) = read_onnx(data, "fuzz.onnx") else {
        return;
    };
    let options = OnnxImport::named("fuzz.onnx");
    let model = match describe::neural_model(&network, &options) {
        Ok(model) => model,
        Err(_) => {
            let generic = OnnxImport {
                features: Some(
                    (0..network.input_mean.len())
                        .map(|k| FeatureInfo::other(format!("x{k}"), -1.0, 1.0))
                        .collect(),
                ),
                ..options
            };
            let Ok(model) = describe::neural_model(&network, &generic) else {
                return;
            };
            model
        }
    };
    let law = NeuralLaw::new(model.clone())
        .unwrap_or_else(|e| panic!("an imported model is not a valid law: {e}"));

    let probes: Vec<Vec<f64>> = stickslip_fuzz::probes(&model);
    let mut single = law.clone();
    for x in &probes {
        let force = single
            .evaluate(x)
            .unwrap_or_else(|e| panic!("evaluate refuses finite features: {e}"));
        assert!(force.is_finite(), "force {force} at {x:?}");
    }
    let d = model.features.len();
    let batch = DMatrix::from_fn(d, probes.len(), |row, col| probes[col][row]);
    let forces = law
        .evaluate_batch(&batch)
        .unwrap_or_else(|e| panic!("evaluate_batch refuses finite features: {e}"));
    assert_eq!(forces.len(), probes.len());
    assert!(
        forces.iter().all(|f| f.is_finite()),
        "batch forces {forces:?}"
    );
});
