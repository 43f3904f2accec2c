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
//!
//! This module holds what the tests share (the log backend, the import, the instances
//! and the library runs); the tests are in one module per concept: the paper scene
//! (`paper_scene`), saved FMU states (`saved_state`), fmi2Reset (`reset`), instances in
//! threads (`threads`), NeuralFriction (`neural_friction`), the coupled run (`coupled`),
//! Initialization Mode (`initialization_mode`), refused calls and parameters
//! (`refusals`); the FMI 3.0 FMUs are in `fmi3`.

use crate::value_reference::vr;
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceCS};
use fmi::fmi2::Fmi2Error;
use fmi::traits::{FmiImport, FmiStatus};
use std::path::PathBuf;
use std::sync::{Mutex, Once};
use stickslip::choice::Choice;
use stickslip::contact::ContactState;
use stickslip::friction::FrictionLawKind;
use stickslip::scene::{CheckedScene, FidelityLevel};
use stickslip::simulation::Simulator;
use stickslip_fmi::friction::NeuralFrictionLaw;
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
// NeuralFriction (its tests are in `neural_friction` and `coupled`).

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

fn start_friction(import: &Fmi2Import, name: &str, law: Option<NeuralFrictionLaw>) -> InstanceCS {
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

mod coupled;
mod export;
mod initialization_mode;
mod neural_friction;
mod paper_scene;
mod refusals;
mod reset;
mod saved_state;
mod threads;

/// The FMI 3.0 FMUs, against the FMI 2.0 ones above.
#[path = "import3.rs"]
mod fmi3;
