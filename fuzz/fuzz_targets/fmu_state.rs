//! Serialized FMU state, as an importer hands it to fmi2DeSerializeFMUstate and then
//! fmi2SetFMUstate, through the plain-Rust `Instance` API that `ffi` forwards to.
//!
//! One instance of each FMU (StickSlipBeam, NeuralFriction) is created per process and
//! reset before each input. The bytes are deserialized; a state that parses is set on
//! the instance its GUID names (the other FMU would refuse it at once), then the
//! harness reads every variable, saves, re-serializes and restores the FMU's own state,
//! leaves initialization mode if the state was saved there, takes one short
//! communication step and saves again.
//!
//! Checked properties (a panic is a finding):
//! - nothing panics, whatever the bytes;
//! - `to_bytes` of a parsed state reads back and writes the same bytes again;
//! - a state that was set once can be set again (the simulation-reuse path);
//! - the FMU's own state, serialized and deserialized, restores (unless saved in the
//!   Error mode, which the FMU documents as not restorable).

#![no_main]

use libfuzzer_sys::fuzz_target;
use serde_json::Value;
use std::cell::RefCell;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::instance::{Instance, Mode, SavedState};
use stickslip_fmi::variables::BaseType;
use stickslip_fmi::model::Model;
use stickslip::scene::Scene;
use stickslip_fuzz::{fmu_scene_is_cheap, resources, weights_name_stays_in_resources};

/// Most internal time steps one fuzz iteration may take.
const MAX_STEPS_PER_INPUT: f64 = 200.0;

struct Fmus {
    beam: Instance<StickSlipBeam>,
    friction: Instance<NeuralFriction>,
}

fn instantiate<M: Model>(name: &str) -> Instance<M> {
    Instance::new(name, Some(&resources()), false, Box::new(|_, _, _| {}))
        .unwrap_or_else(|e| panic!("cannot instantiate {name} on {:?}: {e}", resources()))
}

thread_local! {
    static FMUS: RefCell<Fmus> = RefCell::new(Fmus {
        beam: instantiate("fuzz-beam"),
        friction: instantiate("fuzz-friction"),
    });
}

fuzz_target!(|data: &[u8]| {
    FMUS.with(|fmus| exercise(&mut fmus.borrow_mut(), data));
});

fn exercise(fmus: &mut Fmus, data: &[u8]) {
    // fmi2DeSerializeFMUstate checks the model part as the FMU the GUID names would:
    // the bytes go to that FMU (the beam's for any other GUID, which it refuses).
    // That check reads the weights a state names: outside `resources/` nothing is
    // deserialized (see `affordable`).
    let friction_guid = stickslip_fmi::FmuKind::NeuralFriction.guid();
    let parsed = SavedState::from_bytes(data);
    if parsed.as_ref().is_ok_and(|s| !affordable(&s.model)) {
        return;
    }
    let for_friction = parsed.is_ok_and(|s| s.guid == friction_guid);
    let deserialized = if for_friction {
        fmus.friction.reset();
        fmus.friction.deserialize_state(data)
    } else {
        fmus.beam.reset();
        fmus.beam.deserialize_state(data)
    };
    let Ok(state) = deserialized else {
        return;
    };
    let bytes = state.to_bytes();
    let again = SavedState::from_bytes(&bytes)
        .unwrap_or_else(|e| panic!("to_bytes wrote a state that does not read back: {e}"));
    assert_eq!(again.to_bytes(), bytes, "to_bytes is not stable");

    if state.guid == friction_guid {
        drive(&mut fmus.friction, &state);
    } else {
        drive(&mut fmus.beam, &state);
    }
}

fn drive<M: Model>(fmu: &mut Instance<M>, state: &SavedState) {
    fmu.reset();
    if fmu.set_state(state).is_err() {
        return;
    }
    assert!(
        fmu.set_state(state).is_ok(),
        "a state that was set once is refused the second time"
    );
    read_everything(fmu);
    restore_own_state(fmu);

    if fmu.mode() == Mode::InitializationMode && fmu.exit_initialization_mode().is_err() {
        return;
    }
    if fmu.mode() == Mode::StepComplete {
        let Ok(now) = fmu.get_state() else {
            panic!("fmi2GetFMUstate refused in StepComplete");
        };
        if let Some(h) = short_step(&now) {
            let _ = fmu.do_step(fmu.time(), h);
            read_everything(fmu);
            restore_own_state(fmu);
        }
    }
}

