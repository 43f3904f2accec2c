//! Cost of one friction-force evaluation in the time-step loop: the analytical
//! exponential law (paper Eq. 6) against the shipped neural laws (2-100-100-100-1, tanh),
//! measured in the same run; plus the batch path per sample.
//!
//! Run: `cargo bench --bench friction` (plain `harness = false` main, std::time::Instant,
//! best of several rounds to damp noise from other processes).

use std::hint::black_box;
use std::time::Instant;

use nalgebra::DMatrix;
use stickslip::friction::{ExponentialLaw, FrictionLaw};
use stickslip::neural::NeuralLaw;

/// Sliding velocities (m/s) and normal forces (N) spread over the slip range.
fn inputs(count: usize) -> Vec<(f64, f64)> {
    (0..count)
        .map(|i| {
            let t = i as f64 / count as f64;
            (
                0.001 + 0.05 * t * if i % 2 == 0 { 1.0 } else { -1.0 },
                95.0 + 10.0 * t,
            )
        })
        .collect()
}

/// Best-of-`rounds` nanoseconds per call of `law.sliding_force` over `samples`.
fn time_law(law: &mut dyn FrictionLaw, samples: &[(f64, f64)], rounds: usize) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..rounds {
        let start = Instant::now();
        let mut sum = 0.0;
        for &(v, f_n) in samples {
            sum += law.sliding_force(black_box(v), black_box(f_n));
        }
        black_box(sum);
        best = best.min(start.elapsed().as_nanos() as f64 / samples.len() as f64);
    }
    best
}

fn main() {
    let samples = inputs(20_000);
    let rounds = 7;
    let mut exponential = ExponentialLaw {
        static_coefficient: 0.5,
        kinetic_coefficient: 0.2,
        decay: 5.0,
    };
    let mut plain = NeuralLaw::paper_default().expect("shipped plain weights");
    let mut signed = NeuralLaw::paper_signed().expect("shipped signed weights");
    // Warm-up (page in weights, settle the clock).
    time_law(&mut plain, &samples[..1000], 1);

    let analytical = time_law(&mut exponential, &samples, rounds);
    let plain_ns = time_law(&mut plain, &samples, rounds);
    let signed_ns = time_law(&mut signed, &samples, rounds);

    let batch = DMatrix::from_fn(2, samples.len(), |r, c| {
        if r == 0 {
            samples[c].0
        } else {
            samples[c].1
        }
    });
    let mut batch_ns = f64::INFINITY;
    for _ in 0..3 {
        let start = Instant::now();
        black_box(plain.evaluate_batch(&batch).expect("batch"));
        batch_ns = batch_ns.min(start.elapsed().as_nanos() as f64 / samples.len() as f64);
    }

    println!(
        "friction force per call (best of {rounds} rounds over {} samples):",
        samples.len()
    );
    println!("  exponential (analytical)  {analytical:>10.1} ns");
    println!(
        "  neural plain, single      {plain_ns:>10.1} ns   ({:.0}x analytical)",
        plain_ns / analytical
    );
    println!(
        "  neural signed, single     {signed_ns:>10.1} ns   ({:.0}x analytical)",
        signed_ns / analytical
    );
    println!(
        "  neural plain, batch       {batch_ns:>10.1} ns per sample ({:.0}x analytical)",
        batch_ns / analytical
    );
    // At dt = 1e-4 s over 1.2 s, one call per step: 12 000 calls.
    println!(
        "  paper run (12 000 steps): analytical {:.2} ms, neural {:.2} ms",
        12_000.0 * analytical * 1e-6,
        12_000.0 * plain_ns * 1e-6
    );
}
