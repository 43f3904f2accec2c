//! Tampered values in a serialized FMU state, with a valid checksum (anyone can
//! recompute it), are refused as setting them and initialising would refuse them: by
//! fmi2DeSerializeFMUstate / fmi3DeserializeFMUState and by fmi2SetFMUstate /
//! fmi3SetFMUState, with the parameter's name in the logged reason, and the instance's
//! model left as it was.

use super::state_corruption::{beam_at, friction_at, Log};
use serde_json::Value;
use stickslip::friction::FrictionLawKind;
use stickslip_fmi::friction::NeuralFrictionLaw;
use stickslip_fmi::instance::{with_checksum, FmiVersion, Instance, SavedState};
use stickslip_fmi::model::Model;

/// A tampering: JSON pointers into the saved state and the JSON text each gets (text,
/// so that numbers JSON values cannot hold, such as 1e400, can be written), and what
/// the logged reason must contain.
struct Tamper {
    edits: &'static [(&'static str, &'static str)],
    reason: &'static str,
}

const MARK: &str = "@@tampered@@";

/// The state's bytes with the edits, and a valid checksum.
fn tampered_bytes(state: &SavedState, edits: &[(&str, &str)]) -> Vec<u8> {
    let mut json = serde_json::to_value(state).unwrap();
    for (k, (pointer, _)) in edits.iter().enumerate() {
        *json
            .pointer_mut(pointer)
            .unwrap_or_else(|| panic!("no {pointer} in the state")) =
            Value::String(format!("{MARK}{k}"));
    }
    let mut text = serde_json::to_string(&json).unwrap();
    for (k, (_, value)) in edits.iter().enumerate() {
        text = text.replace(&format!("\"{MARK}{k}\""), value);
    }
    with_checksum(text.as_bytes())
}

fn last_message(log: &Log) -> String {
    log.lock().unwrap().last().cloned().unwrap_or_default()
}

/// Applies each tampering to `instance`'s current state: refused by deserialization and
/// (where the JSON parses) by fmi2SetFMUstate, the reason containing `reason`, the
/// model unchanged; the instance then restores its own state. Returns the table rows.
fn check_refusals<M: Model>(
    instance: &mut Instance<M>,
    log: &Log,
    label: &str,
    cases: &[Tamper],
) -> Vec<String> {
    let saved = instance.get_state().unwrap();
    let mut rows = Vec::new();
    for case in cases {
        let bytes = tampered_bytes(&saved, case.edits);
        let what = case
            .edits
            .iter()
            .map(|(p, v)| format!("`{p}` = {v}"))
            .collect::<Vec<_>>()
            .join(", ");
        assert!(
            instance.deserialize_state(&bytes).is_err(),
            "{label}: {what} deserialized"
        );
        let message = last_message(log);
        if !message.contains(case.reason) {
            // Collected, so that one run lists every mismatch.
            rows.push(format!(
                "MISMATCH {label}: {what}: {message:?} lacks {:?}",
                case.reason
            ));
        }
        // The same state handed to fmi2SetFMUstate directly (not through bytes).
        if let Ok(state) = serde_json::from_slice::<SavedState>(stickslip_tests::state_json(&bytes))
        {
            let before = instance.get_state().unwrap();
            assert!(instance.set_state(&state).is_err(), "{label}: {what} set");
            let set_message = last_message(log);
            if !set_message.contains(case.reason) {
                rows.push(format!("MISMATCH {label}: {what}: set: {set_message:?}"));
            }
            let after = instance.get_state().unwrap();
            assert_eq!(
                after.model, before.model,
                "{label}: {what} changed the model"
            );
            assert_eq!(after.time, before.time, "{label}: {what}");
        }
        instance.set_state(&saved).unwrap();
        rows.push(format!("| {label} | {what} | {message} |"));
    }
    rows
}

const SETTINGS_FORCE: &str = "/model/settings/inputs/normal_force";
const BUILT_FORCE: &str = "/model/running/built_from/inputs/normal_force";
const BEAM_LAW_STATE: &str = "/model/running/state/law_state";