/// Every variable, one get call per base type (outputs are computed on the way).
fn read_everything<M: Model>(fmu: &mut Instance<M>) {
    let vrs = |base: BaseType| -> Vec<u32> {
        M::variables()
            .iter()
            .filter(|v| v.access.base_type() == base)
            .map(|v| v.value_reference)
            .collect()
    };
    let reals = vrs(BaseType::Real);
    let _ = fmu.get_real(&reals, &mut vec![0.0; reals.len()]);
    let integers = vrs(BaseType::Integer);
    let _ = fmu.get_integer(&integers, &mut vec![0; integers.len()]);
    let booleans = vrs(BaseType::Boolean);
    let _ = fmu.get_boolean(&booleans, &mut vec![false; booleans.len()]);
    let _ = fmu.get_string(&vrs(BaseType::String));
}

/// fmi2GetFMUstate, fmi2SerializeFMUstate, fmi2DeSerializeFMUstate, fmi2SetFMUstate.
fn restore_own_state<M: Model>(fmu: &mut Instance<M>) {
    let own = fmu
        .get_state()
        .expect("fmi2GetFMUstate is allowed in every mode");
    let bytes = fmu
        .serialize_state(&own)
        .expect("fmi2SerializeFMUstate is allowed in every mode");
    let back = fmu
        .deserialize_state(&bytes)
        .unwrap_or_else(|_| panic!("the FMU's own state does not deserialize"));
    assert_eq!(back, own, "the FMU's own state changed in serialization");
    if own.mode != Mode::Error {
        assert!(
            fmu.set_state(&back).is_ok(),
            "the FMU's own state (mode {:?}) does not restore",
            own.mode
        );
    }
}

/// The length of a communication step of a few internal steps for a beam state saved
/// in StepComplete, or None if the beam's simulation lags so far behind the instance's
/// time that the step would take more than `MAX_STEPS_PER_INPUT` internal steps. The
/// friction FMU has no time steps.
fn short_step(state: &SavedState) -> Option<f64> {
    let Some(run) = state.model.get("running") else {
        return Some(1e-3);
    };
    let number = |path: &str| run.pointer(path).and_then(Value::as_f64);
    let dt = number("/built_from/scene/time/step")?;
    let start = number("/start_time")?;
    let sim_time = number("/state/time")?;
    let h = 2.5 * dt;
    let steps = (state.time + h - start - sim_time) / dt;
    (steps.is_finite() && steps <= MAX_STEPS_PER_INPUT).then_some(h)
}

/// False for states whose scenes would build a large model or resolve `auto` (which
/// runs the scene several times), or that name weights outside `resources/` (see
/// `stickslip_fuzz`).
fn affordable(model: &Value) -> bool {
    if !weights_names(model).all(weights_name_stays_in_resources) {
        return false;
    }
    // Version-1 states keep the auto request beside the scene.
    let auto_v1 = ["/settings/fidelity_auto", "/running/built_from/fidelity_auto"]
        .iter()
        .any(|path| model.pointer(path) == Some(&Value::Bool(true)));
    if auto_v1 {
        return false;
    }
    ["/settings/scene", "/running/built_from/scene"]
        .iter()
        .filter_map(|path| model.pointer(path))
        .all(
            |scene| match serde_json::from_value::<Scene>(scene.clone()) {
                Ok(scene) => fmu_scene_is_cheap(&scene),
                // The model's restore refuses it before building anything.
                Err(_) => true,
            },
        )
}

/// Every string stored under a key `weights`, at any depth.
fn weights_names(value: &Value) -> Box<dyn Iterator<Item = &str> + '_> {
    match value {
        Value::Object(map) => Box::new(map.iter().flat_map(|(key, v)| {
            let own = (key == "weights").then(|| v.as_str()).flatten();
            own.into_iter().chain(weights_names(v))
        })),
        Value::Array(items) => Box::new(items.iter().flat_map(weights_names)),
        _ => Box::new(std::iter::empty()),
    }
}
