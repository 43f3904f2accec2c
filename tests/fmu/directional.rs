//! NeuralFriction's directional derivatives through both C interfaces, as an importer
//! calls them: the Jacobian of every output with respect to every input against central
//! differences of the outputs read with fmi2GetReal / fmi3GetFloat64, at quasi-random
//! points of the training domain, for the shipped plain and signed networks, a network that
//! reads all four extra features, and the exponential law; the clamp (derivative 0
//! outside the domain); and the declared dependencies. The refusals are in
//! `directional_errors`.
//!
//! # Tolerance
//! D_h = (y(x + h) - y(x - h)) / 2h differs from y' by the truncation h^2 y'''/6 +
//! O(h^4) and by the rounding of the two outputs, 2 r / 2h for an output error r.
//! h = 1e-4 standard deviations of the input (the network's standardised unit).
//! Truncation: D_2h - D_h = 3 h^2 y'''/6 + O(h^4), so |D_2h - D_h| bounds three times the
//! truncation of D_h where y is smooth over the stencil (a stencil on which the force
//! changes sign or is 0 crosses the jump at v = 0, the kink of |F| or the signed cut,
//! and is skipped). Rounding: r <= 1000 eps Y, Y = max(|y| over the stencil, 1), far
//! above what a 3 x 100 network's sums lose. Asserted: |exact - D_h| <= |D_2h - D_h| +
//! 1000 eps Y / h, output by output.

mod fmu;

use fmu::INPUTS;
pub(crate) use fmu::{outputs, Fmu, ERROR, OK};
use stickslip::neural::NeuralModel;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::friction::{NeuralFriction, EXTRA_FEATURE_ARRAY};
use stickslip_fmi::model::Model;
use stickslip_fmi::variables::Causality;

/// Quasi-random points in [0, 1)^6: the Weyl sequence frac(n sqrt(p_k)) of the first
/// six primes, starting at `start` (equidistributed, so the samples cover the domain).
fn weyl(n: u64, k: usize) -> f64 {
    const PRIMES: [f64; 6] = [2.0, 3.0, 5.0, 7.0, 11.0, 13.0];
    (n as f64 * PRIMES[k].sqrt()).fract()
}

/// Per input: the sampling range and the standardised unit (from the network; the
/// exponential law uses the shipped plain network's domain), unused inputs (0, 0, 1).
fn domain(model: &NeuralModel, inputs: usize) -> Vec<(f64, f64, f64)> {
    (0..6)
        .map(|j| match model.features.get(j).filter(|_| j < inputs) {
            Some(f) => (f.min, f.max, f.input_std),
            None => (0.0, 0.0, 1.0),
        })
        .collect()
}

/// Checks the Jacobian against central differences at `samples` quasi-random points
/// (Weyl sequence from index `start`); returns how many derivatives were compared and
/// the largest error / tolerance.
unsafe fn check(
    fmu: &Fmu,
    model: &NeuralModel,
    inputs: usize,
    samples: u64,
    start: u64,
) -> (usize, f64) {
    let box_ = domain(model, inputs);
    let (mut compared, mut worst) = (0, 0.0f64);
    for n in start..start + samples {
        let mut x = [0.0; 6];
        for (j, (lo, hi, std)) in box_.iter().enumerate() {
            let margin = 3e-4 * std;
            x[j] = if hi > lo {
                lo + margin + (hi - lo - 2.0 * margin) * weyl(n, j)
            } else {
                0.0
            };
        }
        unsafe { fmu.set(&x) };
        let columns: Vec<Vec<f64>> = (0..inputs).map(|j| unsafe { fmu.column(j) }).collect();
        for j in 0..inputs {
            let h = 1e-4 * box_[j].2;
            let stencil: Vec<Vec<f64>> = [-2.0, -1.0, 1.0, 2.0]
                .iter()
                .map(|t| {
                    let mut p = x;
                    p[j] += t * h;
                    unsafe {
                        fmu.set(&p);
                        fmu.outputs()
                    }
                })
                .collect();
            unsafe { fmu.set(&x) };
            let force_signs: Vec<f64> = stencil
                .iter()
                .map(|y| y[0].signum() * (y[0] != 0.0) as u8 as f64)
                .collect();
            if force_signs
                .iter()
                .any(|s| *s != force_signs[0] || *s == 0.0)
            {
                continue;
            }
            for (o, exact) in columns[j].iter().enumerate() {
                let scale = stencil.iter().map(|y| y[o].abs()).fold(1.0, f64::max);
                let d_h = (stencil[2][o] - stencil[1][o]) / (2.0 * h);
                let d_2h = (stencil[3][o] - stencil[0][o]) / (4.0 * h);
                let tolerance = (d_2h - d_h).abs() + 1000.0 * f64::EPSILON * scale / h;
                let error = (exact - d_h).abs();
                assert!(
                    error <= tolerance,
                    "output {} along input {} at {x:?}: exact {exact}, central {d_h} (2h {d_2h}), tolerance {tolerance}",
                    outputs()[o],
                    INPUTS[j]
                );
                worst = worst.max(error / tolerance);
                compared += 1;
            }
        }
    }
    (compared, worst)
}

fn shipped(name: &str) -> NeuralModel {
    NeuralModel::load(&stickslip_tests::weights_dir().join(name)).unwrap()
}

