//! Cost per time step of the plane-stress model against its number of degrees of
//! freedom, up to about 10^5 dofs, and the growth exponent fitted to it.
//!
//! Each step makes one banded solve with the factorised effective matrix and two banded
//! products (M and K), so it costs O(n b) for n dofs and half-bandwidth b (see
//! `banded`); the factorisation is done once, at set-up, and costs O(n b^2). The mesh is
//! numbered column by column along the beam, so b grows with the elements through the
//! height only (b = 6 ny + 9 for Q8 elements). Two refinement families:
//!
//! 1. Uniform refinement of the paper's beam (2 m x 0.01 m, `Scene::default()`), element
//!    size 0.04 m down to 0.001 m (128 020 dofs). Once the element is below the height
//!    (size <= 0.01 m) both nx and ny grow as 1/size, so n ~ nx ny and b ~ ny ~ sqrt(n):
//!    the cost per step should grow as n^1.5. The two coarsest sizes (0.04, 0.02 m) still
//!    have one element through the height (b fixed), so the exponent is fitted both over
//!    every row and over the uniform regime (size <= 0.01 m) alone. Because of the
//!    constant in b = 6 ny + 9, b grows only 4.6x while n grows 64x from ny = 1 to 10, so
//!    the measured exponent on n sits below 1.5 (about 1 + ln 4.6 / ln 64 = 1.37 from the
//!    bandwidth alone); the exponent on n b is the cleaner check.
//! 2. Refinement along the length only: element size fixed at 0.01 m (one element
//!    through the height, b = 15) and the beam made longer, 2 m to 100 m
//!    (100 002 dofs). b is fixed, so the cost per step should grow as n^1.0.
//!
//! For both, and for all rows together, it also fits log(cost per step) against
//! log(n b), whose exponent should be about 1 if O(n b) is the whole story (per-step
//! overheads flatten the smallest meshes; cache effects steepen the largest).
//!
//! Method: for each mesh the `Simulator` (analytical exponential law, generalised-alpha,
//! quasi-static start) is built outside the timing; its set-up time (model assembly,
//! factorisation of the effective matrix, and the K and M factorisations of the
//! quasi-static initial state) is reported separately. A few warm-up steps estimate the
//! cost, then `advance_to` over N steps (N chosen for ~0.25 s, at least 20) is timed
//! three times and the median is reported, in microseconds per step.
//!
//! Run: `cargo bench --bench scaling` (about 15 s once built, on two cores).

use std::time::Instant;
use stickslip::friction::analytical_law;
use stickslip::scene::Scene;
use stickslip::simulation::Simulator;

/// Target wall time of one timed repeat (s).
const TARGET_SECONDS: f64 = 0.25;
/// Fewest steps in one timed repeat.
const MIN_STEPS: u64 = 20;
/// Most steps in one timed repeat (the smallest meshes take a few microseconds a step).
const MAX_STEPS_TIMED: u64 = 200_000;
/// Timed repeats per mesh; the median is reported.
const REPEATS: usize = 3;
/// Untimed steps that warm the caches and estimate the cost of a step.
const WARM_UP_STEPS: u64 = 5;

/// One measured mesh.
struct Row {
    length: f64,
    element_size: f64,
    along: usize,
    through: usize,
    dofs: usize,
    half_bandwidth: usize,
    setup_seconds: f64,
    steps: u64,
    micros_per_step: f64,
}

/// Builds the simulator of the paper's scene with the given beam length and element
/// size, and measures its set-up and its cost per step.
fn measure(length: f64, element_size: f64) -> Row {
    let mut scene = Scene::default();
    scene.geometry.length = length;
    scene.fidelity.element_size = element_size;
    // Long enough that no timed run reaches the end (the end only matters to `run`).
    scene.time.end = 1e4;
    let checked = scene.check().expect("scene within the limits of scene.rs");
    let (along, through) =
        stickslip::scene::plane_stress_divisions(&checked.geometry, element_size);
    let law = analytical_law(&checked).expect("the default law is analytical");
    let dt = checked.time.step;

    let started = Instant::now();
    let mut sim = Simulator::new(checked, law).expect("simulator set-up");
    let setup_seconds = started.elapsed().as_secs_f64();
    let dofs = sim.model().dofs();
    let half_bandwidth = sim.model().stiffness.half_bandwidth();

    let advance = |sim: &mut Simulator, steps: u64| -> f64 {
        let before = sim.state().step;
        let target = sim.state().time + steps as f64 * dt;
        let start = Instant::now();
        sim.advance_to(target).expect("stepping");
        let seconds = start.elapsed().as_secs_f64();
        assert_eq!(
            sim.state().step - before,
            steps,
            "advance_to took full steps only"
        );
        seconds
    };
    let warm = advance(&mut sim, WARM_UP_STEPS) / WARM_UP_STEPS as f64;
    let steps = ((TARGET_SECONDS / warm).ceil() as u64).clamp(MIN_STEPS, MAX_STEPS_TIMED);
    let mut times: Vec<f64> = (0..REPEATS)
        .map(|_| advance(&mut sim, steps) / steps as f64)
        .collect();
    times.sort_by(f64::total_cmp);
    Row {
        length,
        element_size,
        along,
        through,
        dofs,
        half_bandwidth,
        setup_seconds,
        steps,
        micros_per_step: 1e6 * times[REPEATS / 2],
    }
}

