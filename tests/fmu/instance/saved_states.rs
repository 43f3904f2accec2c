//! Saved FMU states: save, run, restore bit for bit, through bytes; malformed and
//! refused states; recovery from an error; the older state versions.

use super::*;

#[test]
fn state_save_run_restore_run_is_bit_for_bit_and_survives_bytes() {
    let (mut b, _) = initialized_beam(FidelityLevel::Beam);
    run(&mut b, 0.0, 0.5, 1e-3);
    let saved = b.get_state().unwrap();
    let first = run(&mut b, 0.5, 0.8, 1e-3);
    b.set_state(&saved).unwrap();
    assert_eq!(b.time(), 0.5);
    let again = run(&mut b, 0.5, 0.8, 1e-3);
    assert_eq!(first, again);

    // Through bytes into a fresh instance that was only instantiated.
    let bytes = b.serialize_state(&saved).unwrap();
    let (mut fresh, _) = beam(false);
    let restored = fresh.deserialize_state(&bytes).unwrap();
    assert_eq!(restored, saved);
    fresh.set_state(&restored).unwrap();
    assert_eq!(fresh.mode(), Mode::StepComplete);
    assert_eq!(run(&mut fresh, 0.5, 0.8, 1e-3), first);
}

#[test]
fn malformed_state_bytes_are_refused() {
    let (mut b, log) = initialized_beam(FidelityLevel::Modal);
    run(&mut b, 0.0, 0.01, 1e-3);
    let saved = b.get_state().unwrap();
    let bytes = b.serialize_state(&saved).unwrap();
    let text = String::from_utf8(bytes.clone()).unwrap();
    let cases: Vec<(Vec<u8>, &str)> = vec![
        (bytes[..bytes.len() / 2].to_vec(), "malformed"),
        (b"\xff\x00garbage".to_vec(), "malformed"),
        (
            // Rewritten with a valid checksum, so that the version is what is refused.
            SavedState {
                version: 99,
                ..saved.clone()
            }
            .to_bytes(),
            "version 99",
        ),
        (
            SavedState {
                format: "other".into(),
                ..saved.clone()
            }
            .to_bytes(),
            "format",
        ),
        (
            text.replace(&format!("\"version\":{STATE_VERSION}"), "\"version\":99")
                .into_bytes(),
            "checksum mismatch",
        ),
    ];
    for (bad, needle) in cases {
        b.reset();
        assert!(b.deserialize_state(&bad).is_err());
        assert!(logged(&log, needle), "{needle}");
    }
    // Well-formed bytes whose model part does not fit: a wrong number of dofs.
    b.reset();
    let mut wrong: SavedState = SavedState::from_bytes(&bytes).unwrap();
    let kinematics = &mut wrong.model["running"]["state"]["kinematics"]["displacement"];
    kinematics.as_array_mut().unwrap().pop();
    assert!(b.set_state(&wrong).is_err());
    assert!(logged(&log, "degrees of freedom"));
    // A state of the other FMU.
    let (mut friction, _) = {
        let (logger, log) = collecting_logger();
        (
            Instance::<NeuralFriction>::new("f", Some(&resources()), false, logger).unwrap(),
            log,
        )
    };
    let other = friction.get_state().unwrap();
    b.reset();
    assert!(b.set_state(&other).is_err());
    assert!(logged(&log, "belongs to the FMU with GUID"));
}

/// The reasons a state's bytes are refused are typed (`StateError`); their messages are
/// the ones fmi2DeSerializeFMUstate logs.
#[test]
fn state_errors_are_typed_and_say_what_is_wrong() {
    use stickslip_fmi::instance::StateError;
    let e = SavedState::from_bytes(b"\xff").unwrap_err();
    assert!(matches!(e, StateError::Malformed { .. }), "{e:?}");
    assert!(e
        .to_string()
        .starts_with("serialized FMU state is malformed: "));
    assert!(std::error::Error::source(&e).is_some());
    let state = |format: &str, version: u32, mode: &str, time: f64| {
        format!(
            r#"{{"format":"{format}","version":{version},"guid":"g","mode":"{mode}","time":{time},"start_time":0,"stop_time":1,"model":null}}"#
        )
    };
    for (text, message) in [
        (
            state("other", 1, "step-complete", 0.5),
            "serialized FMU state has format \"other\", expected \"stickslip-fmu-state\"",
        ),
        (
            state("stickslip-fmu-state", 99, "step-complete", 0.5),
            "serialized FMU state has version 99, this FMU reads versions 1 to 8",
        ),
        (
            state("stickslip-fmu-state", 1, "step-complete", 2.0),
            "the state's time 2 s is past its stop time 1 s",
        ),
        (
            state("stickslip-fmu-state", 1, "instantiated", 0.5),
            "the state was saved in Instantiated mode at time 0.5 s, but before stepping the time must equal the start time 0 s",
        ),
    ] {
        let e = SavedState::from_bytes(text.as_bytes()).unwrap_err();
        assert_eq!(e.to_string(), message);
    }
    assert!(SavedState::from_bytes(
        state("stickslip-fmu-state", 1, "step-complete", 0.5).as_bytes()
    )
    .is_ok());
}

