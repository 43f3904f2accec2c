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
//! quasi-static start) is built outside the timing, on the first call of its benchmark;
//! its set-up time (model assembly, factorisation of the effective matrix, and the K and
//! M factorisations of the quasi-static initial state) is measured once and reported
//! separately. Criterion then times `advance_to` over as many steps as it asks for
//! (one iteration = one time step; groups `scaling_uniform` and `scaling_length`, ten
//! samples each after its warm-up), and the tables give the median time per step over
//! the samples, in microseconds (see `stickslip_tests::bench`). Under `cargo test` only
//! the four smallest meshes of family 1 and the three shortest beams of family 2 are
//! built, each stepped once.
//!
//! Run: `cargo bench -p stickslip-tests --bench scaling` (about 25 s once built, on two
//! cores).

use std::cell::RefCell;
use std::time::{Duration, Instant};

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, SamplingMode};
use stickslip::law_source::LawSource;
use stickslip::scene::Scene;
use stickslip::simulation::Simulator;
use stickslip_tests::bench::{table_note, test_mode, Samples};

/// Samples per mesh.
const SAMPLE_SIZE: usize = 10;

/// One mesh: what it is, and what was measured.
struct Row {
    id: String,
    length: f64,
    element_size: f64,
    along: usize,
    through: usize,
    /// Set when the simulator is built, on the first call of the benchmark.
    built: Option<Built>,
    /// Steps criterion asked for in each call, in order (warm-up calls first).
    steps: Vec<u64>,
}

struct Built {
    dofs: usize,
    half_bandwidth: usize,
    setup_seconds: f64,
}

impl Row {
    fn new(id: String, length: f64, element_size: f64) -> Self {
        let scene = scene(length, element_size);
        let checked = scene.check().expect("scene within the limits of scene.rs");
        let (along, through) =
            stickslip::scene::plane_stress_divisions(&checked.geometry, element_size);
        Self {
            id,
            length,
            element_size,
            along,
            through,
            built: None,
            steps: Vec::new(),
        }
    }

    /// Steps in the measured samples.
    fn steps_timed(&self) -> u64 {
        self.steps[self.steps.len().saturating_sub(SAMPLE_SIZE)..]
            .iter()
            .sum()
    }
}

/// The paper's scene with the given beam length and element size.
fn scene(length: f64, element_size: f64) -> Scene {
    let mut scene = Scene::default();
    scene.geometry.length = length;
    scene.fidelity.element_size = element_size;
    // Long enough that no timed run reaches the end (the end only matters to `run`).
    scene.time.end = 1e4;
    scene
}

/// The benchmark of one mesh: builds the simulator on the first call, then each call
/// advances it by the number of steps criterion asks for and returns their wall time.
fn bench_mesh(group: &mut BenchmarkGroup<'_, WallTime>, times: &Samples, row: &RefCell<Row>) {
    let (id, length, element_size) = {
        let r = row.borrow();
        (r.id.clone(), r.length, r.element_size)
    };
    let mut sim: Option<Simulator> = None;
    group.bench_function(&id, |b| {
        b.iter_custom(|steps| {
            let sim = sim.get_or_insert_with(|| {
                let checked = scene(length, element_size).check().expect("checked above");
                let law = LawSource::resolve(&checked)
                    .and_then(|law| law.law())
                    .expect("the default law is analytical");
                let started = Instant::now();
                let sim = Simulator::new(checked, law).expect("simulator set-up");
                row.borrow_mut().built = Some(Built {
                    dofs: sim.model().dofs(),
                    half_bandwidth: sim.model().stiffness.half_bandwidth(),
                    setup_seconds: started.elapsed().as_secs_f64(),
                });
                sim
            });
            let before = sim.state().step;
            let target = sim.state().time + steps as f64 * sim.scene().time.step;
            let start = Instant::now();
            sim.advance_to(target).expect("stepping");
            let elapsed = start.elapsed();
            assert_eq!(
                sim.state().step - before,
                steps,
                "advance_to took full steps only"
            );
            times.record(&id, elapsed.as_secs_f64() / steps as f64);
            row.borrow_mut().steps.push(steps);
            elapsed
        })
    });
}

/// A row that was measured: (row, its build, microseconds per step).
type Measured<'a> = (&'a Row, &'a Built, f64);

/// Least-squares slope of log(y) against log(x).
fn log_slope(points: impl Iterator<Item = (f64, f64)>) -> f64 {
    let logs: Vec<(f64, f64)> = points
        .map(|(x, y)| (stickslip::elementary::ln(x), stickslip::elementary::ln(y)))
        .collect();
    let count = logs.len() as f64;
    let mean_x = logs.iter().map(|p| p.0).sum::<f64>() / count;
    let mean_y = logs.iter().map(|p| p.1).sum::<f64>() / count;
    let covariance: f64 = logs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    let variance: f64 = logs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    covariance / variance
}

fn slope_vs_dofs(rows: &[Measured]) -> String {
    slope(rows.iter().map(|(_, b, us)| (b.dofs as f64, *us)))
}