fn beam_cases() -> Vec<Tamper> {
    vec![
        Tamper {
            edits: &[(SETTINGS_FORCE, "-100"), (BUILT_FORCE, "-100")],
            reason: "normal_force: -100 must be >= 0",
        },
        Tamper {
            // NaN, as serde_json writes it.
            edits: &[(SETTINGS_FORCE, "null")],
            reason: "settings.inputs.normal_force",
        },
        Tamper {
            edits: &[(SETTINGS_FORCE, "1e400")],
            reason: "at model",
        },
        Tamper {
            edits: &[
                ("/model/settings/scene/material/youngs_modulus", "0"),
                (
                    "/model/running/built_from/scene/material/youngs_modulus",
                    "0",
                ),
            ],
            reason: "material.youngs_modulus = 0e0; it must be finite and > 0",
        },
        Tamper {
            edits: &[("/model/settings/scene/material/youngs_modulus", "-1")],
            reason: "differs from settings at scene.material.youngs_modulus",
        },
        Tamper {
            edits: &[
                ("/model/settings/scene/material/poisson_ratio", "0.5"),
                (
                    "/model/running/built_from/scene/material/poisson_ratio",
                    "0.5",
                ),
            ],
            reason: "material.poisson_ratio = 5e-1; it must be in (-1, 0.5)",
        },
        Tamper {
            edits: &[(BEAM_LAW_STATE, "[1e-6, 2e-6]")],
            reason: "2 values for a state of 1",
        },
        Tamper {
            edits: &[(BEAM_LAW_STATE, "[]")],
            reason: "0 values for a state of 1",
        },
        Tamper {
            edits: &[("/model/settings/scene/friction/law", "\"bogus\"")],
            reason: "settings.scene.friction.law: unknown variant `bogus`",
        },
        Tamper {
            edits: &[("/model/settings/scene/friction/law", "7")],
            reason: "settings.scene.friction.law",
        },
        Tamper {
            edits: &[
                ("/model/settings/scene/fidelity/beam_elements", "0"),
                (
                    "/model/running/built_from/scene/fidelity/beam_elements",
                    "0",
                ),
            ],
            reason: "fidelity.beam_elements: 0 is outside [1,",
        },
        Tamper {
            edits: &[
                ("/model/settings/scene/fidelity/modes", "4294967301"),
                (
                    "/model/running/built_from/scene/fidelity/modes",
                    "4294967301",
                ),
            ],
            reason: "fidelity.modes: 2147483647 is outside [1, 200]",
        },
        Tamper {
            edits: &[
                ("/model/settings/scene/time/end", "1e300"),
                ("/model/running/built_from/scene/time/end", "1e300"),
            ],
            reason: "scene.time.end = 1e+300 is not what the FMU's variables can set it to",
        },
        Tamper {
            edits: &[
                ("/model/settings/scene/friction/law", "\"neural\""),
                ("/model/running/built_from/scene/friction/law", "\"neural\""),
                ("/model/settings/weights", "\"/nonexistent/w.json\""),
                (
                    "/model/running/built_from/weights",
                    "\"/nonexistent/w.json\"",
                ),
            ],
            reason: "/nonexistent/w.json",
        },
        Tamper {
            edits: &[("/model/initialized", "false")],
            reason: "initialized = false disagrees with the state's mode",
        },
        Tamper {
            edits: &[("/mode", "\"initialization-mode\"")],
            reason: "saved in InitializationMode mode at time",
        },
        Tamper {
            edits: &[("/model/running/start_time", "0.1")],
            reason: "running.start_time = 0.1 s differs from the state's start time 0 s",
        },
        Tamper {
            edits: &[("/time", "1e400")],
            reason: "malformed at time",
        },
        Tamper {
            edits: &[("/time", "null")],
            reason: "malformed at time",
        },
        Tamper {
            edits: &[("/stop_time", "-1")],
            reason: "stop time -1 s is not after its start time",
        },
    ]
}

fn rate_state_beam_cases() -> Vec<Tamper> {
    vec![
        Tamper {
            edits: &[(BEAM_LAW_STATE, "[-1e-3]")],
            reason: "state_theta = -1e-3 s; it must be finite and > 0",
        },
        Tamper {
            edits: &[(BEAM_LAW_STATE, "[0]")],
            reason: "state_theta = 0e0 s; it must be finite and > 0",
        },
        Tamper {
            edits: &[
                (
                    "/model/settings/scene/friction/rate_and_state/characteristic_slip",
                    "0",
                ),
                (
                    "/model/running/built_from/scene/friction/rate_and_state/characteristic_slip",
                    "0",
                ),
            ],
            reason: "friction.rate_and_state.characteristic_slip = 0",
        },
    ]
}

const LAW_STATE: &str = "/model/law_state";

fn friction_cases() -> Vec<Tamper> {
    vec![
        Tamper {
            edits: &[("/model/settings/normal_force", "-100")],
            reason: "normal_force: -100 must be >= 0",
        },
        Tamper {
            edits: &[("/model/settings/normal_force", "null")],
            reason: "settings.normal_force",
        },
        Tamper {
            edits: &[(LAW_STATE, "[]")],
            reason: "law_state = []: the law lugre has a state",
        },
        Tamper {
            edits: &[(LAW_STATE, "[1e-6, 2e-6]")],
            reason: "2 values for a state of 1",
        },
        Tamper {
            edits: &[("/model/settings/static_coefficient", "-1")],
            reason: "friction.static_coefficient = -1",
        },
        Tamper {
            edits: &[("/model/settings/lugre/bristle_stiffness", "0")],
            reason: "friction.lugre.bristle_stiffness = 0",
        },
        Tamper {
            edits: &[("/model/settings/law", "\"bogus\"")],
            reason: "settings.law: unknown variant `bogus`",
        },
        Tamper {
            edits: &[("/model/settings/law", "\"exponential\"")],
            reason: "the law exponential has no state",
        },
        Tamper {
            edits: &[("/model/settings/extra_features", "[0, 0, 0]")],
            reason: "settings.extra_features",
        },
        Tamper {
            edits: &[("/model/settings/sliding_velocity", "1e400")],
            reason: "at model",
        },
    ]
}

