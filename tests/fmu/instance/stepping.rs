//! fmi2DoStep: the checks of the communication point, step size and stop time, the
//! steps against the library bit for bit, irregular and off-grid steps, the breakaway.

use super::*;

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
