//! Inference of the shipped networks as the beam's friction law: the force's exact slope
//! (forward mode through the network) that the slip solve's Newton iteration uses, and
//! the faster evaluations (`friction.inference`): the f32 network and the table, each
//! against the exact network, and the refusal of what the table cannot cover.

use std::sync::Arc;
use stickslip::friction::FrictionLaw;
use stickslip::law_source::{LawSource, NetworkOrigin};
use stickslip::neural::inference::Inference;
use stickslip::neural::table::{TableLaw, TABLE_TOLERANCE};
use stickslip::neural::NeuralLaw;
use stickslip::neural::SceneLawError;

fn shipped() -> [(&'static str, NeuralLaw); 2] {
    [
        ("plain", NeuralLaw::paper_default().unwrap()),
        ("signed", NeuralLaw::paper_signed().unwrap()),
    ]
}

/// dF/dv by forward mode against a central difference (F(v + h) - F(v - h)) / 2h at
/// h = 1e-7 m/s. The difference's error is F^(3) h^2 / 6 + eps |F| / h: the plain
/// network's zero crossing is steep (slopes up to ~1e6 N s/m over ~1e-3 m/s, so F^(3) up
/// to ~1e12 N s^3/m^3), giving up to ~1e-3 N s/m, and rounding ~1e-7 N s/m: 1e-6
/// relative plus 1e-5 N s/m bounds both. The force is the same number as
/// `sliding_force`'s.
#[test]
fn network_slope_is_the_derivative_of_the_force() {
    let h = 1e-7;
    for (name, mut law) in shipped() {
        for v in [-0.35, -0.05, -2e-3, -1e-4, 1e-4, 5e-4, 0.02, 0.2, 0.39] {
            for f_n in [92.0, 100.0, 108.0] {
                let (force, slope) = law.sliding_force_and_slope(v, f_n);
                assert_eq!(
                    force.to_bits(),
                    law.sliding_force(v, f_n).to_bits(),
                    "{name} v {v}"
                );
                let difference =
                    (law.sliding_force(v + h, f_n) - law.sliding_force(v - h, f_n)) / (2.0 * h);
                assert!(
                    (slope - difference).abs() <= 1e-6 * slope.abs() + 1e-5,
                    "{name} v {v} F_n {f_n}: slope {slope}, difference {difference}"
                );
            }
        }
        // Clamped to the training range (|v| <= 0.4 m/s): flat beyond it.
        let (_, slope) = law.sliding_force_and_slope(0.6, 100.0);
        assert_eq!(slope, 0.0, "{name}");
    }
    // The plain network's smoothed jump is steep at v = 0, the signed one's magnitude
    // falls there like the paper's law, -alpha (mu_s - mu_k) F_n = -150 N s/m.
    let [(_, mut plain), (_, mut signed)] = shipped();
    assert!(plain.sliding_force_and_slope(0.0, 100.0).1 > 1e4);
    let (force, slope) = signed.sliding_force_and_slope(0.0, 100.0);
    assert_eq!(force, 0.0);
    assert!((slope + 150.0).abs() < 15.0, "{slope}");
}

/// The table's largest error, verified when it is built (at 1/8, 3/8, 5/8 and 7/8 of
/// every interval), against dense sampling: 40 001 velocities across the training range
/// and beyond it (the table is constant there, as the clamped network), at the normal
/// force the table was built for; then the table over velocity x normal force, built on
/// the first call at another force, at 21 forces. The refinement looks at other points
/// (1/4, 1/2, 3/4), so neither sample set is the one the table was fitted to. Dense
/// sampling may find a little more than the verified points: at most 1.5 times it. The
/// table at the built force meets TABLE_TOLERANCE; its slope is the derivative of its
/// value (central difference of the table itself).
#[test]
fn table_error_is_verified_against_dense_sampling() {
    for (name, law) in shipped() {
        let mut exact = law.clone();
        let mut table = TableLaw::build(law, 100.0);
        let verified = table.largest_error();
        assert!(verified <= TABLE_TOLERANCE, "{name}: {verified}");
        let mut dense: f64 = 0.0;
        for i in 0..=40_000 {
            let v = -0.5 + i as f64 * 1e-3 / 40.0;
            let (force, slope) = table.sliding_force_and_slope(v, 100.0);
            dense = dense.max((force - exact.sliding_force(v, 100.0)).abs());
            if v.abs() > 1e-6 && v.abs() < 0.38 {
                let h = 1e-8;
                let difference = (table.sliding_force(v + h, 100.0)
                    - table.sliding_force(v - h, 100.0))
                    / (2.0 * h);
                assert!(
                    (slope - difference).abs() <= 1e-5 * slope.abs() + 1e-4,
                    "{name} v {v}: {slope} vs {difference}"
                );
            }
        }
        println!(
            "{name}: table at 100 N, {} nodes: verified {verified:.2e} N, dense {dense:.2e} N",
            table.fixed().nodes()
        );
        assert!(
            dense <= 1.5 * verified,
            "{name}: dense {dense}, verified {verified}"
        );

        let general = table.general().clone();
        let verified = general.largest_error();
        let mut dense: f64 = 0.0;
        for j in 0..=20 {
            let f_n = 89.0 + j as f64 * 1.1;
            for i in 0..=4_000 {
                let v = -0.42 + i as f64 * 0.84 / 4000.0;
                let force = table.sliding_force(v, f_n);
                dense = dense.max((force - exact.sliding_force(v, f_n)).abs());
            }
        }
        println!(
            "{name}: table over velocity x normal force, {} nodes x {} rows: verified {verified:.2e} N, dense {dense:.2e} N",
            general.nodes(),
            general.rows()
        );
        assert!(
            dense <= 1.5 * verified,
            "{name}: dense {dense}, verified {verified}"
        );
        assert_eq!(
            table.largest_error(),
            verified.max(table.fixed().largest_error())
        );
    }
}

/// The f32 network against a forward error bound of its arithmetic, on 200 x 11 points of
/// the training range (its build measured its deviation on 64 x 16 others). With
/// u = 2^-24 and a = the exact activations, per layer
/// z = W a + b carries the error propagated from a, |W| e (1 + u), plus the rounding of
/// the weights and biases to f32 (u) and of the n-term fused sum, gamma_n = n u /
/// (1 - n u): (u + gamma_(n+1)) (|W| |a| + |b|); tanh adds its own 3 ulp and passes
/// the rest on with slope <= 1. The force is mean + std z. The bound is a worst case
/// (every rounding the same way): the errors found are below 1e-3 of it. The deviation
/// measured at build (f32_deviation) stays within a factor 2 of the largest found here.
#[test]
fn f32_network_stays_within_its_rounding_bound() {
    let u = f64::powi(2.0, -24);
    let gamma = |n: usize| n as f64 * u / (1.0 - n as f64 * u);
    for (name, law) in shipped() {
        let mut exact = law.clone();
        let model = law.model().clone();
        let mut single = law.in_f32();
        let deviation = single.f32_deviation().expect("measured at build");
        let mut worst: f64 = 0.0;
        let mut worst_ratio: f64 = 0.0;
        // Inside the training range (no clamping), where the law's inputs are the
        // standardised (|v| for the signed variant, F_n).
        let signed = model.variant == stickslip::neural::Variant::Signed;
        for i in 0..200 {
            for j in 0..=10 {
                let v = -0.38 + 0.76 * (i as f64 + 0.5) / 200.0;
                let f_n = 91.0 + 1.8 * j as f64;
                let raw = [if signed { v.abs() } else { v }, f_n];
                let mut a: Vec<f64> = Vec::new();
                let mut e: Vec<f64> = Vec::new();
                for (value, feature) in raw.iter().zip(&model.features) {
                    let x = (value - feature.input_mean) / feature.input_std;
                    a.push(x);
                    e.push(u * x.abs());
                }
                let last = model.layers.len() - 1;
                let mut z_error = 0.0;
                for (l, layer) in model.layers.iter().enumerate() {
                    let n = a.len();
                    let mut next_a = Vec::new();
                    let mut next_e = Vec::new();
                    for (row, bias) in layer.weights.iter().zip(&layer.biases) {
                        let z: f64 = bias + row.iter().zip(&a).map(|(w, x)| w * x).sum::<f64>();
                        let magnitude: f64 = bias.abs()
                            + row.iter().zip(&a).map(|(w, x)| (w * x).abs()).sum::<f64>();
                        let propagated: f64 = row
                            .iter()
                            .zip(&e)
                            .map(|(w, err)| w.abs() * err)
                            .sum::<f64>()
                            * (1.0 + u);
                        let error = propagated + (u + gamma(n + 1)) * magnitude;
                        if l == last {
                            z_error = error;
                        } else {
                            let t = stickslip::elementary::tanh(z);
                            next_a.push(t);
                            next_e.push(error + 6.0 * u * t.abs());
                        }
                    }
                    a = next_a;
                    e = next_e;
                }
                let bound = model.target.output_std * z_error * 1.001 + 1e-12;
                let error = (single.sliding_force(v, f_n) - exact.sliding_force(v, f_n)).abs();
                assert!(
                    error <= bound,
                    "{name} v {v} F_n {f_n}: error {error:e} N, bound {bound:e} N"
                );
                worst = worst.max(error);
                worst_ratio = worst_ratio.max(error / bound);
            }
        }
        println!("{name}: f32 against exact: largest {worst:.2e} N (build: {deviation:.2e} N), at most {worst_ratio:.1e} of the bound");
        assert!(
            worst <= 2.0 * deviation,
            "{name}: {worst} against the build's {deviation}"
        );
    }
}

/// The table has two inputs: a network with a third (even one the beam could fix) is
/// refused with the reason and what to use instead; exact and f32 refuse it as a
/// friction law of the beam (the beam does not supply the temperature).
#[test]
fn a_network_with_more_inputs_than_the_table_is_refused() {
    let law = NeuralLaw::from_json(&stickslip_tests::three_input_weights(), "three.json").unwrap();
    let message = friction_law(law.clone(), Inference::Table, 100.0)
        .err()
        .expect("refused")
        .to_string();
    assert!(
        message.contains("friction.inference = table")
            && message.contains("two inputs")
            && message.contains("reads 3")
            && message.contains("temperature")
            && message.contains("use exact or f32"),
        "{message}"
    );
    let fixed = law.clone().with_fixed_feature("temperature", 25.0).unwrap();
    assert!(friction_law(fixed.clone(), Inference::Table, 100.0).is_err());
    assert!(friction_law(fixed, Inference::F32, 100.0).is_ok());
    let message = friction_law(law, Inference::F32, 100.0)
        .err()
        .expect("refused")
        .to_string();
    assert!(message.contains("temperature"), "{message}");
}

/// A network as the beam's law through its law source, evaluated as `inference` asks.
fn friction_law(
    law: NeuralLaw,
    inference: Inference,
    normal_force: f64,
) -> Result<Box<dyn FrictionLaw>, SceneLawError> {
    LawSource::network(
        Arc::new(law),
        NetworkOrigin::Weights("three.json".into()),
        inference,
        normal_force,
    )
    .law()
}

/// `auto` caches its choice by the law's fingerprint: a network whose fixed feature has
/// another value computes other forces, so it must be another entry; the same network
/// loaded twice (another `Arc`, another file name) is the same entry.
#[test]
fn the_law_fingerprint_tells_fixed_feature_values_apart() {
    let law = NeuralLaw::from_json(&stickslip_tests::three_input_weights(), "three.json").unwrap();
    let source = |law: NeuralLaw, name: &str| {
        LawSource::network(
            Arc::new(law),
            NetworkOrigin::Weights(name.into()),
            Inference::Exact,
            100.0,
        )
        .fingerprint()
        .expect("a serialisable network has a fingerprint")
    };
    let at = |value| {
        law.clone()
            .with_fixed_feature("temperature", value)
            .unwrap()
    };
    assert_ne!(source(at(25.0), "a.json"), source(at(80.0), "a.json"));
    assert_eq!(source(at(25.0), "a.json"), source(at(25.0), "b.json"));
    assert_ne!(source(law.clone(), "a.json"), source(at(25.0), "a.json"));
}
