//! Imports the PACKAGED FMUs with the `fmi` crate (the Rust FMI 2.0 importer) and checks
//! them against the library they wrap.
//!
//! `cargo run --release -p fmu-build` writes the FMUs first; a missing FMU fails the
//! tests (it does not skip them). Run them in release: `cargo test --release -p
//! fmu-build`.
//!
//! Every comparison with the library is bit for bit. The FMU runs the same code behind
//! the C interface at the same internal step (1e-4 s), and the communication points
//! (1e-3 s apart) lie on that grid, so `Simulator::advance_to` takes exactly ten full
//! steps per communication step and no shorter landing step.

use crate::value_reference::vr;
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceCS};
use fmi::fmi2::Fmi2Error;
use fmi::traits::{FmiImport, FmiStatus};
use std::path::PathBuf;
use std::sync::{Mutex, Once};
use stickslip::choice::Choice;
use stickslip::contact::ContactState;
use stickslip::friction::LawChoice;
use stickslip::scene::{CheckedScene, FidelityLevel, FrictionLawKind};
use stickslip::simulation::Simulator;
use stickslip_fmi::FmuKind;

/// Communication step (s).
const H: f64 = 1e-3;
/// Experiment end (s): the FMU's default experiment.
const STOP: f64 = 1.2;
/// Communication steps from 0 to STOP.
const STEPS: usize = 1200;
/// The paper's breakaway time (s): 50 N holding force reached at v_b = 0.02 m/s.
const BREAKAWAY: f64 = 0.4;

// ---------------------------------------------------------------------------------------
// Log backend: the fmi crate forwards the FMU's logger callback to the `log` facade,
// with the instance name as target and module_path "logger".

struct Collector;

static MESSAGES: Mutex<Vec<(String, log::Level, String)>> = Mutex::new(Vec::new());

impl log::Log for Collector {
    fn enabled(&self, _: &log::Metadata) -> bool {
        true
    }

    fn log(&self, record: &log::Record) {
        if record.module_path() == Some("logger") {
            if let Ok(mut messages) = MESSAGES.lock() {
                messages.push((
                    record.target().to_owned(),
                    record.level(),
                    record.args().to_string(),
                ));
            }
        }
    }

    fn flush(&self) {}
}

static COLLECTOR: Collector = Collector;
static LOGGER: Once = Once::new();

fn install_logger() {
    LOGGER.call_once(|| {
        log::set_logger(&COLLECTOR).expect("no other logger in this test binary");
        log::set_max_level(log::LevelFilter::Trace);
    });
}

/// The FMU's messages for instance `name` (names are unique per test).
fn messages_of(name: &str) -> Vec<(log::Level, String)> {
    MESSAGES
        .lock()
        .map(|m| {
            m.iter()
                .filter(|(target, _, _)| target == name)
                .map(|(_, level, text)| (*level, text.clone()))
                .collect()
        })
        .unwrap_or_default()
}

// ---------------------------------------------------------------------------------------
// Import helpers.

/// The packaged FMU of `kind`; fails (does not skip) when it has not been built.
fn fmu_file(kind: FmuKind) -> PathBuf {
    let path = fmu_build::fmu_path(kind);
    assert!(
        path.is_file(),
        "{} is missing: run `cargo run --release -p fmu-build` first (with the same CARGO_TARGET_DIR)",
        path.display()
    );
    path
}

/// Unpacks the FMU (a new temporary folder, so a separate copy of the library) and
/// checks that it is the FMU of this source tree.
fn import(kind: FmuKind) -> Fmi2Import {
    install_logger();
    let path = fmu_file(kind);
    let import: Fmi2Import = fmi::import::from_path(&path)
        .unwrap_or_else(|e| panic!("cannot import {}: {e}", path.display()));
    let md = import.model_description();
    assert_eq!(
        md.guid,
        kind.guid(),
        "{} is stale (its interface differs from the source): run `cargo run --release -p fmu-build` first",
        path.display()
    );
    assert_eq!(md.fmi_version, "2.0");
    let cs = md.co_simulation.as_ref().expect("a <CoSimulation> element");
    assert_eq!(cs.model_identifier, kind.model_identifier());
    import
}

// ---------------------------------------------------------------------------------------
// StickSlipBeam.

/// Value references of StickSlipBeam.
#[derive(Clone, Copy)]
struct BeamVrs {
    /// tip_deflection, tip_velocity, relative_velocity, friction_force, holding_force.
    reals: [u32; 5],
    stick: u32,
    transitions: u32,
    fidelity: u32,
    friction_law: u32,
    kinetic_force: u32,
    static_limit: u32,
}

impl BeamVrs {
    fn of(import: &Fmi2Import) -> Self {
        Self {
            reals: [
                vr(import, "tip_deflection"),
                vr(import, "tip_velocity"),
                vr(import, "relative_velocity"),
                vr(import, "friction_force"),
                vr(import, "holding_force"),
            ],
            stick: vr(import, "stick"),
            transitions: vr(import, "transitions"),
            fidelity: vr(import, "fidelity.level"),
            friction_law: vr(import, "friction.law"),
            kinetic_force: vr(import, "external.kinetic_force"),
            static_limit: vr(import, "external.static_limit"),
        }
    }
}

/// The seven outputs of StickSlipBeam at one communication point.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Outputs {
    tip_deflection: f64,
    tip_velocity: f64,
    relative_velocity: f64,
    friction_force: f64,
    holding_force: f64,
    stick: bool,
    transitions: i32,
}

impl Outputs {
    fn of_simulator(sim: &Simulator) -> Self {
        let s = sim.sample();
        Self {
            tip_deflection: s.tip_deflection,
            tip_velocity: s.tip_velocity,
            relative_velocity: s.relative_velocity,
            friction_force: s.friction_force,
            holding_force: s.holding_force,
            stick: s.stick,
            transitions: sim.state().transition_count as i32,
        }
    }