#[test]
fn set_state_is_the_way_back_from_an_error() {
    let (mut b, _) = initialized_beam(FidelityLevel::Modal);
    let saved = b.get_state().unwrap();
    assert!(b.do_step(0.0, -1.0).is_err());
    assert_eq!(b.mode(), Mode::Error);
    b.set_state(&saved).unwrap();
    assert_eq!(b.mode(), Mode::StepComplete);
    b.do_step(0.0, 1e-3).unwrap();
}

/// A state that does not fit leaves the running simulation as it was.
#[test]
fn a_refused_state_leaves_the_instance_running() {
    let (mut b, _) = initialized_beam(FidelityLevel::Beam);
    run(&mut b, 0.0, 0.2, 1e-3);
    let mut wrong = b.get_state().unwrap();
    wrong.model["running"]["state"]["kinematics"]["velocity"][3] =
        serde_json::Value::String("x".into());
    assert!(b.set_state(&wrong).is_err());
    b.reset();
    let (mut reference, _) = initialized_beam(FidelityLevel::Beam);
    let (mut other, _) = initialized_beam(FidelityLevel::Beam);
    run(&mut reference, 0.0, 0.2, 1e-3);
    run(&mut other, 0.0, 0.2, 1e-3);
    let good = other.get_state().unwrap();
    let mut bad = good.clone();
    bad.model["running"]["state"]["time"] = serde_json::json!(null);
    assert!(reference.set_state(&bad).is_err());
    // Back from the error with the good state: the run continues as the other's.
    reference.set_state(&good).unwrap();
    assert_eq!(
        run(&mut reference, 0.2, 0.3, 1e-3),
        run(&mut other, 0.2, 0.3, 1e-3)
    );
}

/// The standard's way back from an error, with the state kept as bytes: deserialize,
/// then set, in the Error mode.
#[test]
fn recovery_from_an_error_through_serialized_bytes() {
    let (mut b, log) = initialized_beam(FidelityLevel::Modal);
    run(&mut b, 0.0, 0.3, 1e-3);
    let saved = b.get_state().unwrap();
    let bytes = b.serialize_state(&saved).unwrap();
    let expected = run(&mut b, 0.3, 0.5, 1e-3);
    assert!(b.do_step(5.0, 1e-3).is_err());
    assert_eq!(b.mode(), Mode::Error);
    let restored = b.deserialize_state(&bytes).unwrap();
    b.set_state(&restored).unwrap();
    assert_eq!(run(&mut b, 0.3, 0.5, 1e-3), expected);
    assert!(logged(&log, "does not match the FMU's time"));
}

#[test]
fn neural_friction_restores_a_state_saved_before_its_parameters_were_checked() {
    let (logger, _) = collecting_logger();
    let mut f = Instance::<NeuralFriction>::new("f", Some(&resources()), false, logger).unwrap();
    f.set_string(&[vr::<NeuralFriction>("weights")], &["missing.json"])
        .unwrap();
    let saved = f.get_state().unwrap();
    f.set_state(&saved).unwrap();
    assert_eq!(f.mode(), Mode::Instantiated);
}

