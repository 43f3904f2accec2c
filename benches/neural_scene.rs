//! The paper scene with the neural friction law against the analytical law (Eq. 6), at
//! modal, beam and plane-stress fidelity, measured in the same run, for the plain and
//! the signed network, each evaluated exactly, in f32 and from the table
//! (`friction.inference`); and where the time of a neural run goes.
//!
//! Criterion times whole runs of the stepping (1.2 s, 12 000 steps of 1e-4 s): the
//! `Simulator` is built outside the timing (model, factorisation, network parsing), so
//! the ratio is that of the time loop the issue is about. Group `neural_scene`, one
//! benchmark per (fidelity, law), ten samples of one run each (flat sampling). Then:
//!
//! - a table of the median wall times and of neural / analytical per fidelity;
//! - where the time goes: the law evaluations each run makes (counted in an untimed run
//!   through `Simulator::last_slip_solve`), times the cost of one evaluation of force
//!   and slope measured here too (group `law_call`, over 20 000 velocities spread over
//!   the slip range at the scene's 100 N), against the run's extra time over the
//!   analytical run; and the cost of reading the network's weights once, the memory
//!   bound of an f64 evaluation.
//!
//! Run: `cargo bench -p stickslip-tests --bench neural_scene` (about a minute once
//! built); `-- modal` or `-- beam` for one fidelity.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, SamplingMode, Throughput};
use std::sync::Arc;
use stickslip::choice::Choice;
use stickslip::friction::FrictionLaw;
use stickslip::law_source::{LawSource, NetworkOrigin};
use stickslip::neural::inference::Inference;
use stickslip::neural::NeuralLaw;
use stickslip::scene::{CheckedScene, FidelityLevel, Scene};
use stickslip::simulation::Simulator;
use stickslip_tests::bench::{ratio, shown, table_note, Samples};

const SAMPLE_SIZE: usize = 10;
const READ: &str = "read the weights";

/// The laws compared: the analytical one, or a shipped network (signed or plain) and
/// its evaluation.
#[derive(Clone, Copy, PartialEq)]
enum Law {
    Analytical,
    Neural { signed: bool, inference: Inference },
}

impl Law {
    const ALL: [Law; 7] = [
        Law::Analytical,
        Law::neural(false, Inference::Exact),
        Law::neural(true, Inference::Exact),
        Law::neural(false, Inference::F32),
        Law::neural(true, Inference::F32),
        Law::neural(false, Inference::Table),
        Law::neural(true, Inference::Table),
    ];

    const fn neural(signed: bool, inference: Inference) -> Law {
        Law::Neural { signed, inference }
    }

    fn name(self) -> String {
        match self {
            Law::Analytical => "analytical".into(),
            Law::Neural { signed, inference } => format!(
                "{} {}",
                if signed { "signed" } else { "plain" },
                inference.name()
            ),
        }
    }

    fn build(self, scene: &CheckedScene) -> Box<dyn FrictionLaw> {
        match self {
            Law::Analytical => Box::new(scene.friction.exponential_law()),
            Law::Neural { signed, inference } => {
                let law = if signed {
                    NeuralLaw::paper_signed()
                } else {
                    NeuralLaw::paper_default()
                }
                .expect("shipped weights");
                LawSource::network(
                    Arc::new(law),
                    NetworkOrigin::Shipped,
                    inference,
                    scene.loading.normal_force,
                )
                .law()
                .expect("a friction law")
            }
        }
    }
}

/// The paper scene at `level` (its default resolution: 10 modes, 100 beam elements, the
/// 0.02 m mesh).
fn scene(level: FidelityLevel) -> CheckedScene {
    let mut scene = Scene::default();
    scene.fidelity.level = level;
    scene.check().expect("paper scene")
}

/// A simulator ready to step, and the steps of the whole run.
fn simulator(scene: &CheckedScene, law: Law) -> (Simulator, u64) {
    let steps = (scene.time.end / scene.time.step).round() as u64;
    let sim = Simulator::new(scene.clone(), law.build(scene)).expect("simulator");
    (sim, steps)
}

/// Law evaluations and slip steps of one whole run.
fn evaluations(scene: &CheckedScene, law: Law) -> (usize, usize) {
    let (mut sim, steps) = simulator(scene, law);
    let (mut evaluations, mut slips) = (0, 0);
    for _ in 0..steps {
        sim.step().expect("step");
        if let Some(solve) = sim.last_slip_solve() {
            evaluations += solve.evaluations;
            slips += 1;
        }
    }
    (evaluations, slips)
}

fn id(level: FidelityLevel, law: Law) -> String {
    format!("{level:?}, {}", law.name())
}

fn neural_laws() -> impl Iterator<Item = Law> {
    Law::ALL.into_iter().filter(|l| *l != Law::Analytical)
}