    /// Every output as bits: equal bits mean the same result, +0 and -0 told apart.
    fn bits(&self) -> [u64; 7] {
        [
            self.tip_deflection.to_bits(),
            self.tip_velocity.to_bits(),
            self.relative_velocity.to_bits(),
            self.friction_force.to_bits(),
            self.holding_force.to_bits(),
            self.stick as u64,
            self.transitions as u64,
        ]
    }
}

/// Asserts that two runs agree bit for bit at every communication point.
fn assert_bitwise(what: &str, a: &[Outputs], b: &[Outputs]) {
    assert_eq!(a.len(), b.len(), "{what}: different numbers of points");
    if let Some(k) = (0..a.len()).find(|&k| a[k].bits() != b[k].bits()) {
        panic!(
            "{what}: first difference at communication point {k}:\n  {:?}\n  {:?}\n(an FMU built from other source than this test also shows here: rerun `cargo run --release -p fmu-build`)",
            a[k], b[k]
        );
    }
}

/// An instance of StickSlipBeam, initialised.
struct Beam {
    inst: InstanceCS,
    vr: BeamVrs,
    /// The current communication point (s), accumulated as t + h, as the FMU does.
    t: f64,
}

impl Beam {
    /// Instantiates, sets the integer parameters `(vr, value)` and initialises for [0, STOP].
    fn start(import: &Fmi2Import, name: &str, integers: &[(u32, i32)]) -> Self {
        let vr = BeamVrs::of(import);
        let mut inst = import
            .instantiate_cs(name, false, false)
            .unwrap_or_else(|e| panic!("{name}: fmi2Instantiate failed: {e}"));
        Self::initialize(&mut inst, integers);
        Self { inst, vr, t: 0.0 }
    }

    fn initialize(inst: &mut InstanceCS, integers: &[(u32, i32)]) {
        inst.setup_experiment(None, 0.0, Some(STOP))
            .expect("fmi2SetupExperiment");
        Common::enter_initialization_mode(inst).expect("fmi2EnterInitializationMode");
        for &(vr, value) in integers {
            inst.set_integer(&[vr], &[value])
                .unwrap_or_else(|e| panic!("fmi2SetInteger({vr}, {value}): {e}"));
        }
        Common::exit_initialization_mode(inst).expect("fmi2ExitInitializationMode");
    }

    fn outputs(&mut self) -> Outputs {
        let mut r = [0.0; 5];
        self.inst
            .get_real(&self.vr.reals, &mut r)
            .expect("fmi2GetReal");
        let mut stick = [0i32; 1];
        self.inst
            .get_boolean(&[self.vr.stick], &mut stick)
            .expect("fmi2GetBoolean");
        let mut transitions = [0i32; 1];
        self.inst
            .get_integer(&[self.vr.transitions], &mut transitions)
            .expect("fmi2GetInteger");
        Outputs {
            tip_deflection: r[0],
            tip_velocity: r[1],
            relative_velocity: r[2],
            friction_force: r[3],
            holding_force: r[4],
            stick: stick[0] != 0,
            transitions: transitions[0],
        }
    }

    fn integer(&mut self, vr: u32) -> i32 {
        let mut v = [0i32; 1];
        self.inst
            .get_integer(&[vr], &mut v)
            .expect("fmi2GetInteger");
        v[0]
    }

    fn step(&mut self) {
        self.inst
            .do_step(self.t, H, true)
            .unwrap_or_else(|e| panic!("fmi2DoStep at t = {} s: {e}", self.t));
        self.t += H;
    }

    /// `n` communication steps; the outputs after each.
    fn run(&mut self, n: usize) -> Vec<Outputs> {
        (0..n)
            .map(|_| {
                self.step();
                self.outputs()
            })
            .collect()
    }

    /// The outputs now, then after each of `n` communication steps.
    fn run_from_start(&mut self, n: usize) -> Vec<Outputs> {
        let mut out = vec![self.outputs()];
        out.extend(self.run(n));
        out
    }
}

/// The communication points 0, h, 2h, ... as the importer accumulates them.
fn communication_points(n: usize) -> Vec<f64> {
    let mut t = 0.0;
    let mut points = vec![t];
    for _ in 0..n {
        t += H;
        points.push(t);
    }
    points
}

/// The library's simulation of the paper scene, with the FMU's fidelity choice.
fn direct_simulator(level: Option<FidelityLevel>) -> Simulator {
    let mut scene = CheckedScene::paper().into_scene();
    if let Some(level) = level {
        scene.fidelity.level = level;
    }
    let scene = scene.check().expect("the modified paper scene is valid");
    let law = stickslip::law_source::LawSource::resolve(&scene)
        .and_then(|law| law.law())
        .expect("the paper's law is analytical");
    let mut sim = Simulator::new(scene, law).expect("the paper scene builds");
    // The logEvents comparison wants every transition of the run.
    sim.keep_all_transitions();
    sim
}

/// The library run with `advance_to` at every communication point.
fn direct_advance_to(level: Option<FidelityLevel>) -> (Vec<Outputs>, Simulator) {
    let mut sim = direct_simulator(level);
    let mut out = vec![Outputs::of_simulator(&sim)];
    for &t in &communication_points(STEPS)[1..] {
        sim.advance_to(t).expect("advance_to");
        out.push(Outputs::of_simulator(&sim));
    }
    (out, sim)
}

/// The library run with `step()`, ten internal steps per communication step.
fn direct_steps(level: Option<FidelityLevel>) -> Vec<Outputs> {
    let mut sim = direct_simulator(level);
    let per = (H / sim.scene().time.step).round() as usize;
    assert_eq!(per, 10, "the paper's internal step is 1e-4 s");
    let mut out = vec![Outputs::of_simulator(&sim)];
    for _ in 0..STEPS {
        for _ in 0..per {
            sim.step().expect("step");
        }
        out.push(Outputs::of_simulator(&sim));
    }
    out
}

