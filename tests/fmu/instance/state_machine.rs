//! The state machine: which call is allowed in which mode, the way out of an error
//! (fmi2Reset, a saved state), and what reads in Initialization Mode see.

use super::*;

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