fn main() {
    let mut c = Criterion::default().without_plots().configure_from_args();
    let times = Samples::new(SAMPLE_SIZE);
    let levels = [
        FidelityLevel::Modal,
        FidelityLevel::Beam,
        FidelityLevel::PlaneStress,
    ];

    let mut group = c.benchmark_group("neural_scene");
    group
        .sample_size(SAMPLE_SIZE)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    for level in levels {
        let scene = scene(level);
        for law in Law::ALL {
            let id = id(level, law);
            group.bench_function(&id, |b| {
                b.iter_custom(|iters| {
                    let mut total = Duration::ZERO;
                    for _ in 0..iters {
                        let (mut sim, steps) = simulator(&scene, law);
                        let start = Instant::now();
                        for _ in 0..steps {
                            sim.step().expect("step");
                        }
                        total += start.elapsed();
                        black_box(sim.sample());
                    }
                    times.record(&id, total.as_secs_f64() / iters.max(1) as f64);
                    total
                })
            });
        }
    }
    group.finish();

    // One evaluation of force and slope, as the slip solve makes it: over the slip range
    // of velocities, at the scene's normal force (the table's).
    let inputs: Vec<(f64, f64)> = (0..20_000)
        .map(|i| {
            let t = i as f64 / 20_000.0;
            let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
            (sign * (0.001 + 0.05 * t), 100.0)
        })
        .collect();
    let paper = scene(FidelityLevel::Modal);
    let mut group = c.benchmark_group("law_call");
    group
        .sample_size(SAMPLE_SIZE)
        .throughput(Throughput::Elements(inputs.len() as u64))
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    // The bound on a network evaluation: reading its weights once (all 20 601 parameters
    // of the shipped networks, 161 KB in f64, from wherever they sit between calls),
    // with eight partial sums so that the additions keep up with the loads.
    let weights = NeuralLaw::paper_default()
        .expect("shipped plain weights")
        .model()
        .parameters();
    group.bench_function(READ, |b| {
        b.iter_custom(|iters| {
            times.time(READ, iters, || {
                let mut sum = [0.0; 8];
                for _ in 0..inputs.len() {
                    for chunk in black_box(&weights).chunks_exact(8) {
                        for k in 0..8 {
                            sum[k] += chunk[k];
                        }
                    }
                }
                sum
            })
        })
    });
    for law in Law::ALL {
        let id = format!("call, {}", law.name());
        group.bench_function(&id, |b| {
            b.iter_custom(|iters| {
                let mut law = law.build(&paper);
                times.time(&id, iters, || {
                    let mut sum = 0.0;
                    for &(v, f_n) in &inputs {
                        let (force, slope) =
                            law.sliding_force_and_slope(black_box(v), black_box(f_n));
                        sum += force + slope;
                    }
                    sum
                })
            })
        });
    }
    group.finish();
    c.final_summary();

    let per_call = |law: Law| {
        times
            .median(&format!("call, {}", law.name()))
            .map(|t| t / inputs.len() as f64)
    };
    println!();
    println!(
        "paper scene, 12 000 steps, stepping only ({})",
        table_note(&times)
    );
    println!("wall time (s) and neural / analytical:");
    print!("{:<13} {:>11}", "fidelity", "analytical");
    for law in neural_laws() {
        print!(" {:>21}", law.name());
    }
    println!();
    for level in levels {
        let time = |law| times.median(&id(level, law));
        let analytical = time(Law::Analytical);
        print!(
            "{:<13} {:>11}",
            format!("{level:?}"),
            shown(analytical, 1.0, 4)
        );
        for law in neural_laws() {
            let cell = format!(
                "{} ({}x)",
                shown(time(law), 1.0, 4),
                ratio(time(law), analytical, 2)
            );
            print!(" {cell:>21}");
        }
        println!();
    }
    println!();
    println!(
        "one evaluation of force and slope (median over {} inputs):",
        inputs.len()
    );
    for law in Law::ALL {
        println!(
            "  {:<17} {:>8} ns   ({}x analytical)",
            law.name(),
            shown(per_call(law), 1e9, 1),
            ratio(per_call(law), per_call(Law::Analytical), 1)
        );
    }
    let read = times.median(READ).map(|t| t / inputs.len() as f64);
    println!(
        "  {:<17} {:>8} ns   (the network's {} KB of weights, once: the bound in f64)",
        READ,
        shown(read, 1e9, 0),
        weights.len() * 8 / 1000
    );
    println!();
    println!("where a neural run's time goes: law evaluations x time per evaluation, against the run's time over the analytical run");
    println!(
        "{:<13} {:<14} {:>11} {:>12} {:>14} {:>16}",
        "fidelity", "law", "slip steps", "evaluations", "law time (s)", "extra time (s)"
    );
    for level in levels {
        let scene = scene(level);
        let analytical = times.median(&id(level, Law::Analytical));
        for law in neural_laws() {
            let (evaluations, slips) = evaluations(&scene, law);
            let extra = times
                .median(&id(level, law))
                .zip(analytical)
                .map(|(t, a)| t - a);
            println!(
                "{:<13} {:<14} {:>11} {:>12} {:>14} {:>16}",
                format!("{level:?}"),
                law.name(),
                slips,
                evaluations,
                shown(per_call(law).map(|t| t * evaluations as f64), 1.0, 4),
                shown(extra, 1.0, 4),
            );
        }
    }
}