/// Index of the first communication point in slip.
fn first_slip(outputs: &[Outputs]) -> usize {
    outputs
        .iter()
        .position(|o| !o.stick)
        .expect("the tip breaks away before 1.2 s")
}

// ---------------------------------------------------------------------------------------
// a. The paper scene through the FMU equals the library's simulation bit for bit.

/// `level` set in the FMU and in the library's scene; None: both keep their default,
/// plane stress.
fn paper_scene_equals_library(level: Option<FidelityLevel>, tag: &str) {
    let import = import(FmuKind::StickSlipBeam);
    let name = format!("paper-{tag}");
    let vrs = BeamVrs::of(&import);
    let parameters: Vec<(u32, i32)> = level
        .map(|l| (vrs.fidelity, l.code()))
        .into_iter()
        .collect();
    let mut beam = Beam::start(&import, &name, &parameters);
    let expected_level = level.unwrap_or(FidelityLevel::PlaneStress);
    assert_eq!(beam.integer(vrs.fidelity), expected_level.code());
    Common::set_debug_logging(&mut beam.inst, true, &["logEvents"]).expect("logEvents on");

    let started = std::time::Instant::now();
    let fmu = beam.run_from_start(STEPS);
    let fmu_time = started.elapsed();
    let (advanced, sim) = direct_advance_to(level);
    let stepped = direct_steps(level);

    assert_bitwise(&format!("{tag}: FMU vs advance_to"), &fmu, &advanced);
    assert_bitwise(&format!("{tag}: step() vs advance_to"), &stepped, &advanced);

    // The run is not trivial: the beam deflects to ~8.4 mm and slips several times.
    let peak = fmu.iter().map(|o| o.tip_deflection).fold(0.0, f64::max);
    assert!(
        (8.0e-3..9.0e-3).contains(&peak),
        "{tag}: peak tip deflection {peak} m"
    );
    assert!(
        fmu[STEPS].transitions >= 10,
        "{tag}: only {} transitions",
        fmu[STEPS].transitions
    );

    // Breakaway: the library's first transition is stick -> slip at 0.4000 s, and the
    // FMU's first communication point in slip is the first one at or after it.
    let first = sim.transitions()[0];
    assert_eq!(first.to, ContactState::Slip);
    assert!(
        (first.time - BREAKAWAY).abs() < 0.5e-4,
        "{tag}: library breakaway at {} s",
        first.time
    );
    let points = communication_points(STEPS);
    let k = first_slip(&fmu);
    assert!(
        points[k - 1] < first.time && first.time <= points[k] + 1e-12,
        "{tag}: first slip at communication point {} s, transition at {} s",
        points[k],
        first.time
    );
    assert!(
        (points[k] - BREAKAWAY).abs() <= H * (1.0 + 1e-9),
        "{tag}: FMU breakaway at {} s",
        points[k]
    );

    // logEvents reports every transition, with the library's times.
    let events: Vec<String> = messages_of(&name)
        .into_iter()
        .filter(|(level, _)| *level == log::Level::Info)
        .map(|(_, text)| text)
        .collect();
    let expected: Vec<String> = sim
        .transitions()
        .iter()
        .map(|t| {
            let to = match t.to {
                ContactState::Stick => "stick",
                ContactState::Slip => "slip",
            };
            format!("t = {:.6} s: {to}", t.time)
        })
        .collect();
    assert_eq!(events, expected, "{tag}: logEvents messages");

    Common::terminate(&mut beam.inst).expect("fmi2Terminate");
    println!(
        "{tag}: {} points bitwise equal (advance_to and step()); FMU breakaway at {:.3} s, library transition at {:.6} s; peak {:.4} mm; {} transitions; FMU run {:.3} s",
        fmu.len(),
        points[k],
        first.time,
        peak * 1e3,
        fmu[STEPS].transitions,
        fmu_time.as_secs_f64()
    );
}

#[test]
fn a_paper_scene_beam_fidelity_equals_library_bit_for_bit() {
    paper_scene_equals_library(Some(FidelityLevel::Beam), "beam");
}

#[test]
fn a_paper_scene_modal_fidelity_equals_library_bit_for_bit() {
    paper_scene_equals_library(Some(FidelityLevel::Modal), "modal");
}

#[test]
fn a_paper_scene_default_plane_stress_equals_library_bit_for_bit() {
    paper_scene_equals_library(None, "plane-stress");
}

/// The FMU's time is absolute, the simulation's relative to the start time: a start at
/// 10 s changes no output. A communication step off the internal grid (2.5e-4 s = 2.5
/// internal steps) ends with a shorter landing step, as `advance_to` does.
#[test]
fn a_start_time_and_off_grid_communication_steps_equal_library() {
    let import = import(FmuKind::StickSlipBeam);
    let vrs = BeamVrs::of(&import);
    let (direct, _) = direct_advance_to(Some(FidelityLevel::Beam));

    let mut inst = import
        .instantiate_cs("start-at-10", false, false)
        .expect("fmi2Instantiate");
    inst.setup_experiment(None, 10.0, Some(10.0 + STOP))
        .expect("fmi2SetupExperiment");
    Common::enter_initialization_mode(&mut inst).expect("fmi2EnterInitializationMode");
    inst.set_integer(&[vrs.fidelity], &[FidelityLevel::Beam.code()])
        .expect("fmi2SetInteger");
    Common::exit_initialization_mode(&mut inst).expect("fmi2ExitInitializationMode");
    let mut shifted = Beam {
        inst,
        vr: vrs,
        t: 10.0,
    };
    let run = shifted.run_from_start(STEPS);
    assert_bitwise("start time 10 s vs library from 0", &run, &direct);

    let h = 2.5e-4;
    let mut beam = Beam::start(
        &import,
        "off-grid",
        &[(vrs.fidelity, FidelityLevel::Beam.code())],
    );
    let mut sim = direct_simulator(Some(FidelityLevel::Beam));
    let mut t = 0.0;
    let (mut fmu, mut library) = (Vec::new(), Vec::new());
    for _ in 0..(STOP / h).round() as usize {
        beam.inst.do_step(t, h, true).expect("fmi2DoStep");
        t += h;
        sim.advance_to(t).expect("advance_to");
        fmu.push(beam.outputs());
        library.push(Outputs::of_simulator(&sim));
    }
    assert_bitwise("h = 2.5e-4 s vs library advance_to", &fmu, &library);
    // Landing steps change the discretisation, so this is a different (close) run.
    let last = fmu.last().expect("points").tip_deflection;
    assert_ne!(last.to_bits(), direct[STEPS].tip_deflection.to_bits());
    assert!(first_slip(&fmu) > 0);
}