/// A version-1 state, which kept the friction model, the auto flag and the tolerance
/// beside the scene, restores into the scene's fields and is saved again as the
/// current version; a current-version state with the old fields is refused.
#[test]
fn a_version_1_beam_state_restores_into_the_scene_fields() {
    let (mut b, log) = beam(true);
    b.setup_experiment(0.0, Some(0.6)).unwrap();
    b.enter_initialization_mode().unwrap();
    let current = b.get_state().unwrap();
    assert_eq!(current.version, STATE_VERSION);
    let mut v1 = current.clone();
    v1.version = 1;
    assert!(v1.model["running"].is_null());
    let settings = v1.model["settings"].as_object_mut().unwrap();
    // A version-1 state has no external.coupling (it came later).
    settings.remove("coupling").unwrap();
    settings["scene"]["fidelity"]
        .as_object_mut()
        .unwrap()
        .remove("tolerance");
    settings.insert("friction_model".into(), "external".into());
    settings.insert("fidelity_auto".into(), true.into());
    settings.insert("fidelity_tolerance".into(), 2e-4.into());
    let restored = b.deserialize_state(&v1.to_bytes()).unwrap();
    b.set_state(&restored).unwrap();
    let mut codes = [0; 2];
    b.get_integer(
        &[
            vr::<StickSlipBeam>("friction.law"),
            vr::<StickSlipBeam>("fidelity.level"),
        ],
        &mut codes,
    )
    .unwrap_or_else(|e| panic!("{e:?}: {:?}", log.lock().unwrap()));
    assert_eq!(codes, [4, 4], "external, auto");
    let mut tolerance = [0.0];
    b.get_real(&[vr::<StickSlipBeam>("fidelity.tolerance")], &mut tolerance)
        .unwrap();
    assert_eq!(tolerance, [2e-4]);
    let again = b.get_state().unwrap();
    assert_eq!(again.version, STATE_VERSION);
    let scene = &again.model["settings"]["scene"];
    assert_eq!(scene["friction"]["law"], "external");
    assert_eq!(scene["fidelity"]["level"], "auto");
    assert_eq!(scene["fidelity"]["tolerance"], 2e-4);
    // It initialises as auto with the external model: the choice is logged, and the
    // tip follows the belt while it sticks (the inputs' static limit holds it).
    b.exit_initialization_mode().unwrap();
    assert!(logged(&log, "fidelity = auto (tolerance 2e-4 m"));
    run(&mut b, 0.0, 0.1, 1e-2);
    assert!((tip(&mut b) - 0.02 * 0.1).abs() < 1e-6, "{}", tip(&mut b));

    let mut mixed = v1;
    mixed.version = STATE_VERSION;
    assert!(b.set_state(&mixed).is_err());
    assert!(logged(&log, "unknown field"), "{:?}", log.lock().unwrap());
}

/// A version-2 beam state listed every transition beside the simulation state; it
/// still restores (the list is checked against the count, then dropped) and steps on
/// exactly as the current state does. A list that disagrees with the count is refused,
/// and the current version has no list.
#[test]
fn a_version_2_beam_state_with_its_transition_list_restores() {
    let (mut b, log) = initialized_beam(FidelityLevel::Modal);
    run(&mut b, 0.0, 0.6, 1e-2);
    let mut count = [0];
    b.get_integer(&[vr::<StickSlipBeam>("transitions")], &mut count)
        .unwrap();
    assert!(count[0] > 0);
    let current = b.get_state().unwrap();
    assert_eq!(current.version, STATE_VERSION);
    let running = &current.model["running"];
    assert_eq!(running["state"]["transition_count"], count[0]);
    assert!(running.get("transitions").is_none());
    let expected = run(&mut b, 0.6, 0.8, 1e-2);

    let with_list = |listed: usize| {
        let mut v2 = current.clone();
        v2.version = 2;
        let list: Vec<serde_json::Value> = (0..listed)
            .map(|k| serde_json::json!({"time": 0.4 + 1e-3 * k as f64, "to": "Slip"}))
            .collect();
        // Version 2 had no mean sliding velocity (version 7).
        v2.model["running"]
            .as_object_mut()
            .unwrap()
            .remove("mean_relative_velocity");
        v2.model["running"]
            .as_object_mut()
            .unwrap()
            .insert("transitions".into(), list.into());
        v2
    };
    let v2 = b
        .deserialize_state(&with_list(count[0] as usize).to_bytes())
        .unwrap();
    b.set_state(&v2).unwrap();
    assert_eq!(run(&mut b, 0.6, 0.8, 1e-2), expected);
    assert_eq!(b.get_state().unwrap().version, STATE_VERSION);

    assert!(b.set_state(&with_list(count[0] as usize + 1)).is_err());
    assert!(logged(
        &log,
        &format!(
            "{} transitions listed, the count says {}",
            count[0] + 1,
            count[0]
        )
    ));
    let mut listed_now = with_list(count[0] as usize);
    listed_now.version = STATE_VERSION;
    assert!(b.set_state(&listed_now).is_err());
    assert!(logged(&log, "unknown field `transitions`"));
}
