//! FMI overhead: wall time of the paper scene (0 to 1.2 s, internal step 1e-4 s) run
//! (a) directly with the library, a `Simulator::step` loop reading the outputs every ten
//!     steps;
//! (b) through the packaged StickSlipBeam.fmu, imported with the `fmi` crate, at
//!     communication step 1e-3 s, reading all 7 outputs after each step;
//! (c) the same at communication step 1e-4 s (one internal step per fmi2DoStep).
//!
//! Criterion measures each of (a), (b), (c) per fidelity (modal, beam, plane stress; group
//! `fmi_overhead_<fidelity>`, one whole run per iteration), and fmi2Instantiate +
//! fmi2FreeInstance alone (group `fmi_instantiate`). "whole" is build + run:
//! Simulator::new, or fmi2Instantiate through fmi2ExitInitializationMode (which builds
//! the model) and fmi2Terminate/fmi2FreeInstance; it is what criterion reports. "stepping"
//! is the step loop alone, timed inside the same runs. The table then gives, per
//! fidelity, the median of both over criterion's samples and the ratio against (a)
//! measured in the same run (see `stickslip_tests::bench`); the variants run one after
//! the other, not interleaved. Unzipping the FMU (once per import) is timed once. The
//! last tip deflection of (a), (b) and (c) must agree to the bit.
//!
//! `cargo run --release -p fmu-build` first, then `cargo bench -p fmu-build --bench
//! fmi_overhead` (same CARGO_TARGET_DIR).

use criterion::{Criterion, SamplingMode};
#[path = "../tests/packaged/value_reference.rs"]
mod value_reference;
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common};
use fmi::traits::FmiImport;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::time::{Duration, Instant};
use stickslip::scene::{CheckedScene, FidelityLevel};
use stickslip::simulation::Simulator;
use stickslip_fmi::FmuKind;
use stickslip_tests::bench::{ratio, shown, table_note, Samples};
use value_reference::vr;

const STOP: f64 = 1.2;
/// Internal step of the paper scene (s).
const DT: f64 = 1e-4;

struct Case {
    name: &'static str,
    level: FidelityLevel,
    /// fidelity.level enumeration value.
    fmu_level: i32,
}

