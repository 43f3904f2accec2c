//! A neural weights file, as `NeuralLaw::from_file` reads it (the CLI's `--weights`,
//! the scene's `friction.weights`, and both FMUs' `resources/` and `weights`
//! parameter): text (`read_to_string`, so UTF-8), then `NeuralLaw::from_json`.
//!
//! A file that loads is then used the ways the crate uses it: written back and re-read,
//! evaluated sample by sample and in a batch at the edges of and outside its training
//! range, and turned into the beam's friction law.
//!
//! Checked properties (a panic is a finding):
//! - nothing panics, whatever the bytes (the loader promises a `NeuralError` instead);
//! - a loaded model writes (`to_json`) text that loads back to the same model;
//! - evaluation accepts every finite feature vector of the right length, one sample at a
//!   time and in a batch, and a batch gives one force per sample.

#![no_main]

use libfuzzer_sys::fuzz_target;
use nalgebra::DMatrix;
use stickslip::neural::{NeuralLaw, NeuralModel};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(law) = NeuralLaw::from_json(text, "fuzz.json") else {
        return;
    };

    let model = law.model().clone();
    let json = model
        .to_json()
        .unwrap_or_else(|e| panic!("a loaded model does not write: {e}"));
    let back = NeuralModel::from_json(&json, "written")
        .unwrap_or_else(|e| panic!("a written model does not load: {e}"));
    assert_eq!(back, model, "a written model loads back different");

    let d = model.features.len();
    let probes: Vec<Vec<f64>> = stickslip_fuzz::probes(&model);
    let mut single = law.clone();
    for x in &probes {
        assert!(
            single.evaluate(x).is_ok(),
            "evaluate refuses a finite vector of {d} features"
        );
    }
    let batch = DMatrix::from_fn(d, probes.len(), |row, col| probes[col][row]);
    let forces = law
        .evaluate_batch(&batch)
        .unwrap_or_else(|e| panic!("evaluate_batch refuses finite features: {e}"));
    assert_eq!(forces.len(), probes.len());
    assert!(single.evaluate(&vec![0.0; d + 1]).is_err());

    if let Ok(mut friction) = law.into_friction_law() {
        for (v, fnormal) in [(0.0, 100.0), (-0.1, 90.0), (1e6, 0.0), (-1e-300, 1e300)] {
            let _ = friction.sliding_force(v, fnormal);
        }
    }
});
