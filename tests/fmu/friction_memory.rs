//! NeuralFriction with a law that has state (the shipped learned law with memory,
//! `rate-and-state-learned.json`): the state is integrated over each communication step,
//! a velocity step gives the law's direct jump and then relaxes to the law's steady
//! force, and the state is part of the FMU state (bit for bit, state version 4, version
//! 3 still read), in FMI 2.0 and 3.0 (one instance code, both entry points stepped).

use std::sync::Arc;
use stickslip::friction::learned_state::{LearnedStateFriction, StateLawFile};
use stickslip::friction::FrictionLaw;
use stickslip_fmi::friction::NeuralFriction;
use stickslip_fmi::instance::{FmiVersion, Instance, SavedState, STATE_VERSION};
use stickslip_tests::vr;

use crate::friction_laws::{set_velocity, steps};

const WEIGHTS: &str = "rate-and-state-learned.json";

fn learned(version: FmiVersion) -> Instance<NeuralFriction> {
    let logger = Box::new(|_, _: &str, _: &str| {});
    let dir = stickslip_tests::weights_dir();
    let mut f =
        Instance::<NeuralFriction>::instantiate(version, "f", Some(&dir), false, logger).unwrap();
    f.set_string(&[vr::<NeuralFriction>("weights")], &[WEIGHTS])
        .unwrap();
    f.setup_experiment(0.0, None).unwrap();
    f.enter_initialization_mode().unwrap();
    f.exit_initialization_mode().unwrap();
    f
}

fn force(f: &mut Instance<NeuralFriction>) -> f64 {
    let mut out = [0.0];
    f.get_real(&[vr::<NeuralFriction>("friction_force")], &mut out)
        .unwrap();
    out[0]
}

fn law() -> LearnedStateFriction {
    let file = StateLawFile::load(&stickslip_tests::weights_dir().join(WEIGHTS)).unwrap();
    LearnedStateFriction::new(Arc::new(file.law()))
}

/// Slide at 1 mm/s over 100 D_c (steady to rounding: the state's memory is e^-100),
/// then set 10 mm/s: the force jumps at once by the direct effect, a ln(10) F_n for
/// the learned a (the law's own number, to 1e-9 N: the same formula at the same
/// state), and relaxes over the next steps to the law's steady force at 10 mm/s.
#[test]
fn a_velocity_step_through_the_fmu_gives_the_laws_direct_jump_then_its_steady_force() {
    let a = law().law().parameters.direct_effect;
    for version in [FmiVersion::V2, FmiVersion::V3] {
        let mut f = learned(version);
        set_velocity(&mut f, 1e-3);
        let t = steps(&mut f, version, 0.0, 0.05, 20);
        let before = force(&mut f);
        let steady_before = law().sliding_force(1e-3, 100.0);
        assert!(
            (before - steady_before).abs() < 1e-9,
            "{before} vs {steady_before}"
        );
        set_velocity(&mut f, 1e-2);
        let jump = force(&mut f) - before;
        // The asinh form is a ln(v) + ... to 1e-30 relative at these speeds.
        let expected = a * stickslip::elementary::ln(10f64) * 100.0;
        assert!(
            (jump - expected).abs() < 1e-9,
            "{version:?}: jump {jump} vs {expected}"
        );
        steps(&mut f, version, t, 0.005, 20);
        let after = force(&mut f);
        let steady_after = law().sliding_force(1e-2, 100.0);
        assert!(
            (after - steady_after).abs() < 1e-9,
            "{after} vs {steady_after}"
        );
        // Velocity weakening (b > a): the steady force falls below the one before.
        assert!(after < before, "{after} {before}");
    }
}