const CASES: [Case; 3] = [
    Case {
        name: "modal",
        level: FidelityLevel::Modal,
        fmu_level: 1,
    },
    Case {
        name: "beam",
        level: FidelityLevel::Beam,
        fmu_level: 2,
    },
    Case {
        name: "plane-stress",
        level: FidelityLevel::PlaneStress,
        fmu_level: 3,
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
    let law = stickslip::law_source::LawSource::resolve(&scene)
        .and_then(|law| law.law())
        .expect("analytical law");
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

/// The variants of one fidelity: (a), (b), (c).
const VARIANTS: [&str; 3] = ["(a) direct", "(b) FMU h=1e-3", "(c) FMU h=1e-4"];
const SAMPLE_SIZE: usize = 10;

fn ms(seconds: Option<f64>) -> String {
    shown(seconds, 1e3, 2)
}

fn main() {
    let mut c = Criterion::default().without_plots().configure_from_args();
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
    let times = Samples::new(SAMPLE_SIZE);
    // The last tip deflection of each (case, variant), as bits.
    let last: RefCell<BTreeMap<(&str, &str), u64>> = RefCell::new(BTreeMap::new());

    // fmi2Instantiate alone (it checks resources/ but reads no network).
    let mut group = c.benchmark_group("fmi_instantiate");
    group.sample_size(SAMPLE_SIZE);
    group.bench_function("fmi2Instantiate + fmi2FreeInstance", |b| {
        b.iter_custom(|iters| {
            times.time("instantiate", iters, || {
                let inst = import
                    .instantiate_cs("bench-instantiate", false, false)
                    .expect("fmi2Instantiate");
                drop(std::hint::black_box(inst));
            })
        })
    });
    group.finish();

    for case in &CASES {
        let mut group = c.benchmark_group(format!("fmi_overhead_{}", case.name));
        // A run takes from 15 ms (modal) to about a second (plane stress).
        group
            .sample_size(SAMPLE_SIZE)
            .sampling_mode(SamplingMode::Flat)
            .warm_up_time(Duration::from_millis(200))
            .measurement_time(Duration::from_secs(1));
        for (k, variant) in VARIANTS.into_iter().enumerate() {
            let run = || match k {
                0 => direct(case.level),
                1 => through_fmu(&import, &vrs, case.fmu_level, 1e-3),
                _ => through_fmu(&import, &vrs, case.fmu_level, 1e-4),
            };
            group.bench_function(variant, |b| {
                b.iter_custom(|iters| {
                    let (mut whole, mut stepping) = (Duration::ZERO, Duration::ZERO);
                    for _ in 0..iters {
                        let (timing, tip) = run();
                        whole += timing.whole;
                        stepping += timing.stepping;
                        last.borrow_mut()
                            .insert((case.name, variant), tip.to_bits());
                    }
                    let per = |d: Duration| d.as_secs_f64() / iters as f64;
                    times.record(&format!("{}/{variant}/whole", case.name), per(whole));
                    times.record(&format!("{}/{variant}/stepping", case.name), per(stepping));
                    whole
                })
            });
        }
        group.finish();
        // All three compute the same run.
        let last = last.borrow();
        if let Some(a) = last.get(&(case.name, VARIANTS[0])) {
            for variant in &VARIANTS[1..] {
                if let Some(other) = last.get(&(case.name, *variant)) {
                    assert_eq!(a, other, "{}: {variant} differs from (a)", case.name);
                }
            }
        }
    }
    c.final_summary();

    println!();
    println!(
        "FMI overhead, paper scene 0..{STOP} s at dt = {DT} s; StickSlipBeam.fmu via the fmi crate, 7 outputs read per communication step"
    );
    println!(
        "{}; ratio = time / (a) of the same fidelity; unzip of the FMU (once per import): {:.1} ms; fmi2Instantiate + fmi2FreeInstance: {} ms",
        table_note(&times),
        unzip.as_secs_f64() * 1e3,
        ms(times.median("instantiate"))
    );
    println!();
    println!(
        "| fidelity     |  N | part     | (a) direct ms | (b) FMU h=1e-3 ms | ratio | (c) FMU h=1e-4 ms | ratio |"
    );
    println!(
        "| ------------ | -- | -------- | ------------- | ----------------- | ----- | ----------------- | ----- |"
    );
    let time = |case: &Case, k: usize, part: &str| {
        times.median(&format!("{}/{}/{part}", case.name, VARIANTS[k]))
    };
    for case in &CASES {
        let n = times.count(&format!("{}/{}/whole", case.name, VARIANTS[0]));
        for part in ["whole", "stepping"] {
            let t = [
                time(case, 0, part),
                time(case, 1, part),
                time(case, 2, part),
            ];
            println!(
                "| {:<12} | {:>2} | {:<8} | {:>13} | {:>17} | {:>5} | {:>17} | {:>5} |",
                case.name,
                n,
                part,
                ms(t[0]),
                ms(t[1]),
                ratio(t[1], t[0], 2),
                ms(t[2]),
                ratio(t[2], t[0], 2),
            );
        }
    }
    println!();
    let steps = (STOP / DT).round();
    for case in &CASES {
        if let (Some(c), Some(a)) = (time(case, 2, "stepping"), time(case, 0, "stepping")) {
            println!(
                "{}: interface cost per fmi2DoStep + 3 get calls at h = 1e-4 s: {:.2} us (stepping (c) - (a), over {steps} calls)",
                case.name,
                (c - a) / steps * 1e6
            );
        }
    }
    println!(
        "bench wall time {:.1} s",
        bench_started.elapsed().as_secs_f64()
    );
}
