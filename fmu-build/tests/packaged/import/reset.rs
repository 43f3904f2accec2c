//! c. fmi2Reset: a rerun reproduces the first run.

use super::*;

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
