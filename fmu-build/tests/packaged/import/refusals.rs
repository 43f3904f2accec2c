//! Refusals reach the importer: an illegal call sequence and bad parameters give
//! fmi2Error and the reason in the log; fmi2Reset recovers.

use super::*;

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
