//! ONNX import (issue 23): networks exported as PyTorch and skl2onnx write them (by the
//! test encoder `stickslip_tests::onnx`) are imported and evaluate as the network they
//! came from; every refusal names its culprit.
//!
//! The helpers the tests share are here; the tests are in `exports`, `versions`,
//! `refusals` and `weights_files`.

use std::sync::Arc;
use stickslip::friction::FrictionLawKind;
use stickslip::law_source::{LawSource, NetworkOrigin};
use stickslip::neural::inference::Inference;
use stickslip::neural::onnx::{import_onnx, FeatureInfo, OnnxImport, OnnxImportError};
use stickslip::neural::weights::LayerWeights;
use stickslip::neural::{FeatureRole, NeuralLaw, NeuralModel};
use stickslip::scene::Scene;
use stickslip_formats::onnx::{read_onnx, OnnxError, Precision};
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

fn import(onnx: &Onnx) -> Result<NeuralModel, OnnxImportError> {
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

mod exports;
mod refusals;
mod versions;
mod weights_files;
