//! A 3D solid too wide for the band (issue 35's "Speed": a structure of 50,000 DOFs
//! reduced in under 30 s and run at 100x real time or better; the full model's time per
//! step beside it), on one CalculiX block of examples/calculix-block per process, so that
//! the peak resident memory is that block's:
//!
//! 1. read: the ccx files parsed (`read_calculix`);
//! 2. factorise: `SparseStructure::new` (checks, M's check block by block, faer's
//!    symbolic analysis and numeric Cholesky of K);
//! 3. reduce: `sparse_modal::reduce`, the lowest `MODES` modes by shift-invert Lanczos on
//!    that factor plus the static correction at the contact DOF;
//! 4. the full model's cost per time step, measured as what a step of it does at least:
//!    one sparse solve with a factor of the same pattern plus the products with M and K
//!    (the mean of 20);
//! 5. the reduced model in the time loop: the paper scene of examples/calculix-block
//!    (1.2 s at dt = 1e-4 s, analytical friction) on the reduced model, its wall time
//!    against the 1.2 s it simulates (the real-time factor);
//! 6. the peak resident set of the process (VmHWM), after all of it.
//!
//! 7. with `SPARSE_BLOCK_AUTO` (tolerances in m, comma-separated, e.g. `1e-6,1e-7`):
//!    `fidelity = auto` on the paper scene of that block (`auto::structure::choose`,
//!    which takes a structure too wide for the band through its converged modal
//!    reference), each tolerance calibrated from scratch: the choice, its estimate, the
//!    calibration's runs and time; then the chosen scene as a user runs it: its model
//!    built from the files (read, factorise, reduce: the reduction time a user waits)
//!    and its run's wall time against the simulated time (the real-time factor), beside
//!    the full model's time per step measured above (a ratio, not a timed assertion).
//!
//! Not criterion: each stage runs once on tens of MB of input, and one process per block
//! is what makes the memory column mean something. Timing is printed, never asserted.
//!
//! Run: `bash examples/calculix-block/regenerate.sh 100 12 /tmp/b100` then
//! `SPARSE_BLOCK=/tmp/b100/block SPARSE_BLOCK_ACROSS=12 SPARSE_BLOCK_ALONG=100 cargo bench
//! -p stickslip-tests --bench sparse_block` (without the variables: the committed
//! 20 x 4 x 4 block).

use std::path::{Path, PathBuf};
use std::time::Instant;

use stickslip::auto::structure::choose;
use stickslip::auto::Horizon;
use stickslip::law_source::LawSource;
use stickslip::linear_structure::read_calculix;
use stickslip::linear_structure::sparse::SparseStructure;
use stickslip::linear_structure::sparse_modal::reduce;
use stickslip::scene::{FidelityLevel, Scene};
use stickslip::simulation::Simulator;
use stickslip::structure::StructuralModel;
use stickslip::user_structure::PointDof;
use stickslip_formats::structure_file::DofLabel;

fn variable(name: &str, default: &str) -> String {
    std::env::var(name).unwrap_or_else(|_| default.to_string())
}

/// The process's peak resident set (VmHWM, bytes) from /proc/self/status.
fn peak_rss() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024.0)
}

/// The mean wall time (s) of `count` repetitions of one solve with K's factor (the
/// effective matrix of a step has K's pattern and costs the same) and the products with
/// M and K: what a step of the full model does at least.
fn full_step_seconds(structure: &SparseStructure, count: usize) -> f64 {
    let n = structure.dofs();
    let mut x: Vec<f64> = (0..n).map(|i| ((i % 7) as f64 - 3.0) * 1e-6).collect();
    let (mut mx, mut kx) = (vec![0.0; n], vec![0.0; n]);
    let started = Instant::now();
    for _ in 0..count {
        structure.mass().mul_vec(&x, &mut mx);
        structure.stiffness().mul_vec(&x, &mut kx);
        x.iter_mut().zip(&mx).for_each(|(a, b)| *a = b + 1e-12 * *a);
        structure.factor().solve_in_place(&mut x);
    }
    std::hint::black_box(&x);
    started.elapsed().as_secs_f64() / count as f64
}

