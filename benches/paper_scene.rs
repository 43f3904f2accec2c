//! Wall time of the paper scene (1.2 s, dt = 1e-4 s, analytical friction) at each
//! fidelity level, as a real-time factor, and the banded solver against a dense
//! Cholesky on the same effective matrix, measured in the same run.
//!
//! Criterion groups: `paper_scene` (one whole run per iteration, per model),
//! `effective_matrix_factorisation` and `effective_matrix_solve` (banded and dense);
//! then tables of the real-time factors and of dense / banded from the same run (see
//! `stickslip_tests::bench`).
//!
//! Run: `cargo bench -p stickslip-tests --bench paper_scene`.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, SamplingMode};
use stickslip::law_source::LawSource;
use stickslip::run::run_scene;
use stickslip::scene::{FidelityLevel, Scene};
use stickslip::structure::StructuralModel;
use stickslip_tests::bench::{ratio, shown, table_note, Samples};

const SAMPLE_SIZE: usize = 10;

/// A group of costly routines: a few iterations per sample, each sample the same count
/// (flat sampling), a short warm-up, `seconds` of measurement.
fn flat_group<'a>(c: &'a mut Criterion, name: &str, seconds: u64) -> BenchmarkGroup<'a, WallTime> {
    let mut group = c.benchmark_group(name);
    group
        .sample_size(SAMPLE_SIZE)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(seconds));
    group
}

fn main() {
    let mut c = Criterion::default().without_plots().configure_from_args();
    let times = Samples::new(SAMPLE_SIZE);

    let cases: [(FidelityLevel, usize, f64); 6] = [
        (FidelityLevel::Modal, 100, 0.02),
        (FidelityLevel::Beam, 20, 0.02),
        (FidelityLevel::Beam, 100, 0.02),
        (FidelityLevel::PlaneStress, 100, 0.04),
        (FidelityLevel::PlaneStress, 100, 0.02),
        (FidelityLevel::PlaneStress, 100, 0.01),
    ];
    let mut models = Vec::new();
    // A run takes 15 ms (modal) to about 2 s (the finest plane-stress mesh).
    let mut group = flat_group(&mut c, "paper_scene", 2);
    for (level, elements, size) in cases {
        let mut scene = Scene::default();
        scene.fidelity.level = level;
        scene.fidelity.beam_elements = elements;
        scene.fidelity.element_size = size;
        let checked = scene.check().unwrap();
        let law = LawSource::resolve(&checked).unwrap();
        let model = StructuralModel::build(&checked).unwrap();
        let id = model.label.clone();
        group.bench_function(&id, |b| {
            b.iter_custom(|iters| {
                times.time(&id, iters, || run_scene(checked.clone(), &law, 1).unwrap())
            })
        });
        models.push((id, model.dofs(), checked.time.end));
    }
    group.finish();

    // Solver choice: factorisation and one solve, banded against dense (nalgebra), on the
    // plane-stress effective matrix at the paper's mesh.
    let checked = Scene::default().check().unwrap();
    let model = StructuralModel::plane_stress(&checked, 0.02);
    let n = model.dofs();
    let s = model
        .mass
        .linear_combination(1.0 / (0.25 * 1e-8), &model.stiffness, 1.0);
    let rhs: Vec<f64> = (0..n)
        .map(|i| stickslip::elementary::sin(i as f64))
        .collect();
    let factor = s.cholesky().unwrap();
    let dense = nalgebra::DMatrix::from_fn(n, n, |i, j| s.get(i, j));
    let dense_chol = dense.clone().cholesky().unwrap();
    let b_dense = nalgebra::DVector::from_vec(rhs.clone());

    let mut group = flat_group(&mut c, "effective_matrix_factorisation", 1);
    group.bench_function("banded", |b| {
        b.iter_custom(|iters| times.time("factor banded", iters, || s.cholesky().unwrap()))
    });
    // The copy the dense factorisation consumes is made outside the timing.
    group.bench_function("dense", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let copy = dense.clone();
                let start = Instant::now();
                black_box(copy.cholesky().unwrap());
                total += start.elapsed();
            }
            times.record("factor dense", total.as_secs_f64() / iters as f64);
            total
        })
    });
    group.finish();

    let mut group = c.benchmark_group("effective_matrix_solve");
    group
        .sample_size(SAMPLE_SIZE)
        .warm_up_time(Duration::from_millis(200))
        .measurement_time(Duration::from_secs(1));
    group.bench_function("banded", |b| {
        b.iter_custom(|iters| {
            times.time("solve banded", iters, || {
                let mut x = rhs.clone();
                factor.solve_in_place(&mut x);
                x
            })
        })
    });
    group.bench_function("dense", |b| {
        b.iter_custom(|iters| times.time("solve dense", iters, || dense_chol.solve(&b_dense)))
    });
    group.finish();
    c.final_summary();

    println!();
    println!(
        "paper scene, 12 000 steps of 1e-4 s ({})",
        table_note(&times)
    );
    println!(
        "{:<58} {:>10} {:>12} {:>14}",
        "model", "dofs", "wall (s)", "x real time"
    );
    for (id, dofs, end) in &models {
        let seconds = times.median(id);
        println!(
            "{:<58} {:>10} {:>12} {:>14}",
            id,
            dofs,
            shown(seconds, 1.0, 4),
            shown(seconds.map(|s| end / s), 1.0, 1),
        );
    }
    println!();
    println!(
        "solver on the plane-stress effective matrix ({n} dofs, half-bandwidth {})",
        s.half_bandwidth()
    );
    for (what, banded, dense) in [
        ("factorisation:", "factor banded", "factor dense"),
        ("solve:        ", "solve banded", "solve dense"),
    ] {
        let (banded, dense) = (times.median(banded), times.median(dense));
        println!(
            "  {what} banded {} s, dense {} s, dense / banded = {}",
            banded.map_or("-".into(), |t| format!("{t:.3e}")),
            dense.map_or("-".into(), |t| format!("{t:.3e}")),
            ratio(dense, banded, 0)
        );
    }
}
