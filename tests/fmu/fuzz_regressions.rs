//! Inputs that made a parser of outside bytes panic, each inlined as the bytes that
//! reached it, now refused with a clear error. The fuzz targets are in `fuzz/` (run
//! them with `scripts/fuzz.sh`); add every new crash here.
//!
//! The inputs below were found by reading the parsers while writing the fuzz targets,
//! and confirmed to crash the fuzz target binaries (`fuzz/target/.../scene FILE`,
//! `.../fmu_state FILE`); the timed fuzz runs did not reach them by themselves.
//!
//! `cargo test --release -p stickslip-tests --test fmu fuzz_regressions`

use std::sync::{Arc, Mutex};
use stickslip::scene::Scene;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::instance::Instance;
use stickslip_fmi::FmuKind;

/// Parses a scene file's text as `Scene::load` does for its extension, and checks it.
fn check_scene(text: &[u8], json: bool) -> Result<(), stickslip::scene::SceneError> {
    let text = std::str::from_utf8(text).unwrap();
    let scene = if json {
        Scene::from_json_str(text)
    } else {
        Scene::from_toml_str(text)
    }
    .expect("the scene parses; the check must refuse it");
    scene.check().map(|_| ())
}

/// Scene file (fuzz target `scene`): a plane-stress element far smaller than the beam
/// makes more elements than usize counts. Counting the mesh nodes in `Scene::check`
/// overflowed: "attempt to multiply with overflow" with overflow checks (the fuzz and
/// test builds); in the release binary the count wrapped, and for 2^63 elements along
/// the length it wrapped to 6 degrees of freedom, passed the MAX_DOFS guard, and
/// `stickslip simulate --scene` died building the mesh ("capacity overflow").
#[test]
fn scene_with_more_elements_than_usize_holds_is_refused() {
    // 8 m / 2^-60 m = 2^63 elements along, 1 through the height.
    const WRAPS_UNDER_THE_GUARD: &[u8] = b"[geometry]\nlength = 8.0\nheight = 4.336808689942018e-19\n\n[fidelity]\nelement_size = 8.673617379884035e-19\n";
    const LONG_BEAM: &[u8] = b"[geometry]\nlength = 1e10\n[fidelity]\nelement_size = 1e-10\n";
    // Both divisions saturate at usize::MAX.
    const SATURATED: &[u8] =
        br#"{"geometry": {"length": 1e300, "height": 1e299}, "fidelity": {"element_size": 1e-300}}"#;
    for (bytes, json) in [
        (WRAPS_UNDER_THE_GUARD, false),
        (LONG_BEAM, false),
        (SATURATED, true),
    ] {
        let error = check_scene(bytes, json).unwrap_err();
        assert_eq!(error.field(), Some("fidelity.element_size"), "{error}");
        assert!(error.to_string().contains("degrees of freedom"), "{error}");
    }
    // The limit itself still holds: the paper's mesh passes, a fine one does not.
    assert!(check_scene(b"", false).is_ok());
    let fine = check_scene(b"[fidelity]\nelement_size = 1e-4\n", false).unwrap_err();
    assert_eq!(fine.field(), Some("fidelity.element_size"));
}

/// GUID of StickSlipBeam when the states below were recorded. The GUID is a hash of the
/// interface, so it is replaced by the current one before use: otherwise an interface
/// change would make these states fail the GUID check instead of the check they test.
const RECORDED_GUID: &str = "{680ce4ed-0068-5ae3-fd82-aeda6a747be9}";

/// A beam state saved after two steps of a one-element beam, with the step counter
/// (`step`) or the steps since the last irregular step (`steps_since_anchor`) at
/// u64::MAX.
const STEP_AT_U64_MAX: &[u8] = br#"{"format":"stickslip-fmu-state","version":1,"guid":"{680ce4ed-0068-5ae3-fd82-aeda6a747be9}","mode":"step-complete","time":0.002,"start_time":0,"stop_time":null,"model":{"settings":{"scene":{"fidelity":{"level":"beam","beam_elements":1},"time":{"step":0.001}},"friction_model":"exponential","weights":"paper-plain.json","inputs":{"belt_speed":0.02,"normal_force":100,"kinetic_force":20,"static_limit":50}},"initialized":true,"running":{"built_from":{"scene":{"fidelity":{"level":"beam","beam_elements":1},"time":{"step":0.001}},"friction_model":"exponential","weights":"paper-plain.json","inputs":{"belt_speed":0.02,"normal_force":100,"kinetic_force":20,"static_limit":50}},"start_time":0,"state":{"step":18446744073709551615,"time":0.002,"kinematics":{"displacement":[0,0],"velocity":[0,0],"acceleration":[0,0]},"contact":"Stick","relative_velocity":0,"contact_force":0,"holding_force":0,"transition_count":0},"transitions":[]}}}"#;
const STEPS_SINCE_ANCHOR_AT_U64_MAX: &[u8] = br#"{"format":"stickslip-fmu-state","version":1,"guid":"{680ce4ed-0068-5ae3-fd82-aeda6a747be9}","mode":"step-complete","time":0.002,"start_time":0,"stop_time":null,"model":{"settings":{"scene":{"fidelity":{"level":"beam","beam_elements":1},"time":{"step":0.001}},"friction_model":"exponential","weights":"paper-plain.json","inputs":{"belt_speed":0.02,"normal_force":100,"kinetic_force":20,"static_limit":50}},"initialized":true,"running":{"built_from":{"scene":{"fidelity":{"level":"beam","beam_elements":1},"time":{"step":0.001}},"friction_model":"exponential","weights":"paper-plain.json","inputs":{"belt_speed":0.02,"normal_force":100,"kinetic_force":20,"static_limit":50}},"start_time":0,"state":{"step":2,"time":0.002,"kinematics":{"displacement":[0,0],"velocity":[0,0],"acceleration":[0,0]},"contact":"Stick","relative_velocity":0,"contact_force":0,"holding_force":0,"transition_count":0,"steps_since_anchor":18446744073709551615},"transitions":[]}}}"#;