/// Least-squares slope of log(y) against log(x).
fn log_slope(points: impl Iterator<Item = (f64, f64)>) -> f64 {
    let logs: Vec<(f64, f64)> = points.map(|(x, y)| (x.ln(), y.ln())).collect();
    let count = logs.len() as f64;
    let mean_x = logs.iter().map(|p| p.0).sum::<f64>() / count;
    let mean_y = logs.iter().map(|p| p.1).sum::<f64>() / count;
    let covariance: f64 = logs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    let variance: f64 = logs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    covariance / variance
}

fn slope_vs_dofs<'a>(rows: impl Iterator<Item = &'a Row>) -> f64 {
    log_slope(rows.map(|r| (r.dofs as f64, r.micros_per_step)))
}

fn slope_vs_work<'a>(rows: impl Iterator<Item = &'a Row>) -> f64 {
    log_slope(rows.map(|r| ((r.dofs * r.half_bandwidth) as f64, r.micros_per_step)))
}

fn print_table(title: &str, rows: &[Row]) {
    println!("### {title}");
    println!();
    println!(
        "| length (m) | element size (m) | mesh | dofs | half-bandwidth | n b | setup (s) | steps timed | us per step |"
    );
    println!("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for r in rows {
        println!(
            "| {} | {:.5} | {} x {} | {} | {} | {:.3e} | {:.3} | {} | {:.1} |",
            r.length,
            r.element_size,
            r.along,
            r.through,
            r.dofs,
            r.half_bandwidth,
            (r.dofs * r.half_bandwidth) as f64,
            r.setup_seconds,
            r.steps,
            r.micros_per_step
        );
    }
    println!();
}

fn main() {
    let started = Instant::now();
    println!(
        "plane-stress cost per time step (dt = 1e-4 s, analytical friction, median of {REPEATS} timed runs)"
    );
    println!();

    // Family 1: uniform refinement of the paper's 2 m x 0.01 m beam. Sizes that divide
    // the height, so that every element is square once there are several through it.
    let sizes = [
        0.04,
        0.02,
        0.01,
        0.005,
        0.01 / 3.0,
        0.0025,
        0.002,
        0.00125,
        0.001,
    ];
    let uniform: Vec<Row> = sizes.iter().map(|&h| measure(2.0, h)).collect();
    print_table(
        "1. uniform refinement of the 2 m x 0.01 m beam (b grows with the elements through the height)",
        &uniform,
    );

    // Family 2: refinement along the length only, one 0.01 m element through the height.
    let lengths = [2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 100.0];
    let along: Vec<Row> = lengths.iter().map(|&l| measure(l, 0.01)).collect();
    print_table(
        "2. refinement along the length only (element size 0.01 m, beam 2 m to 100 m, b fixed)",
        &along,
    );

    let square = || uniform.iter().filter(|r| r.element_size <= 0.01 + 1e-12);
    println!("### growth exponents (least-squares slope in log-log)");
    println!();
    println!("| family | rows | cost ~ dofs^p, p = | cost ~ (n b)^q, q = | expected |");
    println!("| --- | ---: | ---: | ---: | --- |");
    println!(
        "| 1. uniform, every size | {} | {:.3} | {:.3} | p ~ 1.5 (b ~ sqrt(n) below 0.01 m), q ~ 1 |",
        uniform.len(),
        slope_vs_dofs(uniform.iter()),
        slope_vs_work(uniform.iter())
    );
    println!(
        "| 1. uniform, size <= 0.01 m | {} | {:.3} | {:.3} | p ~ 1.5, q ~ 1 |",
        square().count(),
        slope_vs_dofs(square()),
        slope_vs_work(square())
    );
    println!(
        "| 2. length only | {} | {:.3} | {:.3} | p ~ 1.0, q ~ 1 (b fixed) |",
        along.len(),
        slope_vs_dofs(along.iter()),
        slope_vs_work(along.iter())
    );
    println!(
        "| all rows | {} | - | {:.3} | q ~ 1 |",
        uniform.len() + along.len(),
        slope_vs_work(uniform.iter().chain(&along))
    );
    println!();
    println!(
        "total bench wall time {:.1} s",
        started.elapsed().as_secs_f64()
    );
}