fn rate_state_friction_cases() -> Vec<Tamper> {
    vec![
        Tamper {
            edits: &[(LAW_STATE, "[-1e-3]")],
            reason: "state_theta = -1e-3 s; it must be finite and > 0",
        },
        Tamper {
            edits: &[(LAW_STATE, "[0]")],
            reason: "state_theta = 0e0 s",
        },
    ]
}

fn learned_friction_cases(corrupt: &'static str) -> Vec<Tamper> {
    vec![
        Tamper {
            edits: &[("/model/settings/weights", "\"/nonexistent/w.json\"")],
            reason: "/nonexistent/w.json",
        },
        Tamper {
            edits: Box::leak(Box::new([("/model/settings/weights", corrupt)])),
            reason: "not a valid",
        },
        Tamper {
            edits: &[("/model/settings/weights", "\"  \"")],
            reason: "weights:",
        },
    ]
}

#[test]
fn tampered_values_with_a_valid_checksum_are_refused_by_name_and_change_nothing() {
    let corrupt = std::env::temp_dir().join(format!(
        "stickslip-corrupt-weights-{}.json",
        std::process::id()
    ));
    std::fs::write(&corrupt, "{\"format\": \"stickslip-network\", \"lay").unwrap();
    let corrupt_json: &'static str =
        Box::leak(format!("{:?}", corrupt.display().to_string()).into_boxed_str());
    let mut table = vec![
        "| instance | tampered value | logged reason |".to_string(),
        "| --- | --- | --- |".to_string(),
    ];
    for version in [FmiVersion::V2, FmiVersion::V3] {
        let mut rows = Vec::new();
        let (mut b, log) = beam_at(version, FrictionLawKind::Lugre, 0.45);
        rows.extend(check_refusals(&mut b, &log, "beam, LuGre", &beam_cases()));
        let (mut b, log) = beam_at(version, FrictionLawKind::RateAndState, 0.45);
        rows.extend(check_refusals(
            &mut b,
            &log,
            "beam, rate-and-state",
            &rate_state_beam_cases(),
        ));
        let (mut f, log) = friction_at(version, NeuralFrictionLaw::LUGRE, None);
        rows.extend(check_refusals(
            &mut f,
            &log,
            "friction, LuGre",
            &friction_cases(),
        ));
        let (mut f, log) = friction_at(version, NeuralFrictionLaw::RATE_AND_STATE, None);
        rows.extend(check_refusals(
            &mut f,
            &log,
            "friction, rate-and-state",
            &rate_state_friction_cases(),
        ));
        let (mut f, log) = friction_at(
            version,
            NeuralFrictionLaw::NEURAL,
            Some("rate-and-state-learned.json"),
        );
        rows.extend(check_refusals(
            &mut f,
            &log,
            "friction, learned law",
            &learned_friction_cases(corrupt_json),
        ));
        if version == FmiVersion::V2 {
            table.extend(rows);
        } else {
            table.extend(rows.into_iter().filter(|r| r.starts_with("MISMATCH")));
        }
    }
    std::fs::remove_file(&corrupt).ok();
    println!("{}", table.join("\n"));
    let mismatches: Vec<&String> = table.iter().filter(|r| r.starts_with("MISMATCH")).collect();
    assert!(mismatches.is_empty(), "{mismatches:#?}");
}

/// Before initialisation a state holds what the setters accept, and a real parameter is
/// checked by initialisation, as when set: a state saved in Instantiated mode with
/// youngs_modulus = -1 restores, and fmi2ExitInitializationMode then refuses it with
/// the message it gives when the value was set. A negative force is refused at once,
/// as its setter does.
#[test]
fn a_state_before_initialisation_is_checked_as_the_setters_check() {
    let (mut b, log) =
        super::state_corruption::logged::<stickslip_fmi::beam::StickSlipBeam>(FmiVersion::V2);
    let saved = b.get_state().unwrap();
    let modulus = tampered_bytes(
        &saved,
        &[("/model/settings/scene/material/youngs_modulus", "-1")],
    );
    let state = b.deserialize_state(&modulus).unwrap();
    b.set_state(&state).unwrap();
    b.enter_initialization_mode().unwrap();
    assert!(b.exit_initialization_mode().is_err());
    let message = last_message(&log);
    assert!(
        message.contains("material.youngs_modulus = -1e0; it must be finite and > 0"),
        "{message}"
    );
    let force = tampered_bytes(&saved, &[(SETTINGS_FORCE, "-1")]);
    assert!(b.deserialize_state(&force).is_err());
    assert!(last_message(&log).contains("normal_force: -1 must be >= 0"));
}