#[test]
fn shipped_networks_match_central_differences_in_both_versions() {
    for (weights, seed) in [("paper-plain.json", 5), ("paper-signed.json", 9)] {
        let model = shipped(weights);
        for three in [false, true] {
            let fmu = unsafe { Fmu::new(three, weights, NeuralFrictionLaw::NEURAL, true) };
            let (compared, worst) = unsafe { check(&fmu, &model, 2, 100, seed) };
            println!(
                "{weights} FMI {}: {compared} derivatives, worst error / tolerance {worst:.3}",
                if three { "3.0" } else { "2.0" }
            );
            // 6 outputs x 2 inputs at most points (a few stencils cross v = 0).
            assert!(compared > 1000, "{compared}");
        }
    }
}

#[test]
fn every_extra_feature_and_the_exponential_law_match_central_differences() {
    let path = stickslip_tests::six_feature_weights("directional");
    let model = NeuralModel::load(&path).unwrap();
    for three in [false, true] {
        let fmu = unsafe {
            Fmu::new(
                three,
                path.to_str().unwrap(),
                NeuralFrictionLaw::NEURAL,
                true,
            )
        };
        let (compared, _) = unsafe { check(&fmu, &model, 6, 30, 13) };
        assert!(compared > 900, "{compared}");
        let fmu = unsafe {
            Fmu::new(
                three,
                "paper-plain.json",
                NeuralFrictionLaw::EXPONENTIAL,
                true,
            )
        };
        let (compared, _) = unsafe { check(&fmu, &shipped("paper-plain.json"), 2, 30, 17) };
        assert!(compared > 300, "{compared}");
    }
    std::fs::remove_file(path).ok();
}

/// Both versions give the same numbers, and an FMI 3.0 seed over several knowns (a
/// scalar and the array) is the matching combination of the columns (linearity).
#[test]
fn both_versions_agree_and_seeds_combine_linearly() {
    let path = stickslip_tests::six_feature_weights("directional-linear");
    let weights = path.to_str().unwrap();
    let (two, three) = unsafe {
        (
            Fmu::new(false, weights, NeuralFrictionLaw::NEURAL, true),
            Fmu::new(true, weights, NeuralFrictionLaw::NEURAL, true),
        )
    };
    let x = [0.07, 101.0, 0.3, -0.2, 0.5, 0.1];
    unsafe {
        two.set(&x);
        three.set(&x);
        for (j, input) in INPUTS.iter().enumerate() {
            assert_eq!(two.column(j), three.column(j), "input {input}");
        }
        let seed = [0.5, 2.0, -1.0, 0.25, 3.0];
        let (status, combined) = three.derivative(&outputs(), &[10, EXTRA_FEATURE_ARRAY], &seed);
        assert_eq!(status, OK);
        let columns: Vec<Vec<f64>> = [0, 2, 3, 4, 5].iter().map(|&j| two.column(j)).collect();
        for (o, value) in combined.iter().enumerate() {
            let expected: f64 = columns.iter().zip(seed).map(|(c, s)| c[o] * s).sum();
            assert!(
                (value - expected).abs() <= 1e-12 * (1.0 + expected.abs()),
                "{value} {expected}"
            );
        }
    }
    std::fs::remove_file(path).ok();
}

/// Outside the training domain the clamped input has derivative 0; what does not go
/// through the network keeps its own derivative (the coefficient's -|F| / F_n^2, the
/// static limit's mu_s). Every non-zero derivative is a declared dependency.
#[test]
fn clamped_inputs_and_declared_dependencies() {
    let model = shipped("paper-plain.json");
    let fmu = unsafe { Fmu::new(false, "paper-plain.json", NeuralFrictionLaw::NEURAL, true) };
    let column = |x: [f64; 6], j: usize| unsafe {
        fmu.set(&x);
        fmu.column(j)
    };
    let fast = column([model.features[0].max + 1.0, 100.0, 0.0, 0.0, 0.0, 0.0], 0);
    assert_eq!(
        (fast[0], fast[4]),
        (0.0, 0.0),
        "force and slope along v beyond the domain"
    );
    let heavy = column([0.1, model.features[1].max + 50.0, 0.0, 0.0, 0.0, 0.0], 1);
    let y = unsafe { fmu.outputs() };
    assert_eq!(heavy[0], 0.0, "force along F_n beyond the domain");
    let normal = model.features[1].max + 50.0;
    assert!((heavy[2] + y[0].abs() / (normal * normal)).abs() < 1e-15);
    assert_eq!(heavy[3], 0.5, "static limit: mu_s");
    let path = stickslip_tests::six_feature_weights("directional-deps");
    let all = unsafe {
        Fmu::new(
            false,
            path.to_str().unwrap(),
            NeuralFrictionLaw::NEURAL,
            true,
        )
    };
    unsafe { all.set(&[0.05, 99.0, 0.1, 0.2, -0.3, 0.4]) };
    for (j, &input) in INPUTS.iter().enumerate() {
        let column = unsafe { all.column(j) };
        for (variable, d) in NeuralFriction::variables()
            .iter()
            .filter(|v| v.causality == Causality::Output)
            .zip(column)
        {
            let declared = variable
                .depends_on
                .as_ref()
                .unwrap()
                .inputs
                .iter()
                .any(|(i, _)| *i == input);
            assert!(
                declared || d == 0.0,
                "{} along {input}: {d}, not declared",
                variable.name
            );
        }
    }
    std::fs::remove_file(path).ok();
}