fn main() {
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/calculix-block");
    let job = PathBuf::from(variable(
        "SPARSE_BLOCK",
        example.join("block").to_str().unwrap(),
    ));
    let along: u64 = variable("SPARSE_BLOCK_ALONG", "20").parse().unwrap();
    let across: u64 = variable("SPARSE_BLOCK_ACROSS", "4").parse().unwrap();
    let modes: usize = variable("SPARSE_BLOCK_MODES", "20").parse().unwrap();
    // make_deck.py's numbering: the end face's centre.
    let half = across / 2;
    let contact = DofLabel {
        node: 1 + half + (across + 1) * (half + (across + 1) * along),
        direction: 2,
    };

    let started = Instant::now();
    let matrices = read_calculix(&job).unwrap();
    let read = started.elapsed().as_secs_f64();

    let started = Instant::now();
    let structure = SparseStructure::new(&matrices, &[]).unwrap();
    let factorise = started.elapsed().as_secs_f64();
    drop(matrices);

    let started = Instant::now();
    let label = format!("block {along} x {across} x {across}");
    let reduced = reduce(&structure, contact, modes, true, &label).unwrap();
    let reduction = started.elapsed().as_secs_f64();

    let step = full_step_seconds(&structure, 20);

    let scene = Scene::load(&example.join("scene.toml")).unwrap();
    let simulated = scene.time.end;
    let law = LawSource::resolve(&scene).unwrap().law().unwrap();
    let started = Instant::now();
    let mut sim = Simulator::with_model(scene.clone(), reduced.clone(), law).unwrap();
    let samples = sim.run(1).unwrap();
    let run = started.elapsed().as_secs_f64();
    let f1 = reduced.stiffness.get(0, 0).sqrt() / (2.0 * std::f64::consts::PI);

    println!(
        "block {along} x {across} x {across}: {} DOFs",
        structure.dofs()
    );
    println!(
        "  K upper entries {}, factor entries {} ({}), f1 = {f1:.4} Hz",
        structure.stiffness().nonzeros(),
        structure.factor().stored_values(),
        if structure.factor().is_supernodal() {
            "supernodal"
        } else {
            "simplicial"
        }
    );
    println!("  read {read:.2} s, factorise {factorise:.2} s, reduce ({modes} modes + static) {reduction:.2} s, total {:.2} s", read + factorise + reduction);
    println!(
        "  full model per step (one solve + M and K products): {:.2} ms, {:.1}x real time at dt = {} s",
        step * 1e3,
        scene.time.step / step,
        scene.time.step
    );
    println!(
        "  reduced model: {} steps in {run:.3} s for {simulated} s simulated: {:.0}x real time; tip range {:.3e} m",
        samples.len(),
        simulated / run,
        samples
            .iter()
            .map(|s| s.tip_deflection)
            .fold(f64::MIN, f64::max)
            - samples
                .iter()
                .map(|s| s.tip_deflection)
                .fold(f64::MAX, f64::min)
    );
    // The bits of the reduced model (omega^2 and the tip's weights) and of the run's tip,
    // to compare one binary across CPUs (docs/structures.md, "A 3D solid": under
    // `qemu-x86_64-static -cpu Nehalem`, without AVX and FMA).
    let bits = (0..reduced.dofs())
        .flat_map(|j| [reduced.stiffness.get(j, j), reduced.tip[j].1])
        .chain(samples.iter().map(|s| s.tip_deflection))
        .fold(0xcbf2_9ce4_8422_2325_u64, |h, v| {
            (h ^ v.to_bits()).wrapping_mul(0x0100_0000_01b3)
        });
    println!("  bits of the reduced model and its run (FNV-1a): {bits:016x}");
    if let Some(bytes) = peak_rss() {
        println!("  peak resident set {:.2} GB", bytes / 1e9);
    }
    let tolerances = variable("SPARSE_BLOCK_AUTO", "");
    let tolerances = tolerances
        .split(',')
        .filter(|t| !t.is_empty())
        .map(|t| t.parse::<f64>().unwrap());
    drop(structure);
    for tolerance in tolerances {
        auto_on_the_block(scene.scene(), &job, contact, tolerance, step);
    }
}

/// `fidelity = auto` at `tolerance` (m) on `scene` with its structure the block `job`,
/// friction at `contact`; `full_step` (s) is the full model's time per step measured in
/// this process.
fn auto_on_the_block(scene: &Scene, job: &Path, contact: DofLabel, tolerance: f64, full_step: f64) {
    let mut scene = scene.clone();
    let section = scene.structure.as_mut().unwrap();
    section.job = Some(job.to_path_buf());
    section.contact = PointDof::at_node(contact.node, contact.direction);
    scene.fidelity.level = FidelityLevel::Auto;
    let law = LawSource::resolve(&scene.clone().check().unwrap()).unwrap();
    let horizon = Horizon::Until(scene.time.end);
    let mut log = |line: &str| eprintln!("    {line}");
    let choice = match choose(&scene, &law, tolerance, horizon, &mut log) {
        Ok(choice) => choice,
        Err(e) => {
            println!("  auto, tolerance {tolerance:e} m: {e}");
            return;
        }
    };
    let reference = choice.tried.last().unwrap().partner;
    println!(
        "  auto, tolerance {tolerance:e} m: chose {} (estimate {:.3e} m, reference {reference}), calibration {} runs in {:.1} s",
        choice.configuration, choice.estimated_error, choice.runs, choice.calibration_seconds
    );
    let chosen = choice.configuration.apply(&scene).check().unwrap();
    let started = Instant::now();
    let model = StructuralModel::build(&chosen).unwrap();
    let reduction = started.elapsed().as_secs_f64();
    // The run takes milliseconds: the fastest of five, so that another process's time
    // slice does not count as the run's.
    let (mut run, mut steps) = (f64::INFINITY, 0);
    for _ in 0..5 {
        let started = Instant::now();
        let mut sim =
            Simulator::with_model(chosen.clone(), model.clone(), law.law().unwrap()).unwrap();
        steps = sim.run(1).unwrap().len() - 1;
        run = run.min(started.elapsed().as_secs_f64());
    }
    println!(
        "    the chosen run: model built from the files (read, factorise, reduce) in {reduction:.1} s; {steps} steps in {run:.4} s (fastest of 5) for {} s simulated: {:.0}x real time; the full model: {:.1} ms per step at dt = {} s, {:.4}x real time",
        chosen.time.end,
        chosen.time.end / run,
        full_step * 1e3,
        chosen.time.step,
        chosen.time.step / full_step
    );
    if let Some(bytes) = peak_rss() {
        println!("    peak resident set so far {:.2} GB", bytes / 1e9);
    }
}