// ---------------------------------------------------------------------------------------
// b. FMU state: get, set, serialize, deserialize into a fresh instance.

/// Steps from 0.5 s to 0.8 s.
const STATE_AT: usize = 500;
const STATE_RUN: usize = 300;

#[test]
fn b_fmu_state_restores_bit_for_bit_also_in_a_fresh_instance() {
    let import1 = import(FmuKind::StickSlipBeam);
    let vrs = BeamVrs::of(&import1);
    let mut first = Beam::start(
        &import1,
        "state-first",
        &[(vrs.fidelity, FidelityLevel::Beam.code())],
    );
    first.run(STATE_AT);
    let t_saved = first.t;
    let at_saved = first.outputs();
    let state = first.inst.get_fmu_state().expect("fmi2GetFMUstate");
    let bytes = first
        .inst
        .serialize_fmu_state(&state)
        .expect("fmi2SerializeFMUstate");

    let run1 = first.run(STATE_RUN);
    // The interval holds real dynamics (a stick -> slip -> stick cycle), so a state
    // that lost anything would show.
    assert!(
        run1[STATE_RUN - 1].transitions > at_saved.transitions,
        "no transition between 0.5 and 0.8 s"
    );

    first
        .inst
        .set_fmu_state(&state)
        .ok()
        .expect("fmi2SetFMUstate");
    first.t = t_saved;
    assert_bitwise(
        "outputs right after fmi2SetFMUstate",
        &[first.outputs()],
        &[at_saved],
    );
    let run2 = first.run(STATE_RUN);
    assert_bitwise("re-run after fmi2SetFMUstate", &run1, &run2);

    // A fresh instance from a separate import (its own copy of the library), left at the
    // default fidelity (plane stress): the state carries the parameters, so restoring
    // rebuilds the beam model.
    let import2 = import(FmuKind::StickSlipBeam);
    let mut fresh = Beam::start(&import2, "state-fresh", &[]);
    assert_eq!(
        fresh.integer(vrs.fidelity),
        FidelityLevel::PlaneStress.code()
    );
    let restored = fresh
        .inst
        .deserialize_fmu_state(&bytes)
        .expect("fmi2DeSerializeFMUstate");
    fresh
        .inst
        .set_fmu_state(&restored)
        .ok()
        .expect("fmi2SetFMUstate of the deserialized state");
    assert_eq!(fresh.integer(vrs.fidelity), FidelityLevel::Beam.code());
    fresh.t = t_saved;
    assert_bitwise(
        "fresh instance at the restored point",
        &[fresh.outputs()],
        &[at_saved],
    );
    let run3 = fresh.run(STATE_RUN);
    assert_bitwise(
        "fresh instance (plane-stress before restore) vs first",
        &run1,
        &run3,
    );

    // A fresh instance already at the saved fidelity (the model is reused, not rebuilt).
    let mut same = Beam::start(
        &import2,
        "state-same",
        &[(vrs.fidelity, FidelityLevel::Beam.code())],
    );
    let restored = same
        .inst
        .deserialize_fmu_state(&bytes)
        .expect("fmi2DeSerializeFMUstate");
    same.inst
        .set_fmu_state(&restored)
        .ok()
        .expect("fmi2SetFMUstate");
    same.t = t_saved;
    let run4 = same.run(STATE_RUN);
    assert_bitwise(
        "fresh instance (beam before restore) vs first",
        &run1,
        &run4,
    );

    // And all of it is the library's own run.
    let (direct, _) = direct_advance_to(Some(FidelityLevel::Beam));
    assert_bitwise(
        "FMU state runs vs library",
        &run1,
        &direct[STATE_AT + 1..=STATE_AT + STATE_RUN],
    );
    println!(
        "state: {} bytes; 300 points bitwise equal in 4 runs (re-run, fresh plane-stress instance, fresh beam instance, library)",
        bytes.len()
    );
}

// ---------------------------------------------------------------------------------------
// c. fmi2Reset.

#[test]
fn c_reset_then_rerun_reproduces_the_first_run() {
    let import = import(FmuKind::StickSlipBeam);
    let vrs = BeamVrs::of(&import);
    let mut beam = Beam::start(
        &import,
        "reset",
        &[(vrs.fidelity, FidelityLevel::Beam.code())],
    );
    let run1 = beam.run_from_start(STEPS);
    Common::terminate(&mut beam.inst).expect("fmi2Terminate");
    Common::reset(&mut beam.inst).expect("fmi2Reset");

    // Reset restores the start values: the fidelity is plane stress again.
    beam.inst
        .setup_experiment(None, 0.0, Some(STOP))
        .expect("fmi2SetupExperiment after reset");
    Common::enter_initialization_mode(&mut beam.inst).expect("fmi2EnterInitializationMode");
    assert_eq!(
        beam.integer(vrs.fidelity),
        FidelityLevel::PlaneStress.code()
    );
    beam.inst
        .set_integer(&[vrs.fidelity], &[FidelityLevel::Beam.code()])
        .expect("fmi2SetInteger");
    Common::exit_initialization_mode(&mut beam.inst).expect("fmi2ExitInitializationMode");
    beam.t = 0.0;
    let run2 = beam.run_from_start(STEPS);
    assert_bitwise("run after fmi2Reset vs first run", &run1, &run2);
    assert!(run1[STEPS].transitions > 0);
}

