//! The FMI state machine, parameter and input checks, stepping and FMU state of both
//! models, driven through `Instance` (the plain-Rust side of the C interface).

use std::path::PathBuf;
use std::sync::{Arc, Mutex};
use stickslip::choice::Choice;
use stickslip::friction::LawChoice;
use stickslip::law_source::LawSource;
use stickslip::scene::{CheckedScene, FidelityLevel, FrictionLawKind, Scene};
use stickslip::simulation::Simulator;
use stickslip_fmi::beam::StickSlipBeam;
use stickslip_fmi::friction::NeuralFriction;
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

#[test]
fn wrong_call_order_is_an_error_and_only_reset_leads_out() {
    let (mut b, log) = beam(false);
    assert!(b.do_step(0.0, 1e-3).is_err());
    assert_eq!(b.mode(), Mode::Error);
    assert!(logged(&log, "fmi2DoStep: illegal call sequence"));
    // After an error: no stepping, setting or mode change; reads are allowed (the
    // standard's table), and report without computing.
    assert!(b
        .set_real(&[vr::<StickSlipBeam>("belt_speed")], &[0.01])
        .is_err());
    let mut out = [0.0];
    b.get_real(&[vr::<StickSlipBeam>("geometry.length")], &mut out)
        .unwrap();
    assert_eq!(out[0], 2.0);
    assert!(b.enter_initialization_mode().is_err());
    assert!(b.setup_experiment(0.0, None).is_err());
    b.reset();
    assert_eq!(b.mode(), Mode::Instantiated);
    b.setup_experiment(0.0, None).unwrap();
    b.enter_initialization_mode().unwrap();
    assert!(b.enter_initialization_mode().is_err(), "entered twice");
}

#[test]
fn every_call_outside_its_modes_is_refused() {
    // ExitInitializationMode before Enter; Terminate before initialisation; get before
    // initialisation; DoStep after Terminate.
    let (mut b, log) = beam(false);
    assert!(b.exit_initialization_mode().is_err());
    b.reset();
    assert!(b.terminate().is_err());
    b.reset();
    let mut out = [0.0];
    assert!(b
        .get_real(&[vr::<StickSlipBeam>("tip_deflection")], &mut out)
        .is_err());
    let (mut b, _) = initialized_beam(FidelityLevel::Modal);
    b.do_step(0.0, 1e-3).unwrap();
    b.terminate().unwrap();
    assert!(b.do_step(1e-3, 1e-3).is_err());
    assert_eq!(
        log.lock()
            .unwrap()
            .iter()
            .filter(|(_, _, m)| m.contains("illegal call sequence"))
            .count(),
        3
    );
}

#[test]
fn invalid_parameters_fail_initialisation_with_the_scene_message() {
    let (mut b, log) = beam(false);
    b.set_real(
        &[vr::<StickSlipBeam>("material.youngs_modulus")],
        &[-2.1e11],
    )
    .unwrap();
    b.enter_initialization_mode().unwrap();
    assert!(b.exit_initialization_mode().is_err());
    let mut scene = Scene::default();
    scene.material.youngs_modulus = -2.1e11;
    let expected = scene.check().err().unwrap().to_string();
    assert!(
        logged(&log, &format!("fmi2ExitInitializationMode: {expected}")),
        "{:?}",
        log.lock().unwrap()
    );
    assert_eq!(b.mode(), Mode::Error);
}

#[test]
fn non_finite_and_out_of_range_values_are_refused_when_set() {
    let (mut b, log) = beam(false);
    assert!(b
        .set_real(&[vr::<StickSlipBeam>("belt_speed")], &[f64::NAN])
        .is_err());
    assert!(logged(&log, "belt_speed: NaN is not a finite number"));
    b.reset();
    assert!(b
        .set_real(&[vr::<StickSlipBeam>("normal_force")], &[-1.0])
        .is_err());
    b.reset();
    assert!(b
        .set_integer(&[vr::<StickSlipBeam>("fidelity.level")], &[7])
        .is_err());
    assert!(logged(&log, "7 is not a FidelityLevel code"));
    b.reset();
    assert!(b
        .set_real(&[vr::<StickSlipBeam>("tip_deflection")], &[1.0])
        .is_err());
    assert!(logged(
        &log,
        "tip_deflection is an output and cannot be set"
    ));
    b.reset();
    assert!(b.set_real(&[9999], &[1.0]).is_err());
    assert!(logged(&log, "no variable has value reference 9999"));
    b.reset();
    // Accessing an Integer as a Real.
    assert!(b
        .set_real(&[vr::<StickSlipBeam>("fidelity.modes")], &[3.0])
        .is_err());
}

