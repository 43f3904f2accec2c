//! The network Jacobian against central finite differences of the law as it is
//! evaluated (`NeuralLaw::evaluate_with_velocity_slope`, the time loop's forward pass),
//! at random points of the training box, for both variants, an extra feature and each
//! activation.
//!
//! # Tolerance
//! D_h = (f(x + h) - f(x - h)) / 2h differs from f' by the truncation h^2 f'''/6 (plus
//! O(h^4)) and by the rounding of the two evaluations, at most 2 r / 2h for an
//! evaluation error r. The step is h = 1e-4 standard deviations of the feature (in the
//! network's standardised units the functions vary on scales of 0.01 to 1): the
//! truncation is then ~1e-9 |f'''| and the rounding ~1e4 r.
//! - Truncation: D_2h - D_h = 3 h^2 f'''/6 + O(h^4), so |D_2h - D_h| bounds three times
//!   the truncation of D_h wherever f is smooth on [x - 2h, x + 2h] (points whose
//!   stencil crosses the clamp's edge, v = 0 or the signed variant's cut are skipped).
//! - Rounding: r <= 1000 eps F_scale, F_scale = max(|F|, 1) (a 100-term dot product per
//!   unit through four layers loses far less than 1000 ulp of the output's scale).
//!
//! So |exact - D_h| <= |D_2h - D_h| + 1000 eps F_scale / h, asserted point by point.

use super::*;
use crate::neural::weights::FeatureSpec;

/// xorshift64*: reproducible uniform numbers in [0, 1) without a dependency.
struct Uniform(u64);

impl Uniform {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Evaluates force and slope; panics on an evaluation error (the points are valid).
fn evaluate(law: &mut NeuralLaw, point: &[f64]) -> (f64, f64) {
    law.evaluate_with_velocity_slope(point).unwrap()
}

/// Checks the Jacobian at `samples` random points; returns the largest error relative
/// to its tolerance, and how many derivatives were compared.
fn check(mut law: NeuralLaw, samples: usize, seed: u64) -> (f64, usize) {
    let model = law.model().clone();
    let velocity = model.feature_with_role(FeatureRole::SlidingVelocity);
    let signed = model.variant == Variant::Signed;
    let mut uniform = Uniform(seed);
    let mut worst: f64 = 0.0;
    let mut compared = 0;
    for _ in 0..samples {
        let point: Vec<f64> = model
            .features
            .iter()
            .map(|f| f.min + (f.max - f.min) * uniform.next())
            .collect();
        let exact = law.input_jacobian(&point).unwrap();
        for (k, spec) in model.features.iter().enumerate() {
            let h = 1e-4 * spec.input_std;
            let (lo, hi) = network_input_range(spec, model.variant);
            let magnitude = if signed && Some(k) == velocity {
                point[k].abs()
            } else {
                point[k]
            };
            if magnitude - 3.0 * h < lo || magnitude + 3.0 * h > hi {
                continue;
            }
            let at = |t: f64| {
                let mut p = point.clone();
                p[k] += t * h;
                p
            };
            let values: Vec<(f64, f64)> = [-2.0, -1.0, 1.0, 2.0]
                .iter()
                .map(|&t| evaluate(&mut law, &at(t)))
                .collect();
            if signed && values.iter().any(|(f, _)| *f == 0.0) {
                continue; // the stencil reaches the cut max(0, y)
            }
            let scale = values.iter().map(|(f, _)| f.abs()).fold(1.0, f64::max);
            let rounding = 1000.0 * f64::EPSILON * scale / h;
            let pick = |which: usize, (f, s): (f64, f64)| if which == 0 { f } else { s };
            for (which, derivative) in [(0, exact.force_gradient[k]), (1, exact.slope_gradient[k])]
            {
                let central =
                    |t: usize| (pick(which, values[3 - t]) - pick(which, values[t])) / (2.0 * h);
                let (d_h, d_2h) = (central(1), central(0) / 2.0);
                let tolerance = (d_2h - d_h).abs() + rounding;
                let error = (derivative - d_h).abs();
                assert!(
                    error <= tolerance,
                    "feature {k} ({which}) at {point:?}: exact {derivative}, central {d_h} (2h: {d_2h}), tolerance {tolerance}"
                );
                worst = worst.max(error / tolerance);
                compared += 1;
            }
        }
    }
    (worst, compared)
}

#[test]
fn shipped_networks_match_central_differences() {
    for (law, seed) in [
        (NeuralLaw::paper_default().unwrap(), 7),
        (NeuralLaw::paper_signed().unwrap(), 11),
    ] {
        let variant = law.variant();
        let (worst, compared) = check(law, 200, seed);
        println!("{variant:?}: {compared} derivatives, largest error / tolerance {worst:.3}");
        // Most points have all four derivatives (force and slope, by v and F_n).
        assert!(compared > 600, "{compared}");
    }
}

/// A third feature (a temperature-like input), the sigmoid and the signed variant: the
/// model of the shipped plain network with one more input column. (relu is left out:
/// its slope is piecewise constant, and a stencil across a unit's kink is no test.)
#[test]
fn extra_features_and_activations_match_central_differences() {
    for (variant, activation) in [
        (Variant::Plain, Activation::Sigmoid),
        (Variant::Signed, Activation::Tanh),
    ] {
        let mut model = NeuralLaw::paper_default().unwrap().model().clone();
        model.variant = variant;
        model.activation = activation;
        model.layer_sizes[0] = 3;
        model.features.push(FeatureSpec {
            name: "temperature".into(),
            unit: "K".into(),
            role: FeatureRole::Other,
            input_mean: 300.0,
            input_std: 20.0,
            min: 260.0,
            max: 340.0,
        });
        if variant == Variant::Signed {
            // |v| has its own statistics; the plain network's are a fair stand-in.
            model.target.output_mean = 45.0;
        }
        for (o, row) in model.layers[0].weights.iter_mut().enumerate() {
            row.push(0.3 * ((o * 37 % 11) as f64 / 11.0 - 0.5));
        }
        let law = NeuralLaw::new(model).unwrap();
        let (worst, compared) = check(law, 60, 3);
        println!("{variant:?} {activation:?}: {compared} derivatives, worst {worst:.3}");
        assert!(compared > 200, "{compared}");
    }
}