// ---------------------------------------------------------------------------------------
// d. Instances in parallel threads.

fn run_alone(import: &Fmi2Import, name: &str, level: FidelityLevel) -> Vec<Outputs> {
    let vrs = BeamVrs::of(import);
    let mut beam = Beam::start(import, name, &[(vrs.fidelity, level.code())]);
    beam.run_from_start(STEPS)
}

#[test]
fn d_two_threads_give_the_same_outputs_as_one_instance_alone() {
    let shared = import(FmuKind::StickSlipBeam);
    let alone_beam = run_alone(&shared, "alone-beam", FidelityLevel::Beam);
    let alone_modal = run_alone(&shared, "alone-modal", FidelityLevel::Modal);
    assert_ne!(
        alone_beam[STEPS].tip_deflection.to_bits(),
        alone_modal[STEPS].tip_deflection.to_bits(),
        "beam and modal differ, so cross-talk would show"
    );

    // Each thread imports its own copy and instantiates there (InstanceCS is !Send).
    for levels in [
        [FidelityLevel::Beam, FidelityLevel::Beam],
        [FidelityLevel::Beam, FidelityLevel::Modal],
    ] {
        let results: Vec<Vec<Outputs>> = std::thread::scope(|s| {
            let handles: Vec<_> = levels
                .iter()
                .enumerate()
                .map(|(k, &level)| {
                    s.spawn(move || {
                        let own = import(FmuKind::StickSlipBeam);
                        run_alone(&own, &format!("thread-own-{k}-{}", level.code()), level)
                    })
                })
                .collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("thread"))
                .collect()
        });
        for (&level, result) in levels.iter().zip(&results) {
            let alone = if level == FidelityLevel::Beam {
                &alone_beam
            } else {
                &alone_modal
            };
            assert_bitwise("own import in a thread vs alone", result, alone);
        }
    }

    // Two threads with instances of ONE import share one loaded library.
    let results: Vec<Vec<Outputs>> = std::thread::scope(|s| {
        let shared = &shared;
        let a = s.spawn(move || run_alone(shared, "thread-shared-beam", FidelityLevel::Beam));
        let b = s.spawn(move || run_alone(shared, "thread-shared-modal", FidelityLevel::Modal));
        vec![a.join().expect("thread"), b.join().expect("thread")]
    });
    assert_bitwise(
        "shared import, beam thread vs alone",
        &results[0],
        &alone_beam,
    );
    assert_bitwise(
        "shared import, modal thread vs alone",
        &results[1],
        &alone_modal,
    );
}

// ---------------------------------------------------------------------------------------
// e. NeuralFriction.

struct FrictionVrs {
    law: u32,
    sliding_velocity: u32,
    normal_force: u32,
    /// friction_force, friction_force_magnitude, friction_coefficient, static_limit.
    outputs: [u32; 4],
}

impl FrictionVrs {
    fn of(import: &Fmi2Import) -> Self {
        Self {
            law: vr(import, "law"),
            sliding_velocity: vr(import, "sliding_velocity"),
            normal_force: vr(import, "normal_force"),
            outputs: [
                vr(import, "friction_force"),
                vr(import, "friction_force_magnitude"),
                vr(import, "friction_coefficient"),
                vr(import, "static_limit"),
            ],
        }
    }
}

fn start_friction(import: &Fmi2Import, name: &str, law: Option<LawChoice>) -> InstanceCS {
    let vrs = FrictionVrs::of(import);
    let mut inst = import
        .instantiate_cs(name, false, false)
        .unwrap_or_else(|e| panic!("{name}: fmi2Instantiate failed: {e}"));
    inst.setup_experiment(None, 0.0, Some(STOP))
        .expect("fmi2SetupExperiment");
    Common::enter_initialization_mode(&mut inst).expect("fmi2EnterInitializationMode");
    if let Some(law) = law {
        inst.set_integer(&[vrs.law], &[law.code()])
            .expect("set law");
    }
    Common::exit_initialization_mode(&mut inst).expect("fmi2ExitInitializationMode");
    inst
}

/// The friction outputs at (v, F_n).
fn friction_at(inst: &mut InstanceCS, vrs: &FrictionVrs, v: f64, normal: f64) -> [f64; 4] {
    inst.set_real(&[vrs.sliding_velocity, vrs.normal_force], &[v, normal])
        .expect("set inputs");
    let mut out = [0.0; 4];
    inst.get_real(&vrs.outputs, &mut out).expect("get outputs");
    out
}

/// The paper's law, Eq. 6, with mu_s = 0.5, mu_k = 0.2, alpha = 5 s/m.
fn paper_law(v: f64, normal: f64) -> f64 {
    v.signum() * (0.2 + 0.3 * stickslip::elementary::exp(-5.0 * v.abs())) * normal
}

/// Tolerance of the shipped network (`weights/paper-plain.json`) against Eq. 6 at 0.1 m/s
/// and 100 N. Measured: 37.921 N against 38.196 N, 0.72 %. The network is the paper's
/// plain one: 3 x 100 tanh, trained on 3500 noisy samples of Eq. 6 with v ~ N(0, 0.1 m/s)
/// and a weight penalty. Its error is smallest where the samples are dense and the law
/// is smooth, and 0.1 m/s is such a point, so 1 % holds the measurement with margin and
/// is three times tighter than the 3 % the brief allows.
const NEURAL_TOLERANCE_AT_01: f64 = 0.01;

