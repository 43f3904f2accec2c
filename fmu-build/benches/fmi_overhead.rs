//! FMI overhead: wall time of the paper scene (0 to 1.2 s, internal step 1e-4 s) run
//! (a) directly with the library, a `Simulator::step` loop reading the outputs every ten
//!     steps;
//! (b) through the packaged StickSlipBeam.fmu, imported with the `fmi` crate, at
//!     communication step 1e-3 s, reading all 7 outputs after each step;
//! (c) the same at communication step 1e-4 s (one internal step per fmi2DoStep).
//!
//! For each fidelity (modal, beam, plane stress) it prints the median over repetitions
//! (interleaved a, b, c, a, b, c, ...) and the ratio against (a) measured in the same
//! run. "whole" is build + run: Simulator::new, or fmi2Instantiate through
//! fmi2ExitInitializationMode (which builds the model) and fmi2Terminate/fmi2FreeInstance.
//! "stepping" is the step loop alone. Unzipping the FMU (once per import) and
//! fmi2Instantiate alone are shown separately.
//!
//! `cargo run --release -p fmu-build` first, then `cargo bench -p fmu-build --bench
//! fmi_overhead` (same CARGO_TARGET_DIR).

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common};
use fmi::traits::FmiImport;
use std::time::{Duration, Instant};
use stickslip::scene::{CheckedScene, FidelityLevel};
use stickslip::simulation::Simulator;
use stickslip_fmi::FmuKind;

const STOP: f64 = 1.2;
/// Internal step of the paper scene (s).
const DT: f64 = 1e-4;

struct Case {
    name: &'static str,
    level: FidelityLevel,
    /// fidelity.level enumeration value.
    fmu_level: i32,
    repetitions: usize,
}

const CASES: [Case; 3] = [
    Case {
        name: "modal",
        level: FidelityLevel::Modal,
        fmu_level: 1,
        repetitions: 21,
    },
    Case {
        name: "beam",
        level: FidelityLevel::Beam,
        fmu_level: 2,
        repetitions: 11,
    },
    Case {
        name: "plane-stress",
        level: FidelityLevel::PlaneStress,
        fmu_level: 3,
        repetitions: 7,
    },
];

/// Wall times of one run: (whole, stepping).
#[derive(Clone, Copy)]
struct Timing {
    whole: Duration,
    stepping: Duration,
}

/// (a) The library: build, then step, sampling every ten steps. Returns the last tip
/// deflection to check that the FMU computes the same.
fn direct(level: FidelityLevel) -> (Timing, f64) {
    let started = Instant::now();
    let mut scene = CheckedScene::paper().into_scene();
    scene.fidelity.level = level;
    let scene = scene.check().expect("valid scene");
    let law = stickslip::friction::analytical_law(&scene).expect("analytical law");
    let mut sim = Simulator::new(scene, law).expect("the paper scene builds");
    let stepping = Instant::now();
    let steps = (STOP / DT).round() as usize;
    let mut last = 0.0;
    for k in 1..=steps {
        sim.step().expect("step");
        if k % 10 == 0 {
            let sample = std::hint::black_box(sim.sample());
            let transitions = std::hint::black_box(sim.state().transition_count);
            let _ = transitions;
            last = sample.tip_deflection;
        }
    }
    let stepping = stepping.elapsed();
    drop(std::hint::black_box(sim));
    (
        Timing {
            whole: started.elapsed(),
            stepping,
        },
        last,
    )
}

struct Vrs {
    reals: [u32; 5],
    stick: u32,
    transitions: u32,
    fidelity: u32,
}

fn vr(import: &Fmi2Import, name: &str) -> u32 {
    import
        .model_description()
        .model_variable_by_name(name)
        .unwrap_or_else(|e| panic!("variable {name}: {e}"))
        .value_reference
}

/// (b), (c) The FMU at communication step `h`, all 7 outputs read after every step.
fn through_fmu(import: &Fmi2Import, vrs: &Vrs, level: i32, h: f64) -> (Timing, f64) {
    let started = Instant::now();
    let mut inst = import
        .instantiate_cs("bench", false, false)
        .expect("fmi2Instantiate");
    inst.setup_experiment(None, 0.0, Some(STOP))
        .expect("fmi2SetupExperiment");
    Common::enter_initialization_mode(&mut inst).expect("fmi2EnterInitializationMode");
    inst.set_integer(&[vrs.fidelity], &[level])
        .expect("fidelity.level");
    Common::exit_initialization_mode(&mut inst).expect("fmi2ExitInitializationMode");
    let stepping = Instant::now();
    let (mut reals, mut stick, mut transitions) = ([0.0; 5], [0i32; 1], [0i32; 1]);
    let mut t = 0.0;
    for _ in 0..(STOP / h).round() as usize {
        inst.do_step(t, h, true).expect("fmi2DoStep");
        t += h;
        inst.get_real(&vrs.reals, &mut reals).expect("fmi2GetReal");
        inst.get_boolean(&[vrs.stick], &mut stick)
            .expect("fmi2GetBoolean");
        inst.get_integer(&[vrs.transitions], &mut transitions)
            .expect("fmi2GetInteger");
        std::hint::black_box((&reals, &stick, &transitions));
    }
    let stepping = stepping.elapsed();
    Common::terminate(&mut inst).expect("fmi2Terminate");
    drop(inst);
    (
        Timing {
            whole: started.elapsed(),
            stepping,
        },
        reals[0],
    )
}