#[test]
fn fixed_parameters_cannot_change_after_initialisation_but_inputs_can() {
    let (mut b, log) = initialized_beam(FidelityLevel::Modal);
    b.set_real(&[vr::<StickSlipBeam>("belt_speed")], &[0.03])
        .unwrap();
    assert!(b
        .set_real(&[vr::<StickSlipBeam>("geometry.length")], &[1.0])
        .is_err());
    assert!(logged(&log, "geometry.length is a fixed parameter"));
}

#[test]
fn do_step_checks_the_communication_point_step_size_and_stop_time() {
    for (t, h, needle) in [
        (0.5, 1e-3, "does not match the FMU's time"),
        (0.0, 0.0, "must be positive"),
        (0.0, -1e-3, "must be positive"),
        (0.0, f64::NAN, "must be positive"),
        (0.0, 1.3, "passes stopTime"),
    ] {
        let (mut b, log) = initialized_beam(FidelityLevel::Modal);
        assert!(b.do_step(t, h).is_err(), "t = {t}, h = {h}");
        assert!(logged(&log, needle), "{needle}: {:?}", log.lock().unwrap());
    }
    // Within the tolerance of the communication point (a master that accumulates t).
    let (mut b, _) = initialized_beam(FidelityLevel::Modal);
    b.do_step(0.0, 0.1).unwrap();
    b.do_step(0.1 + 1e-15, 0.1).unwrap();
    assert_eq!(b.time(), 0.1 + 1e-15 + 0.1);
}

/// The FMU at a communication step of 1e-3 s gives exactly the library's result.
#[test]
fn fmu_steps_equal_the_library_bit_for_bit() {
    let (mut b, _) = initialized_beam(FidelityLevel::Beam);
    let fmu = run(&mut b, 0.0, 0.6, 1e-3);
    let mut scene = CheckedScene::paper().into_scene();
    scene.fidelity.level = FidelityLevel::Beam;
    scene.time.end = 1.2;
    let scene = scene.check().unwrap();
    let law = LawSource::resolve(&scene).unwrap().law().unwrap();
    let mut sim = Simulator::new(scene, law).unwrap();
    for (k, &u) in fmu.iter().enumerate() {
        for _ in 0..10 {
            sim.step().unwrap();
        }
        assert_eq!(u, sim.sample().tip_deflection, "communication point {k}");
    }
    // Stick phase: the tip follows the belt until 0.4 s.
    assert!((fmu[199] - 0.02 * 0.2).abs() < 1e-9);
}

/// Communication steps off the internal grid land exactly on the communication point
/// and change the result only by the integrator's error over the odd steps.
#[test]
fn irregular_communication_steps_land_exactly() {
    let (mut regular, _) = initialized_beam(FidelityLevel::Beam);
    let reference = run(&mut regular, 0.0, 0.6, 1e-3);
    let (mut b, _) = initialized_beam(FidelityLevel::Beam);
    let mut t = 0.0;
    let pattern: [f64; 3] = [2.5e-4, 7e-4, 5e-5];
    let mut k = 0;
    while t < 0.6 - 1e-12 {
        let h = pattern[k % 3].min(0.6 - t);
        b.do_step(t, h).unwrap();
        t += h;
        k += 1;
    }
    assert_eq!(b.time(), t);
    let mut out = [0.0; 2];
    b.get_real(
        &[
            vr::<StickSlipBeam>("tip_deflection"),
            vr::<StickSlipBeam>("relative_velocity"),
        ],
        &mut out,
    )
    .unwrap();
    let end = *reference.last().unwrap();
    eprintln!("irregular steps: {} m, regular: {end} m", out[0]);
    // At 0.6 s (mid-slip) the two agree to 1 um (measured: 1.6e-8 m): the steps of
    // 2.5e-4, 7e-4 and 5e-5 s cut into 1e-4 s steps plus one short landing step carry
    // only the integrator's O(dt^2) error, far below the 8 mm scale.
    assert!((out[0] - end).abs() < 1e-6, "{} vs {end} m", out[0]);
    assert!(out[1].is_finite());
}

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
            "serialized FMU state has version 99, this FMU reads versions 1 to 5",
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