fn slope_vs_work(rows: &[Measured]) -> String {
    slope(
        rows.iter()
            .map(|(_, b, us)| ((b.dofs * b.half_bandwidth) as f64, *us)),
    )
}

/// The fitted exponent, or "-" with fewer than two rows.
fn slope(points: impl Iterator<Item = (f64, f64)>) -> String {
    let points: Vec<(f64, f64)> = points.collect();
    if points.len() < 2 {
        return "-".to_owned();
    }
    format!("{:.3}", log_slope(points.into_iter()))
}

fn print_table(title: &str, rows: &[Measured]) {
    println!("### {title}");
    println!();
    println!(
        "| length (m) | element size (m) | mesh | dofs | half-bandwidth | n b | setup (s) | steps timed | us per step |"
    );
    println!("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for (r, b, us) in rows {
        println!(
            "| {} | {:.5} | {} x {} | {} | {} | {:.3e} | {:.3} | {} | {:.1} |",
            r.length,
            r.element_size,
            r.along,
            r.through,
            b.dofs,
            b.half_bandwidth,
            (b.dofs * b.half_bandwidth) as f64,
            b.setup_seconds,
            r.steps_timed(),
            us
        );
    }
    println!();
}

/// The rows that ran (all but those filtered out on the command line), with their
/// median cost per step.
fn measured<'a>(rows: &'a [Row], times: &Samples) -> Vec<Measured<'a>> {
    rows.iter()
        .filter_map(|r| Some((r, r.built.as_ref()?, 1e6 * times.median(&r.id)?)))
        .collect()
}

fn main() {
    let started = Instant::now();
    let mut c = Criterion::default().without_plots().configure_from_args();
    let times = Samples::new(SAMPLE_SIZE);
    let quick = test_mode();

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
    // Family 2: refinement along the length only, one 0.01 m element through the height.
    let lengths = [2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 100.0];
    let (sizes, lengths) = if quick {
        (&sizes[..4], &lengths[..3])
    } else {
        (&sizes[..], &lengths[..])
    };
    let uniform: Vec<RefCell<Row>> = sizes
        .iter()
        .map(|&h| RefCell::new(Row::new(format!("size {h:.5} m"), 2.0, h)))
        .collect();
    let along: Vec<RefCell<Row>> = lengths
        .iter()
        .map(|&l| RefCell::new(Row::new(format!("length {l} m"), l, 0.01)))
        .collect();
    for (name, rows) in [("scaling_uniform", &uniform), ("scaling_length", &along)] {
        let mut group = c.benchmark_group(name);
        // The finest meshes take about 0.1 s a step: at least one step per sample.
        group
            .sample_size(SAMPLE_SIZE)
            .sampling_mode(SamplingMode::Flat)
            .warm_up_time(Duration::from_millis(100))
            .measurement_time(Duration::from_secs(1));
        for row in rows {
            bench_mesh(&mut group, &times, row);
        }
        group.finish();
    }
    c.final_summary();

    let uniform: Vec<Row> = uniform.into_iter().map(RefCell::into_inner).collect();
    let along: Vec<Row> = along.into_iter().map(RefCell::into_inner).collect();
    let uniform = measured(&uniform, &times);
    let along = measured(&along, &times);
    println!();
    println!(
        "plane-stress cost per time step (dt = 1e-4 s, analytical friction; {})",
        table_note(&times)
    );
    println!();
    print_table(
        "1. uniform refinement of the 2 m x 0.01 m beam (b grows with the elements through the height)",
        &uniform,
    );
    print_table(
        "2. refinement along the length only (element size 0.01 m, beam 2 m to 100 m, b fixed)",
        &along,
    );

    let square: Vec<Measured> = uniform
        .iter()
        .copied()
        .filter(|(r, _, _)| r.element_size <= 0.01 + 1e-12)
        .collect();
    let all: Vec<Measured> = uniform.iter().chain(&along).copied().collect();
    println!("### growth exponents (least-squares slope in log-log)");
    println!();
    println!("| family | rows | cost ~ dofs^p, p = | cost ~ (n b)^q, q = | expected |");
    println!("| --- | ---: | ---: | ---: | --- |");
    println!(
        "| 1. uniform, every size | {} | {} | {} | p ~ 1.5 (b ~ sqrt(n) below 0.01 m), q ~ 1 |",
        uniform.len(),
        slope_vs_dofs(&uniform),
        slope_vs_work(&uniform)
    );
    println!(
        "| 1. uniform, size <= 0.01 m | {} | {} | {} | p ~ 1.5, q ~ 1 |",
        square.len(),
        slope_vs_dofs(&square),
        slope_vs_work(&square)
    );
    println!(
        "| 2. length only | {} | {} | {} | p ~ 1.0, q ~ 1 (b fixed) |",
        along.len(),
        slope_vs_dofs(&along),
        slope_vs_work(&along)
    );
    println!(
        "| all rows | {} | - | {} | q ~ 1 |",
        all.len(),
        slope_vs_work(&all)
    );
    println!();
    println!(
        "total bench wall time {:.1} s",
        started.elapsed().as_secs_f64()
    );
}