fn median(mut values: Vec<Duration>) -> Duration {
    values.sort();
    values[values.len() / 2]
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn main() {
    let quick = !std::env::args().any(|a| a == "--bench");
    let path = fmu_build::fmu_path(FmuKind::StickSlipBeam);
    assert!(
        path.is_file(),
        "{} is missing: run `cargo run --release -p fmu-build` first (with the same CARGO_TARGET_DIR)",
        path.display()
    );
    let unzip = Instant::now();
    let import: Fmi2Import = fmi::import::from_path(&path).expect("import StickSlipBeam.fmu");
    let unzip = unzip.elapsed();
    assert_eq!(
        import.model_description().guid,
        FmuKind::StickSlipBeam.guid(),
        "stale FMU: run `cargo run --release -p fmu-build` first"
    );
    let vrs = Vrs {
        reals: [
            vr(&import, "tip_deflection"),
            vr(&import, "tip_velocity"),
            vr(&import, "relative_velocity"),
            vr(&import, "friction_force"),
            vr(&import, "holding_force"),
        ],
        stick: vr(&import, "stick"),
        transitions: vr(&import, "transitions"),
        fidelity: vr(&import, "fidelity.level"),
    };

    let bench_started = Instant::now();
    // fmi2Instantiate alone (it checks resources/ but reads no network).
    let instantiate = median(
        (0..11)
            .map(|_| {
                let started = Instant::now();
                let inst = import
                    .instantiate_cs("bench-instantiate", false, false)
                    .expect("fmi2Instantiate");
                drop(std::hint::black_box(inst));
                started.elapsed()
            })
            .collect(),
    );
    let mut rows = Vec::new();
    for case in &CASES {
        // Warm-up, and a check that all three compute the same run.
        let (_, a) = direct(case.level);
        let (_, b) = through_fmu(&import, &vrs, case.fmu_level, 1e-3);
        let (_, c) = through_fmu(&import, &vrs, case.fmu_level, 1e-4);
        assert_eq!(
            a.to_bits(),
            b.to_bits(),
            "{}: FMU h = 1e-3 s differs",
            case.name
        );
        assert_eq!(
            a.to_bits(),
            c.to_bits(),
            "{}: FMU h = 1e-4 s differs",
            case.name
        );

        let mut times: [Vec<Timing>; 3] = Default::default();
        // `cargo test --all-targets` runs this bench without `--bench`: one repetition
        // each, as a smoke test of the measuring code.
        let repetitions = if quick { 1 } else { case.repetitions };
        for _ in 0..repetitions {
            times[0].push(direct(case.level).0);
            times[1].push(through_fmu(&import, &vrs, case.fmu_level, 1e-3).0);
            times[2].push(through_fmu(&import, &vrs, case.fmu_level, 1e-4).0);
        }
        let whole: Vec<Duration> = times
            .iter()
            .map(|t| median(t.iter().map(|x| x.whole).collect()))
            .collect();
        let stepping: Vec<Duration> = times
            .iter()
            .map(|t| median(t.iter().map(|x| x.stepping).collect()))
            .collect();
        rows.push((case, whole, stepping));
    }

    println!();
    println!(
        "FMI overhead, paper scene 0..{STOP} s at dt = {DT} s; StickSlipBeam.fmu via the fmi crate, 7 outputs read per communication step"
    );
    println!(
        "median of N repetitions; ratio = time / (a) of the same fidelity in this run; unzip of the FMU (once per import): {:.1} ms; fmi2Instantiate + fmi2FreeInstance: {:.2} ms",
        ms(unzip),
        ms(instantiate)
    );
    println!();
    println!(
        "| fidelity     |  N | part     | (a) direct ms | (b) FMU h=1e-3 ms | ratio | (c) FMU h=1e-4 ms | ratio |"
    );
    println!(
        "| ------------ | -- | -------- | ------------- | ----------------- | ----- | ----------------- | ----- |"
    );
    for (case, whole, stepping) in &rows {
        for (part, t) in [("whole", whole), ("stepping", stepping)] {
            println!(
                "| {:<12} | {:>2} | {:<8} | {:>13.2} | {:>17.2} | {:>5.2} | {:>17.2} | {:>5.2} |",
                case.name,
                case.repetitions,
                part,
                ms(t[0]),
                ms(t[1]),
                t[1].as_secs_f64() / t[0].as_secs_f64(),
                ms(t[2]),
                t[2].as_secs_f64() / t[0].as_secs_f64(),
            );
        }
    }
    println!();
    let steps = (STOP / DT).round();
    for (case, _, stepping) in &rows {
        println!(
            "{}: interface cost per fmi2DoStep + 3 get calls at h = 1e-4 s: {:.2} us (stepping (c) - (a), over {steps} calls)",
            case.name,
            (stepping[2].as_secs_f64() - stepping[0].as_secs_f64()) / steps * 1e6
        );
    }
    println!(
        "bench wall time {:.1} s",
        bench_started.elapsed().as_secs_f64()
    );
}