type Log = Arc<Mutex<Vec<String>>>;

fn beam() -> (Instance<StickSlipBeam>, Log) {
    let log: Log = Arc::default();
    let sink = log.clone();
    let resources = stickslip_tests::weights_dir();
    let instance = Instance::new(
        "fuzz-regression",
        Some(&resources),
        false,
        Box::new(move |_, _, message| sink.lock().unwrap().push(message.to_string())),
    )
    .unwrap();
    (instance, log)
}

/// fmi2DeSerializeFMUstate + fmi2SetFMUstate (fuzz target `fmu_state`) on `bytes`, then
/// one fmi2DoStep if the state was accepted; returns the log.
fn deserialize_set_and_step(bytes: &[u8]) -> (bool, Vec<String>) {
    let text = std::str::from_utf8(bytes)
        .unwrap()
        .replace(RECORDED_GUID, &FmuKind::StickSlipBeam.guid());
    let (mut fmu, log) = beam();
    let state = fmu
        .deserialize_state(text.as_bytes())
        .expect("the state is well-formed; fmi2SetFMUstate must refuse it");
    let accepted = fmu.set_state(&state).is_ok();
    if accepted {
        // Before the fix this step panicked: "attempt to add with overflow".
        let _ = fmu.do_step(fmu.time(), 1e-3);
    }
    let messages = log.lock().unwrap().clone();
    (accepted, messages)
}

/// Serialized FMU state: a step counter at u64::MAX was accepted, and the next
/// fmi2DoStep overflowed it (`state.step += 1` in `Simulator::take_step`), a panic
/// that the C interface turned into fmi2Error only by catching it.
#[test]
fn fmu_state_with_step_counter_at_u64_max_is_refused() {
    for (bytes, field) in [
        (STEP_AT_U64_MAX, "step"),
        (STEPS_SINCE_ANCHOR_AT_U64_MAX, "steps_since_anchor"),
    ] {
        let (accepted, log) = deserialize_set_and_step(bytes);
        assert!(!accepted, "{field} = u64::MAX was accepted");
        let expected = format!("{field} = 18446744073709551615 is above 2^53");
        assert!(
            log.iter()
                .any(|m| m.starts_with("fmi2SetFMUstate") && m.contains(&expected)),
            "{log:?}"
        );
    }
    // The same state with real counters restores and steps.
    let sane = std::str::from_utf8(STEP_AT_U64_MAX)
        .unwrap()
        .replace("\"step\":18446744073709551615", "\"step\":2");
    let (accepted, log) = deserialize_set_and_step(sane.as_bytes());
    assert!(accepted, "{log:?}");
    assert!(log.is_empty(), "{log:?}");
}

/// The same two-step state with consistent counters, and its clocks changed.
fn two_step_state(instance_time: &str, mode: &str, stop_time: &str) -> Vec<u8> {
    std::str::from_utf8(STEP_AT_U64_MAX)
        .unwrap()
        .replace("\"step\":18446744073709551615", "\"step\":2")
        .replace(
            "\"time\":0.002,\"start_time\"",
            &format!("\"time\":{instance_time},\"start_time\""),
        )
        .replace(
            "\"mode\":\"step-complete\"",
            &format!("\"mode\":\"{mode}\""),
        )
        .replace("\"stop_time\":null", &format!("\"stop_time\":{stop_time}"))
        .into_bytes()
}

/// Serialized FMU state whose FMU time is far ahead of its simulation (found by review
/// of the restore path, not by the fuzzer): it was accepted, and the next fmi2DoStep
/// from the FMU time integrated through the gap, up to 1e9 internal steps for one call.
/// Now the two clocks must agree to half a time step, and the FMU clock must be one an
/// instance could have reached.
#[test]
fn fmu_state_with_disagreeing_clocks_is_refused() {
    // The unchanged state restores and steps: the check does not refuse honest states.
    let (accepted, log) =
        deserialize_set_and_step(&two_step_state("0.002", "step-complete", "null"));
    assert!(accepted, "{log:?}");
    for (bytes, expected) in [
        (
            two_step_state("1000000", "step-complete", "null"),
            "the two clocks must agree",
        ),
        (
            two_step_state("0.0026", "step-complete", "null"),
            "the two clocks must agree",
        ),
        (
            two_step_state("0.002", "step-complete", "0.001"),
            "past its stop time",
        ),
        (
            two_step_state("-1", "step-complete", "null"),
            "before its start time",
        ),
        (
            two_step_state("0.002", "initialization-mode", "null"),
            "before stepping the time must equal the start time",
        ),
    ] {
        let text = std::str::from_utf8(&bytes)
            .unwrap()
            .replace(RECORDED_GUID, &FmuKind::StickSlipBeam.guid());
        let (mut fmu, log) = beam();
        // The instance-level checks refuse at deserialisation, the model's at restore.
        let refused = match fmu.deserialize_state(text.as_bytes()) {
            Err(_) => true,
            Ok(state) => fmu.set_state(&state).is_err(),
        };
        let log = log.lock().unwrap().clone();
        assert!(refused, "accepted: {text}");
        assert!(
            log.iter().any(|m| m.contains(expected)),
            "{expected}: {log:?}"
        );
        // A refused state leaves the instance usable and where it was.
        assert_eq!(fmu.time(), 0.0);
    }
}