/// Tolerance over the well-sampled band 5 mm/s <= |v| <= 0.2 m/s (within two standard
/// deviations of the training velocities, away from the jump at v = 0 that the network
/// smooths). Measured worst: 1.50 % at +0.15 m/s. Outside the band the error grows:
/// 6.4 % at +1 mm/s (the smoothed jump), 7.9 % at 0.35 m/s (sparse samples), 20 % at
/// 0.5 m/s, where the input is clamped to the training range (max 0.361 m/s).
const NEURAL_TOLERANCE_BAND: f64 = 0.02;

#[test]
fn e_neural_friction_fmu_matches_the_law() {
    let import = import(FmuKind::NeuralFriction);
    let vrs = FrictionVrs::of(&import);

    // Exponential law: Eq. 6 to 1e-12, signed, and the static limit mu_s F_n.
    let mut exponential = start_friction(
        &import,
        "friction-exponential",
        Some(LawChoice::Exponential),
    );
    let mut law = [0i32; 1];
    exponential.get_integer(&[vrs.law], &mut law).expect("law");
    assert_eq!(law[0], LawChoice::Exponential.code());
    for v in [0.1, -0.1] {
        let [force, magnitude, coefficient, limit] = friction_at(&mut exponential, &vrs, v, 100.0);
        let expected = v.signum() * (0.2 + 0.3 * stickslip::elementary::exp(-5.0 * 0.1)) * 100.0;
        assert!(
            (force - expected).abs() <= 1e-12,
            "exponential at v = {v}: {force} N, expected {expected} N"
        );
        assert_eq!(magnitude, force.abs());
        assert!((coefficient - expected.abs() / 100.0).abs() <= 1e-14);
        assert_eq!(limit, 50.0);
    }
    // Outputs follow inputs after a step too.
    exponential.do_step(0.0, H, true).expect("do_step");
    let [force, ..] = friction_at(&mut exponential, &vrs, 0.05, 80.0);
    assert!((force - paper_law(0.05, 80.0)).abs() <= 1e-12);

    // The default law is the shipped network.
    let mut neural = start_friction(&import, "friction-neural", None);
    neural.get_integer(&[vrs.law], &mut law).expect("law");
    assert_eq!(law[0], LawChoice::Neural.code());
    let [force, magnitude, _, limit] = friction_at(&mut neural, &vrs, 0.1, 100.0);
    let expected = paper_law(0.1, 100.0);
    let error_at_01 = (force - expected).abs() / expected.abs();
    assert!(
        error_at_01 <= NEURAL_TOLERANCE_AT_01,
        "neural at 0.1 m/s: {force} N vs {expected} N ({:.3} %)",
        100.0 * error_at_01
    );
    assert!(force > 0.0, "the force acts in the direction of v_rel");
    assert_eq!(magnitude, force.abs());
    assert_eq!(limit, 50.0, "static_limit is mu_s F_n exactly");

    let mut worst = (0.0f64, 0.0);
    for v in [
        -0.2, -0.15, -0.1, -0.08, -0.05, -0.03, -0.02, -0.01, -0.005, 0.005, 0.01, 0.02, 0.03,
        0.05, 0.08, 0.1, 0.15, 0.2,
    ] {
        let [force, ..] = friction_at(&mut neural, &vrs, v, 100.0);
        let error = (force - paper_law(v, 100.0)).abs() / paper_law(v, 100.0).abs();
        if error > worst.0 {
            worst = (error, v);
        }
    }
    assert!(
        worst.0 <= NEURAL_TOLERANCE_BAND,
        "neural: {:.3} % off at v = {} m/s",
        100.0 * worst.0,
        worst.1
    );
    // The FMU evaluates the same network as the library, and clamps the input to the
    // training range (max 0.361 m/s) like it.
    let network = stickslip::neural::NeuralLaw::paper_default().expect("shipped weights");
    let v_max = network
        .model()
        .features
        .iter()
        .find(|f| f.role == stickslip::neural::FeatureRole::SlidingVelocity)
        .expect("a sliding-velocity feature")
        .max;
    let [beyond, ..] = friction_at(&mut neural, &vrs, 0.5, 100.0);
    let [at_max, ..] = friction_at(&mut neural, &vrs, v_max, 100.0);
    assert!(v_max < 0.5);
    assert_eq!(beyond.to_bits(), at_max.to_bits());
    let mut library = network.into_friction_law().expect("a beam law");
    let [force, ..] = friction_at(&mut neural, &vrs, 0.1, 100.0);
    assert_eq!(force.to_bits(), library.sliding_force(0.1, 100.0).to_bits());
    println!(
        "neural friction: {force:.6} N at 0.1 m/s vs Eq. 6 {expected:.6} N ({:.3} %); worst {:.3} % at {} m/s",
        100.0 * error_at_01,
        100.0 * worst.0,
        worst.1
    );
}

// ---------------------------------------------------------------------------------------
// f. Coupled: StickSlipBeam (friction.law = external) + NeuralFriction (exponential).

/// How far the coupled tip deflection may stray from the monolithic run (m), up to the
/// second major slip (0.7051 s). The coupling holds the kinetic force of t_k over
/// [t_k, t_k + h] (zero-order hold), a first-order error: measured 45.6, 22.9, 9.3 and
/// 4.9 um at h = 1e-3, 5e-4, 2e-4 and 1e-4 s over the first major slip. 0.1 mm is twice
/// the h = 1e-3 s value. A coupling that passes a 5 % wrong kinetic force or static
/// limit is off by 1.34 mm or 0.71 mm here (measured), so both fail.
const COUPLED_TOLERANCE_FIRST_SLIP: f64 = 0.1e-3;