/// The law state is in the FMU state: a saved state, serialised and restored in a fresh
/// instance, gives the same forces bit for bit as the instance that went on; its version
/// is 6 and it carries the state and the step size (without which it is refused); a version-3 state (the settings alone) still restores,
/// with the law's initial state.
#[test]
fn the_law_state_round_trips_bit_for_bit_and_old_states_are_read() {
    for version in [FmiVersion::V2, FmiVersion::V3] {
        let mut f = learned(version);
        set_velocity(&mut f, 3e-3);
        let t = steps(&mut f, version, 0.0, 1e-3, 7);
        let saved = f.get_state().unwrap();
        assert_eq!(saved.version, STATE_VERSION);
        assert_eq!(saved.version, 8);
        assert_eq!(saved.model["step_size"], serde_json::json!(1e-3));
        let law_state = saved.model["law_state"].as_array().unwrap();
        assert_eq!(law_state.len(), 1);
        let bytes = f.serialize_state(&saved).unwrap();
        let mut other = learned(version);
        let restored = other.deserialize_state(&bytes).unwrap();
        other.set_state(&restored).unwrap();
        let run = |g: &mut Instance<NeuralFriction>| -> Vec<u64> {
            let mut out = Vec::new();
            let mut t = t;
            for v in [3e-2, -1e-2, 0.0, 5e-3] {
                set_velocity(g, v);
                out.push(force(g).to_bits());
                t = steps(g, version, t, 2e-3, 3);
                out.push(force(g).to_bits());
            }
            out
        };
        assert_eq!(run(&mut f), run(&mut other));

        let mut old: SavedState = saved.clone();
        old.version = 3;
        old.model = saved.model["settings"].clone();
        let mut fresh = learned(version);
        fresh
            .set_state(&SavedState::from_bytes(&old.to_bytes()).unwrap())
            .unwrap();
        set_velocity(&mut fresh, 1e-3);
        // The initial state psi = 0 is steady sliding at V_0 = 1 mm/s.
        assert!((force(&mut fresh) - law().sliding_force(1e-3, 100.0)).abs() < 1e-9);
        let mut bad = saved.clone();
        bad.model["law_state"] = serde_json::json!([1.0, 2.0]);
        let e = fresh.set_state(&bad);
        assert!(e.is_err());

        // Without the step size (the h the step-consistent pair looks ahead over) a
        // state after a step is refused: required from version 6; version 5 states
        // were written with and without it, and without it they cannot restore the run.
        for v in [6, 5] {
            let mut no_h = saved.clone();
            no_h.version = v;
            no_h.model.as_object_mut().unwrap().remove("step_size");
            assert!(fresh.set_state(&no_h).is_err(), "version {v}");
        }
        let mut with_h = saved.clone();
        with_h.version = 5;
        fresh.set_state(&with_h).unwrap();
    }
}

/// StickSlipBeam with `friction.law = neural` and the learned law's weights runs that
/// law (told by the file, as the scene does): its tip follows the library run of the
/// same scene bit for bit at 1e-3 s communication steps through the first slip
/// (0 to 0.6 s, breakaway at 0.442 s), and its saved state carries the law state.
#[test]
fn stick_slip_beam_runs_the_learned_law_as_the_library_does() {
    use stickslip::choice::Choice;
    use stickslip::friction::FrictionLawKind;
    use stickslip::law_source::LawSource;
    use stickslip::scene::{FidelityLevel, Scene};
    use stickslip::simulation::Simulator;
    use stickslip_fmi::beam::StickSlipBeam;
    let logger = Box::new(|_, _: &str, _: &str| {});
    let dir = stickslip_tests::weights_dir();
    let mut b = Instance::<StickSlipBeam>::new("b", Some(&dir), false, logger).unwrap();
    b.setup_experiment(0.0, Some(1.2)).unwrap();
    b.set_integer(
        &[
            vr::<StickSlipBeam>("fidelity.level"),
            vr::<StickSlipBeam>("friction.law"),
        ],
        &[FidelityLevel::Modal.code(), FrictionLawKind::Neural.code()],
    )
    .unwrap();
    b.set_string(&[vr::<StickSlipBeam>("friction.weights")], &[WEIGHTS])
        .unwrap();
    b.enter_initialization_mode().unwrap();
    b.exit_initialization_mode().unwrap();
    let mut scene = Scene::default();
    scene.fidelity.level = FidelityLevel::Modal;
    scene.friction.law = FrictionLawKind::Neural;
    scene.friction.weights = Some(dir.join(WEIGHTS).display().to_string());
    scene.time.end = 1.2;
    let scene = scene.check().unwrap();
    let source = LawSource::resolve(&scene).unwrap();
    assert!(matches!(source, LawSource::LearnedState(_)));
    let mut sim = Simulator::new(scene, source.law().unwrap()).unwrap();
    let mut out = [0.0];
    for k in 0..600 {
        b.do_step(k as f64 * 1e-3, 1e-3).unwrap();
        sim.advance_to((k + 1) as f64 * 1e-3).unwrap();
        b.get_real(&[vr::<StickSlipBeam>("tip_deflection")], &mut out)
            .unwrap();
        assert_eq!(
            out[0],
            sim.sample().tip_deflection,
            "communication point {k}"
        );
    }
    assert!(
        sim.sample().tip_deflection < 0.02 * 0.44,
        "the first slip happened"
    );
    let saved = b.get_state().unwrap();
    let law_state = &saved.model["running"]["state"]["law_state"];
    assert_eq!(law_state.as_array().map(Vec::len), Some(1), "{law_state}");
}