/// A network that cannot be had says which file, once, and keeps the loader's error.
#[test]
fn network_errors_name_the_weights_file() {
    use stickslip_fmi::networks::{NetworkError, Networks};
    let mut networks = Networks::default();
    let e = networks.get("w.json").unwrap_err();
    assert_eq!(
        e.to_string(),
        "weights \"w.json\": no resources folder is known"
    );
    let e = networks
        .open(std::path::Path::new("/nonexistent"))
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "weights file /nonexistent/paper-plain.json: no such file"
    );
    let dir = std::env::temp_dir().join(format!("stickslip-fmu-networks-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let not_weights = dir.join("not-weights.json");
    std::fs::write(&not_weights, "x").unwrap();
    let e = networks.get(not_weights.to_str().unwrap()).unwrap_err();
    let path = not_weights.display().to_string();
    let message = e.to_string();
    assert!(
        message.starts_with(&format!(
            "weights file {path}: not a valid model description"
        )),
        "{message}"
    );
    assert_eq!(message.matches(&path).count(), 1, "{message}");
    assert!(
        matches!(
            e,
            NetworkError::Unreadable(stickslip::neural::NeuralError::Json { .. })
        ),
        "{e:?}"
    );
    std::fs::remove_dir_all(&dir).ok();
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

#[test]
fn reset_then_rerun_reproduces_the_first_run() {
    let (mut b, _) = initialized_beam(FidelityLevel::Modal);
    let first = run(&mut b, 0.0, 0.7, 1e-3);
    b.reset();
    b.setup_experiment(0.0, Some(1.2)).unwrap();
    b.set_integer(
        &[vr::<StickSlipBeam>("fidelity.level")],
        &[FidelityLevel::Modal.code()],
    )
    .unwrap();
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    assert_eq!(run(&mut b, 0.0, 0.7, 1e-3), first);
}

#[test]
fn two_instances_in_two_threads_are_independent() {
    let alone = {
        let (mut b, _) = initialized_beam(FidelityLevel::Modal);
        run(&mut b, 0.0, 0.6, 1e-3)
    };
    let handles: Vec<_> = (0..2)
        .map(|k| {
            std::thread::spawn(move || {
                let (mut b, _) = initialized_beam(FidelityLevel::Modal);
                if k == 1 {
                    // A different belt speed in the other instance must not leak.
                    b.set_real(&[vr::<StickSlipBeam>("belt_speed")], &[0.03])
                        .unwrap();
                }
                run(&mut b, 0.0, 0.6, 1e-3)
            })
        })
        .collect();
    let results: Vec<Vec<f64>> = handles.into_iter().map(|h| h.join().unwrap()).collect();
    assert_eq!(results[0], alone);
    assert_ne!(results[1], alone);
}

#[test]
fn missing_or_corrupted_weights_fail_instantiation_with_a_reason() {
    let dir = std::env::temp_dir().join(format!("stickslip-res-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (logger, log) = collecting_logger();
    assert!(Instance::<StickSlipBeam>::new("b", Some(&dir), false, logger).is_err());
    assert!(logged(&log, "paper-plain.json: no such file"));
    std::fs::write(dir.join("paper-plain.json"), "{\"format\": 3").unwrap();
    let (logger, log) = collecting_logger();
    assert!(Instance::<NeuralFriction>::new("f", Some(&dir), false, logger).is_err());
    assert!(
        logged(&log, "paper-plain.json"),
        "{:?}",
        log.lock().unwrap()
    );
    let (logger, log) = collecting_logger();
    assert!(Instance::<StickSlipBeam>::new("b", None, false, logger).is_err());
    assert!(logged(&log, "no resource location"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn logging_honours_categories() {
    // Off: only errors are logged (logStatusError is on by default).
    let (mut b, log) = initialized_beam(FidelityLevel::Modal);
    run(&mut b, 0.0, 0.5, 1e-3);
    assert!(log.lock().unwrap().is_empty());
    // logEvents on: the breakaway is reported.
    assert_eq!(b.set_debug_logging(true, &["logEvents"]), Status::Ok);
    run(&mut b, 0.5, 0.6, 1e-3);
    assert!(logged(&log, ": stick") || logged(&log, ": slip"));
    assert!(log
        .lock()
        .unwrap()
        .iter()
        .all(|(_, category, _)| category == "logEvents"));
    // An undeclared category is a warning, not an error.
    assert_eq!(b.set_debug_logging(true, &["logNonsense"]), Status::Warning);
    // Everything off: even errors are silent.
    b.set_debug_logging(false, &[]);
    let before = log.lock().unwrap().len();
    assert!(b.do_step(7.0, 1e-3).is_err());
    assert_eq!(log.lock().unwrap().len(), before);
}

#[test]
fn breakaway_through_the_fmu_is_at_0_400_s() {
    let (mut b, _) = initialized_beam(FidelityLevel::Modal);
    let stick = vr::<StickSlipBeam>("stick");
    let mut t = 0.0;
    let h = 1e-3;
    loop {
        b.do_step(t, h).unwrap();
        t += h;
        let mut s = [true];
        b.get_boolean(&[stick], &mut s).unwrap();
        if !s[0] {
            break;
        }
        assert!(t < 0.5, "no breakaway by 0.5 s");
    }
    // The first step whose end finds the tip slipping: (0.399, 0.400].
    assert!((t - 0.4).abs() < 0.5 * h, "breakaway at {t} s");
}

#[test]
fn external_friction_equal_to_the_law_reproduces_coulomb() {
    // friction.law = external with inputs mu_k F_n and mu_s F_n is Coulomb friction
    // with the static limit mu_s F_n: same as friction.law = coulomb.
    let runs: Vec<Vec<f64>> = [FrictionLawKind::Coulomb, FrictionLawKind::External]
        .iter()
        .map(|&model| {
            let (mut b, _) = beam(false);
            b.setup_experiment(0.0, Some(1.2)).unwrap();
            b.set_integer(
                &[
                    vr::<StickSlipBeam>("fidelity.level"),
                    vr::<StickSlipBeam>("friction.law"),
                ],
                &[FidelityLevel::Modal.code(), model.code()],
            )
            .unwrap();
            b.set_real(
                &[
                    vr::<StickSlipBeam>("external.kinetic_force"),
                    vr::<StickSlipBeam>("external.static_limit"),
                ],
                &[20.0, 50.0],
            )
            .unwrap();
            b.enter_initialization_mode().unwrap();
            b.exit_initialization_mode().unwrap();
            run(&mut b, 0.0, 1.0, 1e-3)
        })
        .collect();
    assert_eq!(runs[0], runs[1]);
}

#[test]
fn neural_friction_outputs_follow_the_inputs() {
    let (logger, _) = collecting_logger();
    let mut f = Instance::<NeuralFriction>::new("f", Some(&resources()), false, logger).unwrap();
    f.set_integer(
        &[vr::<NeuralFriction>("law")],
        &[LawChoice::Exponential.code()],
    )
    .unwrap();
    f.setup_experiment(0.0, None).unwrap();
    f.enter_initialization_mode().unwrap();
    f.exit_initialization_mode().unwrap();
    let outputs = [
        vr::<NeuralFriction>("friction_force"),
        vr::<NeuralFriction>("friction_force_magnitude"),
        vr::<NeuralFriction>("friction_coefficient"),
        vr::<NeuralFriction>("static_limit"),
    ];
    for v in [-0.2, 0.05, 0.3] {
        f.set_real(&[vr::<NeuralFriction>("sliding_velocity")], &[v])
            .unwrap();
        let mut out = [0.0; 4];
        f.get_real(&outputs, &mut out).unwrap();
        let mu = 0.2 + 0.3 * stickslip::elementary::exp(-5.0 * v.abs());
        assert!((out[0] - v.signum() * mu * 100.0).abs() < 1e-12);
        assert_eq!(out[1], out[0].abs());
        assert!((out[2] - mu).abs() < 1e-14);
        assert_eq!(out[3], 50.0);
    }
}

#[test]
fn every_parameter_start_value_is_the_scene_default() {
    // One source of truth: the XML start values are read from the model defaults,
    // which come from Scene::default(). Spot-check the chain end to end.
    let xml = FmuKind::StickSlipBeam.model_description();
    let scene = Scene::default();
    for (name, value) in [
        ("geometry.length", scene.geometry.length),
        ("material.youngs_modulus", scene.material.youngs_modulus),
        ("time.step", scene.time.step),
        ("belt_speed", scene.loading.belt_speed),
    ] {
        let at = xml.find(&format!("name=\"{name}\"")).unwrap();
        let start = &xml[at..];
        let start = &start[start.find("start=\"").unwrap() + 7..];
        let text = &start[..start.find('"').unwrap()];
        assert_eq!(text.parse::<f64>().unwrap(), value, "{name}");
    }
    for v in StickSlipBeam::variables() {
        let with_start = xml.contains(&format!("name=\"{}\"", v.name));
        assert!(with_start);
        if v.causality == Causality::Output {
            assert!(!v.access.is_settable());
        }
    }
}

/// Reading outputs during initialisation must not freeze the inputs or parameters
/// that shape the start: a belt speed set afterwards still gives its own quasi-static
/// start (tip at belt speed) and its own breakaway, mu_s F_n / k_tip / v_b later.
#[test]
fn outputs_read_in_initialization_mode_do_not_freeze_the_start() {
    let start = |read_first: bool| {
        let (mut b, _) = beam(false);
        b.setup_experiment(0.0, Some(1.2)).unwrap();
        b.enter_initialization_mode().unwrap();
        b.set_integer(
            &[vr::<StickSlipBeam>("fidelity.level")],
            &[FidelityLevel::Beam.code()],
        )
        .unwrap();
        if read_first {
            tip(&mut b);
        }
        b.set_real(&[vr::<StickSlipBeam>("belt_speed")], &[0.05])
            .unwrap();
        let mut v = [0.0];
        b.get_real(&[vr::<StickSlipBeam>("tip_velocity")], &mut v)
            .unwrap();
        assert!((v[0] - 0.05).abs() < 1e-15, "start velocity {} m/s", v[0]);
        b.exit_initialization_mode().unwrap();
        run(&mut b, 0.0, 0.3, 1e-3)
    };
    assert_eq!(start(true), start(false));
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

/// A communication step just off the grid (10 steps + 1e-8 s) must not leave a 1e-8 s
/// step: the last full step and the rest become two equal steps. The stick phase then
/// still follows the belt exactly and the holding force stays that of quasi-static
/// bending (3 EI u / L^3 = 25 N at u = 4 mm).
#[test]
fn slightly_off_grid_steps_do_not_leave_tiny_steps() {
    for level in [FidelityLevel::Modal, FidelityLevel::Beam] {
        let (mut b, _) = initialized_beam(level);
        let h = 1.00001e-3;
        let mut t = 0.0;
        for _ in 0..200 {
            b.do_step(t, h).unwrap();
            t += h;
        }
        let mut out = [0.0; 3];
        b.get_real(
            &[
                vr::<StickSlipBeam>("tip_deflection"),
                vr::<StickSlipBeam>("tip_velocity"),
                vr::<StickSlipBeam>("holding_force"),
            ],
            &mut out,
        )
        .unwrap();
        assert!(
            (out[0] - 0.02 * t).abs() < 1e-9,
            "tip {} at t = {t}",
            out[0]
        );
        assert!((out[1] - 0.02).abs() < 1e-6, "tip velocity {}", out[1]);
        assert!(
            (out[2] - 25.0 * t / 0.2).abs() < 0.5,
            "holding force {}",
            out[2]
        );
    }
}

#[test]
fn a_step_of_more_than_1e9_internal_steps_is_refused_at_once() {
    let (mut b, _) = beam(false);
    b.setup_experiment(0.0, None).unwrap();
    b.set_integer(
        &[vr::<StickSlipBeam>("fidelity.level")],
        &[FidelityLevel::Modal.code()],
    )
    .unwrap();
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    let began = std::time::Instant::now();
    assert!(b.do_step(0.0, 1e12).is_err());
    assert!(began.elapsed().as_secs_f64() < 1.0);
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

/// Reading a parameter during initialisation computes nothing, so parameters that are
/// inconsistent only until the importer has set them all do not fail the read; the
/// experiment's stop time counts when outputs are read.
#[test]
fn reads_in_initialization_mode_follow_the_experiment() {
    let (mut b, _) = beam(false);
    b.setup_experiment(0.0, Some(100.0)).unwrap();
    b.enter_initialization_mode().unwrap();
    b.set_real(&[vr::<StickSlipBeam>("geometry.length")], &[0.005])
        .unwrap();
    let mut out = [0.0];
    b.get_real(&[vr::<StickSlipBeam>("geometry.length")], &mut out)
        .unwrap();
    b.set_real(&[vr::<StickSlipBeam>("geometry.length")], &[2.0])
        .unwrap();
    b.set_integer(
        &[vr::<StickSlipBeam>("fidelity.level")],
        &[FidelityLevel::Modal.code()],
    )
    .unwrap();
    // time.step = 1.5 s exceeds the default end of 1.2 s but not the experiment's 100 s.
    b.set_real(&[vr::<StickSlipBeam>("time.step")], &[1.5])
        .unwrap();
    b.get_real(&[vr::<StickSlipBeam>("tip_deflection")], &mut out)
        .unwrap();
    b.exit_initialization_mode().unwrap();
}

#[test]
fn non_finite_outputs_are_errors_not_values() {
    let (logger, log) = collecting_logger();
    let mut f = Instance::<NeuralFriction>::new("f", Some(&resources()), false, logger).unwrap();
    f.set_integer(
        &[vr::<NeuralFriction>("law")],
        &[LawChoice::Exponential.code()],
    )
    .unwrap();
    f.set_real(&[vr::<NeuralFriction>("static_coefficient")], &[4.0])
        .unwrap();
    f.setup_experiment(0.0, None).unwrap();
    f.enter_initialization_mode().unwrap();
    f.exit_initialization_mode().unwrap();
    f.set_real(&[vr::<NeuralFriction>("normal_force")], &[1e308])
        .unwrap();
    let mut out = [0.0];
    assert!(f
        .get_real(&[vr::<NeuralFriction>("static_limit")], &mut out)
        .is_err());
    assert!(logged(&log, "not finite"));
    // The beam: a belt speed whose products overflow.
    let (mut b, log) = initialized_beam(FidelityLevel::Modal);
    b.set_real(&[vr::<StickSlipBeam>("belt_speed")], &[1e307])
        .unwrap();
    let steps: Vec<bool> = (0..100)
        .map(|k| b.do_step(k as f64 * 1e-3, 1e-3).is_ok())
        .take_while(|&ok| ok)
        .collect();
    assert!(steps.len() < 100, "the overflow was never reported");
    assert_eq!(b.mode(), Mode::Error);
    assert!(logged(&log, "non-finite"), "{:?}", log.lock().unwrap());
}

/// Parts a scene does not use cost nothing: a StickSlipBeam with an analytical law
/// never reads a network, not at instantiation, not when stepping; the neural law reads
/// exactly one, once, however often the simulation is rebuilt.
#[test]
fn the_beam_reads_a_network_only_for_the_neural_law() {
    let (mut b, _) = initialized_beam(FidelityLevel::Modal);
    run(&mut b, 0.0, 0.5, 1e-2);
    assert_eq!(b.model().networks_read(), 0);
    b.reset();
    assert_eq!(b.model().networks_read(), 0);
    let law = vr::<StickSlipBeam>("friction.law");
    let level = vr::<StickSlipBeam>("fidelity.level");
    for _ in 0..2 {
        b.reset();
        b.set_integer(&[level, law], &[FidelityLevel::Modal.code(), 3])
            .unwrap();
        b.setup_experiment(0.0, Some(1.2)).unwrap();
        b.enter_initialization_mode().unwrap();
        b.exit_initialization_mode().unwrap();
        run(&mut b, 0.0, 0.5, 1e-2);
        assert_eq!(b.model().networks_read(), 1);
    }
}

/// fidelity.level = auto in the FMU: the choice is made at initialisation, logged in
/// logEvents, and the instance steps; the parameter reads back as auto (item 4); a
/// non-positive tolerance is refused when set.
#[test]
fn fidelity_auto_chooses_at_initialisation_and_logs_the_choice() {
    let (mut b, log) = beam(true);
    let level = vr::<StickSlipBeam>("fidelity.level");
    let tolerance = vr::<StickSlipBeam>("fidelity.tolerance");
    assert!(b.set_real(&[tolerance], &[0.0]).is_err());
    b.reset();
    b.set_integer(&[level], &[FidelityLevel::Auto.code()])
        .unwrap();
    b.set_real(&[tolerance], &[1e-4]).unwrap();
    b.setup_experiment(0.0, Some(0.6)).unwrap();
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    assert!(
        logged(&log, "fidelity = auto (tolerance 1e-4 m"),
        "{:?}",
        log.lock().unwrap()
    );
    // The bound is over the experiment, to its stop time.
    assert!(
        logged(&log, "over the whole run, 0 to 0.600 s"),
        "{:?}",
        log.lock().unwrap()
    );
    let mut read = [0];
    b.get_integer(&[level], &mut read).unwrap();
    assert_eq!(read[0], FidelityLevel::Auto.code());
    run(&mut b, 0.0, 0.6, 1e-2);
    // Past breakaway at 0.4 s the tip has slipped back below its 8 mm peak.
    assert!(tip(&mut b) > 0.0 && tip(&mut b) < 8.1e-3);
}

/// Without a stop time the horizon is open: auto bounds the calibration window of the
/// first slips and logs the projected phase drift per second of simulated time; a
/// tolerance no configuration meets over the experiment fails initialisation with the
/// best achievable number in the log.
#[test]
fn fidelity_auto_reports_the_drift_without_a_stop_time_and_refuses_an_unmet_tolerance() {
    // An auto instance at `tolerance` (m) and stop time, through initialisation.
    let initialised = |tolerance: f64, stop: Option<f64>| {
        let (mut b, log) = beam(true);
        b.set_integer(
            &[vr::<StickSlipBeam>("fidelity.level")],
            &[FidelityLevel::Auto.code()],
        )
        .unwrap();
        b.set_real(&[vr::<StickSlipBeam>("fidelity.tolerance")], &[tolerance])
            .unwrap();
        b.setup_experiment(0.0, stop).unwrap();
        let status = b
            .enter_initialization_mode()
            .and_then(|_| b.exit_initialization_mode());
        let lines: Vec<String> = log.lock().unwrap().iter().map(|l| l.2.clone()).collect();
        (status.is_ok(), lines.join("\n"))
    };
    let (ok, lines) = initialised(1e-4, None);
    assert!(ok, "{lines}");
    assert!(lines.contains("the horizon is open"), "{lines}");
    assert!(lines.contains("ms per s of simulated time"), "{lines}");
    // 1e-11 m over 0.6 s: below the 6e-10 m by which the front's finest pair differs
    // there (tests/physics/auto_horizon.rs).
    let (ok, lines) = initialised(1e-11, Some(0.6));
    assert!(!ok, "{lines}");
    assert!(
        lines.contains("the best achievable estimated largest tip deviation is"),
        "{lines}"
    );
}

/// With the neural law, auto calibrates with the network of friction.weights, the one
/// the instance will run: the instance reads it once, before the calibration, so
/// weights that are not a network fail there, named in the message, where the shipped
/// plain network would have calibrated; no calibration run starts.
#[test]
fn fidelity_auto_calibrates_with_the_instances_own_weights() {
    let dir = std::env::temp_dir().join(format!("stickslip-auto-weights-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let broken = dir.join("broken.json");
    std::fs::write(&broken, "{ not a network").unwrap();
    let (mut b, log) = beam(true);
    let level = vr::<StickSlipBeam>("fidelity.level");
    let law = vr::<StickSlipBeam>("friction.law");
    b.set_integer(&[level, law], &[FidelityLevel::Auto.code(), 3])
        .unwrap();
    b.set_string(
        &[vr::<StickSlipBeam>("friction.weights")],
        &[broken.to_str().unwrap()],
    )
    .unwrap();
    b.setup_experiment(0.0, Some(0.05)).unwrap();
    b.enter_initialization_mode().unwrap();
    assert!(b.exit_initialization_mode().is_err());
    let entries = log.lock().unwrap().clone();
    assert!(
        entries
            .iter()
            .any(|(_, _, m)| m.contains("weights file") && m.contains(broken.to_str().unwrap())),
        "{entries:?}"
    );
    assert!(
        !entries
            .iter()
            .any(|(_, _, m)| m.contains("calibration run")),
        "{entries:?}"
    );
    std::fs::remove_dir_all(&dir).ok();
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

/// `friction.inference` of StickSlipBeam: each option runs the library's simulation of
/// the same scene bit for bit; f32 and the table follow the exact network to nanometres;
/// a network with more inputs than the table is refused at fmi2ExitInitializationMode
/// with the reason in the log.
#[test]
fn neural_inference_is_a_parameter_of_the_beam() {
    use stickslip::scene::Inference;
    let mut runs = Vec::new();
    for inference in Inference::ALL {
        let (mut b, _) = beam(false);
        b.setup_experiment(0.0, Some(0.6)).unwrap();
        b.set_integer(
            &[
                vr::<StickSlipBeam>("fidelity.level"),
                vr::<StickSlipBeam>("friction.law"),
                vr::<StickSlipBeam>("friction.inference"),
            ],
            &[
                FidelityLevel::Modal.code(),
                FrictionLawKind::Neural.code(),
                inference.code(),
            ],
        )
        .unwrap();
        b.enter_initialization_mode().unwrap();
        b.exit_initialization_mode().unwrap();
        let fmu = run(&mut b, 0.0, 0.6, 1e-3);
        let mut scene = Scene::default();
        scene.fidelity.level = FidelityLevel::Modal;
        scene.friction.law = FrictionLawKind::Neural;
        scene.friction.inference = *inference;
        scene.time.end = 0.6;
        let scene = scene.check().unwrap();
        let law = LawSource::resolve(&scene).unwrap().law().unwrap();
        let mut sim = Simulator::new(scene, law).unwrap();
        let library: Vec<f64> = (1..=600)
            .map(|k| {
                sim.advance_to(k as f64 * 1e-3).unwrap();
                sim.sample().tip_deflection
            })
            .collect();
        assert_eq!(fmu, library, "{inference:?}");
        runs.push(fmu);
    }
    for (inference, tip) in Inference::ALL.iter().zip(&runs).skip(1) {
        let deviation = runs[0]
            .iter()
            .zip(tip)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(deviation < 1e-7, "{inference:?}: {deviation} m");
    }

    let dir = std::env::temp_dir().join(format!("stickslip-inference-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let weights = dir.join("three.json");
    std::fs::write(&weights, stickslip_tests::three_input_weights()).unwrap();
    let (mut b, log) = beam(false);
    b.set_integer(
        &[
            vr::<StickSlipBeam>("friction.law"),
            vr::<StickSlipBeam>("friction.inference"),
        ],
        &[FrictionLawKind::Neural.code(), Inference::Table.code()],
    )
    .unwrap();
    b.set_string(
        &[vr::<StickSlipBeam>("friction.weights")],
        &[weights.to_str().unwrap()],
    )
    .unwrap();
    b.enter_initialization_mode().unwrap();
    assert!(b.exit_initialization_mode().is_err());
    assert!(
        logged(&log, "friction.inference = table") && logged(&log, "temperature"),
        "{:?}",
        log.lock().unwrap()
    );
    std::fs::remove_dir_all(&dir).ok();
}
