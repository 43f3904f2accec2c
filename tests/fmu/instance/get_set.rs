//! Setting and reading values: parameter and input checks, start values, fixed
//! parameters after initialisation, non-finite outputs, and the log's categories.

use super::*;

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

#[test]
fn non_finite_outputs_are_errors_not_values() {
    let (logger, log) = collecting_logger();
    let mut f = Instance::<NeuralFriction>::new("f", Some(&resources()), false, logger).unwrap();
    f.set_integer(
        &[vr::<NeuralFriction>("law")],
        &[NeuralFrictionLaw::EXPONENTIAL.code()],
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
