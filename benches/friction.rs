//! Cost of one friction-force evaluation in the time-step loop: the analytical
//! exponential law (paper Eq. 6) against the shipped neural laws (2-100-100-100-1, tanh),
//! measured in the same run; plus the batch path per sample.
//!
//! Criterion measures each law over 20 000 inputs spread over the slip range (group
//! `friction_force_per_call`: one call per input; group `friction_force_batch`: one
//! `evaluate_batch` over all of them), then a table gives the time per call and the ratios
//! to the analytical law from the same run (see `stickslip_tests::bench`).
//!
//! Run: `cargo bench -p stickslip-tests --bench friction`.

use std::hint::black_box;
use std::time::Duration;

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, SamplingMode, Throughput};
use nalgebra::DMatrix;
use stickslip::friction::{exponential::ExponentialLaw, FrictionLaw};
use stickslip::neural::NeuralLaw;
use stickslip_tests::bench::{ratio, shown, table_note, Samples};

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

/// One call of `law.sliding_force` per input; generic, so that the call is direct (as in
/// the hand-rolled loop this replaced) and the analytical law can be inlined.
fn bench_law<L: FrictionLaw + Clone>(
    group: &mut BenchmarkGroup<'_, WallTime>,
    times: &Samples,
    id: &str,
    law: L,
    samples: &[(f64, f64)],
) {
    group.bench_function(id, |b| {
        b.iter_custom(|iters| {
            // A local copy (untimed): the loop then keeps the law's state in registers.
            let mut law = law.clone();
            times.time(id, iters, || {
                let mut sum = 0.0;
                for &(v, f_n) in samples {
                    sum += law.sliding_force(black_box(v), black_box(f_n));
                }
                sum
            })
        })
    });
}

const SAMPLE_SIZE: usize = 20;
const EXPONENTIAL: &str = "exponential (analytical)";
const PLAIN: &str = "neural plain, single";
const SIGNED: &str = "neural signed, single";
const BATCH: &str = "neural plain, batch";

fn main() {
    let mut c = Criterion::default().without_plots().configure_from_args();
    let samples = inputs(20_000);
    let times = Samples::new(SAMPLE_SIZE);
    let exponential = ExponentialLaw {
        static_coefficient: 0.5,
        kinetic_coefficient: 0.2,
        decay: 5.0,
    };
    let plain = NeuralLaw::paper_default().expect("shipped plain weights");
    let signed = NeuralLaw::paper_signed().expect("shipped signed weights");

    // One iteration is one pass over the inputs (the sum keeps the calls alive), so that
    // the loop costs no more than the analytical law's few nanoseconds; criterion's
    // throughput line gives calls per second, the table below the time per call.
    let mut group = c.benchmark_group("friction_force_per_call");
    group
        .sample_size(SAMPLE_SIZE)
        .throughput(Throughput::Elements(samples.len() as u64))
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    bench_law(&mut group, &times, EXPONENTIAL, exponential, &samples);
    bench_law(&mut group, &times, PLAIN, plain.clone(), &samples);
    bench_law(&mut group, &times, SIGNED, signed, &samples);
    group.finish();

    let batch = DMatrix::from_fn(2, samples.len(), |r, c| {
        if r == 0 {
            samples[c].0
        } else {
            samples[c].1
        }
    });
    let mut group = c.benchmark_group("friction_force_batch");
    group
        .sample_size(SAMPLE_SIZE)
        .sampling_mode(SamplingMode::Flat)
        .throughput(Throughput::Elements(samples.len() as u64))
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    group.bench_function(BATCH, |b| {
        b.iter_custom(|iters| {
            times.time(BATCH, iters, || {
                plain.evaluate_batch(black_box(&batch)).expect("batch")
            })
        })
    });
    group.finish();
    c.final_summary();

    let per_call = |id: &str| times.median(id).map(|t| t / samples.len() as f64);
    let analytical = per_call(EXPONENTIAL);
    println!();
    println!(
        "friction force per call ({}), over {} inputs:",
        table_note(&times),
        samples.len()
    );
    println!("  {EXPONENTIAL:<26}{:>10} ns", shown(analytical, 1e9, 1));
    for (id, time) in [
        (PLAIN, per_call(PLAIN)),
        (SIGNED, per_call(SIGNED)),
        (BATCH, per_call(BATCH)),
    ] {
        let per = if id == BATCH { " per sample" } else { "" };
        println!(
            "  {id:<26}{:>10} ns{per}   ({}x analytical)",
            shown(time, 1e9, 1),
            ratio(time, analytical, 0)
        );
    }
    // At dt = 1e-4 s over 1.2 s, one call per step: 12 000 calls.
    println!(
        "  paper run (12 000 steps): analytical {} ms, neural {} ms",
        shown(analytical, 12_000.0 * 1e3, 2),
        shown(per_call(PLAIN), 12_000.0 * 1e3, 2)
    );
}