/// The same over the whole run to 1.2 s. Measured 0.222 mm (at 1.033 s). After the first
/// slip the deviation is no longer first order in h (0.25 mm at h = 5e-4 s, 0.09 mm at
/// 1e-4 s): the slip ends in bursts of re-stick and slip whose count and timing are
/// sensitive to any perturbation (35 transitions coupled, 33 monolithic), and each
/// moved burst shifts the following sawtooth a little. 0.5 mm (6 % of the 8.4 mm peak)
/// holds the measurement with a factor two and still fails a 5 % wrong kinetic force
/// or static limit (both 1.62 mm off over the run, measured).
const COUPLED_TOLERANCE: f64 = 0.5e-3;

/// Communication points up to (excluding) the second major slip at 0.7051 s.
const FIRST_SLIP_END: usize = 700;

#[test]
fn f_coupled_with_neural_friction_fmu_matches_the_monolithic_run() {
    let beam_import = import(FmuKind::StickSlipBeam);
    let friction_import = import(FmuKind::NeuralFriction);
    let vrs = BeamVrs::of(&beam_import);
    let fvrs = FrictionVrs::of(&friction_import);
    let mut beam = Beam::start(
        &beam_import,
        "coupled-beam",
        &[
            (vrs.fidelity, FidelityLevel::Beam.code()),
            (vrs.friction_law, FrictionLawKind::External.code()),
        ],
    );
    let mut friction = start_friction(
        &friction_import,
        "coupled-friction",
        Some(LawChoice::Exponential),
    );
    let friction_outputs = [fvrs.outputs[1], fvrs.outputs[3]];

    // Gauss-Seidel at each point t_k: the beam's v_rel(t_k) goes through NeuralFriction
    // (direct feedthrough, no state) and its force back into the beam, then both step
    // to t_k + h. (python-checks/stickslip_checks/cosim_convergence.py compares this
    // with one-pass Jacobi, where the beam gets the force of v_rel(t_{k-1}).)
    let mut coupled = vec![beam.outputs()];
    let mut t = 0.0;
    for _ in 0..STEPS {
        let v_rel = coupled.last().map(|o| o.relative_velocity).unwrap_or(0.0);
        friction
            .set_real(&[fvrs.sliding_velocity], &[v_rel])
            .expect("friction input");
        let mut f = [0.0; 2];
        friction
            .get_real(&friction_outputs, &mut f)
            .expect("friction outputs");
        beam.inst
            .set_real(&[vrs.kinetic_force, vrs.static_limit], &[f[0], f[1]])
            .expect("beam inputs");
        beam.step();
        friction.do_step(t, H, true).expect("friction do_step");
        t += H;
        coupled.push(beam.outputs());
    }

    // Monolithic: the same beam with friction.law = exponential, i.e. the library.
    let monolithic_fmu = {
        let mut mono = Beam::start(
            &beam_import,
            "coupled-monolithic",
            &[
                (vrs.fidelity, FidelityLevel::Beam.code()),
                (vrs.friction_law, FrictionLawKind::Exponential.code()),
            ],
        );
        mono.run_from_start(STEPS)
    };
    let (monolithic, _) = direct_advance_to(Some(FidelityLevel::Beam));
    assert_bitwise("monolithic FMU vs library", &monolithic_fmu, &monolithic);

    let points = communication_points(STEPS);
    let k = first_slip(&coupled);
    assert!(
        (points[k] - BREAKAWAY).abs() <= H * (1.0 + 1e-9),
        "coupled breakaway at {} s",
        points[k]
    );
    assert_eq!(
        k,
        first_slip(&monolithic),
        "same breakaway point as monolithic"
    );
    // Until breakaway the static limit is the only coupled quantity: identical.
    assert_bitwise(
        "coupled vs monolithic before breakaway",
        &coupled[..k],
        &monolithic[..k],
    );

    let deviation = |range: std::ops::Range<usize>| {
        range
            .map(|j| {
                (
                    (coupled[j].tip_deflection - monolithic[j].tip_deflection).abs(),
                    j,
                )
            })
            .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a })
    };
    let (first_worst, first_at) = deviation(0..FIRST_SLIP_END);
    let (worst, at) = deviation(0..STEPS + 1);
    let peak = monolithic
        .iter()
        .map(|o| o.tip_deflection)
        .fold(0.0, f64::max);
    println!(
        "coupled: breakaway at {:.3} s; max |tip deflection - monolithic| = {:.4} mm to 0.7 s (at {:.3} s), {:.4} mm to 1.2 s (at {:.3} s); peak {:.3} mm; {} vs {} transitions",
        points[k],
        first_worst * 1e3,
        points[first_at],
        worst * 1e3,
        points[at],
        peak * 1e3,
        coupled[STEPS].transitions,
        monolithic[STEPS].transitions
    );
    assert!(
        worst > 0.0,
        "the coupled run holds the force over h: not identical"
    );
    assert!(
        first_worst <= COUPLED_TOLERANCE_FIRST_SLIP,
        "coupled tip deflection {:.4} mm off the monolithic run at t = {:.3} s",
        first_worst * 1e3,
        points[first_at]
    );
    assert!(
        worst <= COUPLED_TOLERANCE,
        "coupled tip deflection {:.4} mm off the monolithic run at t = {:.3} s",
        worst * 1e3,
        points[at]
    );
}

// ---------------------------------------------------------------------------------------
// Illegal call sequence: the FMU refuses and logs why; fmi2Reset recovers.

