//! The FMI state machine, parameter and input checks, stepping and FMU state of both
//! models, driven through `Instance` (the plain-Rust side of the C interface).
//!
//! The helpers the tests share are here; the tests are in one module per concept: the
//! state machine (`state_machine`), setting and reading values (`get_set`), fmi2DoStep
//! (`stepping`), saved FMU states (`saved_states`), the friction law and its network
//! (`friction`), `fidelity.level = auto` (`fidelity_auto`).

use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use stickslip::choice::Choice;
use stickslip::friction::FrictionLawKind;
use stickslip::law_source::LawSource;
use stickslip::scene::{CheckedScene, FidelityLevel, Scene};
use stickslip::simulation::Simulator;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::instance::{Instance, Logger, Mode, SavedState, Status, STATE_VERSION};
use stickslip_fmi::model::Model;
use stickslip_fmi::variables::Causality;
use stickslip_fmi::FmuKind;
use stickslip_tests::vr;

type Log = Arc<Mutex<Vec<(Status, String, String)>>>;

fn collecting_logger() -> (Logger, Log) {
    let log: Log = Arc::new(Mutex::new(Vec::new()));
    let sink = log.clone();
    let logger: Logger = Box::new(move |status, category, message| {
        sink.lock()
            .unwrap()
            .push((status, category.to_string(), message.to_string()));
    });
    (logger, log)
}

/// The shipped weights folder stands in for the unpacked resources/.
fn resources() -> PathBuf {
    stickslip_tests::weights_dir()
}

fn beam(logging_on: bool) -> (Instance<StickSlipBeam>, Log) {
    let (logger, log) = collecting_logger();
    let instance = Instance::new("beam", Some(&resources()), logging_on, logger).unwrap();
    (instance, log)
}

fn logged(log: &Log, needle: &str) -> bool {
    log.lock()
        .unwrap()
        .iter()
        .any(|(_, _, m)| m.contains(needle))
}

/// Beam fidelity (fast) and the experiment 0..1.2 s, initialised.
fn initialized_beam(level: FidelityLevel) -> (Instance<StickSlipBeam>, Log) {
    let (mut b, log) = beam(false);
    b.setup_experiment(0.0, Some(1.2)).unwrap();
    b.set_integer(&[vr::<StickSlipBeam>("fidelity.level")], &[level.code()])
        .unwrap();
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    (b, log)
}

fn tip(b: &mut Instance<StickSlipBeam>) -> f64 {
    let mut out = [0.0];
    b.get_real(&[vr::<StickSlipBeam>("tip_deflection")], &mut out)
        .unwrap();
    out[0]
}

fn run(b: &mut Instance<StickSlipBeam>, from: f64, to: f64, h: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let n = ((to - from) / h).round() as usize;
    for k in 0..n {
        b.do_step(from + k as f64 * h, h).unwrap();
        out.push(tip(b));
    }
    out
}

mod fidelity_auto;
mod friction;
mod get_set;
mod saved_states;
mod state_machine;
mod stepping;