#[test]
fn g_do_step_before_initialization_is_refused_and_logged() {
    let import = import(FmuKind::StickSlipBeam);
    let name = "illegal-sequence";
    let mut inst = import
        .instantiate_cs(name, false, false)
        .expect("fmi2Instantiate");
    assert!(matches!(inst.do_step(0.0, H, true), Err(Fmi2Error::Error)));
    let messages = messages_of(name);
    assert!(
        messages
            .iter()
            .any(|(level, text)| *level == log::Level::Error
                && text.starts_with("fmi2DoStep: illegal call sequence")),
        "logged: {messages:?}"
    );
    // The instance is in the Error mode now: only fmi2Reset (among these) brings it back.
    assert!(inst.setup_experiment(None, 0.0, Some(STOP)).is_err());
    Common::reset(&mut inst).expect("fmi2Reset");
    Beam::initialize(&mut inst, &[]);
    inst.do_step(0.0, H, true)
        .expect("fmi2DoStep after reset and initialisation");
}

// ---------------------------------------------------------------------------------------
// Known FMU bug (reported, not fixed here): reading an output in Initialization Mode
// builds the simulation with the inputs of that moment; a belt_speed set afterwards,
// still in Initialization Mode, reaches the simulation only as an input change, so the
// initial state (tip at belt speed, beam in the static shape moving with it) keeps the
// old belt speed. Run with `--ignored` to see it fail.

#[test]
fn h_outputs_read_in_initialization_mode_do_not_freeze_the_belt_speed() {
    let import = import(FmuKind::StickSlipBeam);
    let vrs = BeamVrs::of(&import);
    let belt_speed = vr(&import, "belt_speed");
    let mut inst = import
        .instantiate_cs("init-mode-get", false, false)
        .expect("fmi2Instantiate");
    inst.setup_experiment(None, 0.0, Some(STOP))
        .expect("fmi2SetupExperiment");
    Common::enter_initialization_mode(&mut inst).expect("fmi2EnterInitializationMode");
    inst.set_integer(&[vrs.fidelity], &[FidelityLevel::Beam.code()])
        .expect("fmi2SetInteger");
    let mut r = [0.0; 5];
    inst.get_real(&vrs.reals, &mut r)
        .expect("fmi2GetReal in Initialization Mode");
    inst.set_real(&[belt_speed], &[0.05])
        .expect("fmi2SetReal belt_speed");
    Common::exit_initialization_mode(&mut inst).expect("fmi2ExitInitializationMode");
    let mut beam = Beam {
        inst,
        vr: vrs,
        t: 0.0,
    };
    let run = beam.run_from_start(STEPS);

    let mut scene = CheckedScene::paper().into_scene();
    scene.fidelity.level = FidelityLevel::Beam;
    scene.loading.belt_speed = 0.05;
    let scene = scene.check().expect("valid scene");
    let law = stickslip::law_source::LawSource::resolve(&scene)
        .and_then(|law| law.law())
        .expect("analytical");
    let mut sim = Simulator::new(scene, law).expect("builds");
    let mut library = vec![Outputs::of_simulator(&sim)];
    for &t in &communication_points(STEPS)[1..] {
        sim.advance_to(t).expect("advance_to");
        library.push(Outputs::of_simulator(&sim));
    }
    // Actual: tip_velocity 0.02 m/s at t = 0, breakaway at 0.125 s instead of 0.160 s,
    // tip deflection up to 2.6 mm off.
    assert_bitwise(
        "belt_speed 0.05 set after an init-mode get vs library",
        &run,
        &library,
    );
}

// ---------------------------------------------------------------------------------------
// Bad parameters reach the importer: fmi2Error and the reason in the log.

#[test]
fn h_a_negative_modulus_fails_initialisation_with_the_reason_logged() {
    let import = import(FmuKind::StickSlipBeam);
    let name = "negative-modulus";
    let mut inst = import
        .instantiate_cs(name, false, false)
        .expect("fmi2Instantiate");
    inst.setup_experiment(None, 0.0, Some(STOP))
        .expect("fmi2SetupExperiment");
    Common::enter_initialization_mode(&mut inst).expect("fmi2EnterInitializationMode");
    inst.set_real(&[vr(&import, "material.youngs_modulus")], &[-1.0])
        .expect("a negative modulus is checked with the whole scene, not when set");
    assert!(matches!(
        Common::exit_initialization_mode(&mut inst),
        Err(Fmi2Error::Error)
    ));
    let messages = messages_of(name);
    assert!(
        messages.iter().any(|(level, text)| *level == log::Level::Error
            && text == "fmi2ExitInitializationMode: invalid scene: material.youngs_modulus = -1e0; it must be finite and > 0 (Pa)"),
        "logged: {messages:?}"
    );
}

#[test]
fn h_an_out_of_range_choice_code_is_refused_with_the_allowed_codes() {
    let import = import(FmuKind::StickSlipBeam);
    let name = "bad-choice";
    let mut inst = import
        .instantiate_cs(name, false, false)
        .expect("fmi2Instantiate");
    inst.setup_experiment(None, 0.0, Some(STOP))
        .expect("fmi2SetupExperiment");
    Common::enter_initialization_mode(&mut inst).expect("fmi2EnterInitializationMode");
    let law = vr(&import, "friction.law");
    // One past the last code; the message lists every allowed one, from the same enum.
    let beyond = FrictionLawKind::ALL.len() as i32 + 1;
    assert!(matches!(
        inst.set_integer(&[law], &[beyond]),
        Err(Fmi2Error::Error)
    ));
    let allowed: Vec<String> = FrictionLawKind::ALL
        .iter()
        .map(|k| format!("{} = {}", k.code(), k.name()))
        .collect();
    assert!(
        allowed.len() >= 6,
        "the laws with state are among them: {allowed:?}"
    );
    let expected = format!(
        "fmi2SetInteger: friction.law: {beyond} is not a FrictionModel code; allowed: {}",
        allowed.join(", ")
    );
    let messages = messages_of(name);
    assert!(
        messages
            .iter()
            .any(|(level, text)| *level == log::Level::Error && *text == expected),
        "expected {expected:?}, logged: {messages:?}"
    );
}

/// The FMI 3.0 FMUs, against the FMI 2.0 ones above.
#[path = "import3.rs"]
mod fmi3;
