//! The scene options after the paper authors' transient algorithm, each against a
//! closed form: the damping that acts only in slip, the preloaded start, the
//! finite-difference tip velocity, and the `paper-authors` preset's breakaway.

use stickslip::contact::ContactState;
use stickslip::friction::FrictionLawKind;
use stickslip::integrator::Coefficients;
use stickslip::law_source::LawSource;
use stickslip::scene::{
    CheckedScene, DampingPhase, FidelityLevel, InitialState, Scene, TipVelocity,
};
use stickslip::scene_preset::ScenePreset;
use stickslip::simulation::Simulator;

fn simulator(scene: Scene) -> Simulator {
    let scene = scene.check().unwrap();
    let law = LawSource::resolve(&scene).unwrap().law().unwrap();
    Simulator::new(scene, law).unwrap()
}

fn tip_displacement(sim: &Simulator) -> f64 {
    sim.sample().tip_deflection
}

/// A beam scene that slips from the first step on and never re-sticks: the belt at
/// 10 m/s drags the tip with the constant Coulomb force mu F_n = 50 N (the tip's own
/// velocity stays below 0.2 m/s, so v_rel never changes sign), from the static shape
/// under half of that force. The tip then vibrates freely about the 50 N shape.
fn long_slip(phase: DampingPhase, stiffness_damping: f64) -> Scene {
    let mut s = preloaded_beam(0.5, phase, stiffness_damping, 2.0);
    s.friction.law = FrictionLawKind::Coulomb;
    s.friction.kinetic_coefficient = s.friction.static_coefficient;
    s.loading.belt_speed = 10.0;
    s
}

/// The paper's scene on beam elements, at rest under the preload `preload` (fraction of
/// mu_s F_n), with stiffness-proportional damping `b` (s) in the phases `phase`.
fn preloaded_beam(preload: f64, phase: DampingPhase, b: f64, end: f64) -> Scene {
    let mut s = Scene::default();
    s.fidelity.level = FidelityLevel::Beam;
    s.contact.preload = preload;
    s.contact.initial_state = InitialState::AtRest;
    s.contact.damping_phase = phase;
    s.damping.mass_proportional = 0.0;
    s.damping.stiffness_proportional = b;
    s.time.end = end;
    s
}

#[test]
fn in_a_long_slip_the_slip_only_damping_decays_mode_one_at_its_rayleigh_ratio() {
    let b = 1e-3;
    let scene = long_slip(DampingPhase::Slip, b);
    let checked = scene.clone().check().unwrap();
    let omega = stickslip::stability::cantilever_omega(&checked, 1).unwrap();
    let zeta = b * omega / 2.0;
    let mut sim = simulator(scene);
    // Peaks of the tip deflection, after 0.5 s: by then modes 2 and up (zeta >= 11 %)
    // have decayed by exp(-0.11 * 225 * 0.5) < 1e-5 and the tip vibrates in mode 1.
    let mut previous = (f64::NAN, f64::NAN);
    let mut peaks = Vec::new();
    while sim.state().time < 2.0 {
        sim.step().unwrap();
        assert_eq!(sim.state().contact, ContactState::Slip, "a long slip");
        let u = tip_displacement(&sim);
        if sim.state().time > 0.5 && previous.1 > previous.0 && previous.1 >= u {
            peaks.push(previous.1);
        }
        previous = (previous.1, u);
    }
    // About the mean position 50 N / k = 8 mm (the Coulomb force's static shape).
    let centre = 50.0 / checked.euler_bernoulli_tip_stiffness();
    let (first, last) = (peaks[0] - centre, peaks[peaks.len() - 1] - centre);
    let cycles = (peaks.len() - 1) as f64;
    // Log decrement delta = 2 pi zeta / sqrt(1 - zeta^2) per cycle (Chopra, Sec. 2.2).
    let decrement = stickslip::elementary::ln(first / last) / cycles;
    let expected = 2.0 * std::f64::consts::PI * zeta / (1.0 - zeta * zeta).sqrt();
    // 2 %: generalised-alpha adds O((omega dt)^3) damping at omega dt = 0.0036
    // (< 1e-6 of a cycle), sampled peaks miss the true ones by (omega dt)^2 / 2 = 6e-6
    // relative, and the 100-element omega_1 is beam theory's to 1e-8; what is left is
    // the residue of the higher modes.
    assert!(
        (decrement / expected - 1.0).abs() < 0.02,
        "log decrement {decrement} against 2 pi zeta = {expected} (zeta = {zeta}, {} peaks)",
        peaks.len()
    );
}

/// The paper's scene from the authors' 1 % preload.
fn preloaded_paper(phase: DampingPhase, b: f64) -> Scene {
    preloaded_beam(0.01, phase, b, 0.8)
}

#[test]
fn the_slip_only_damping_is_off_in_stick_and_switches_at_the_transitions() {
    let mut slip_only = simulator(preloaded_paper(DampingPhase::Slip, 1e-3));
    let mut undamped = simulator(preloaded_paper(DampingPhase::Always, 0.0));
    let mut always = simulator(preloaded_paper(DampingPhase::Always, 1e-3));
    // Stick up to breakaway: the same steps as without damping, to the last bit (the
    // same undamped factorisation and the same arithmetic), and not those of the
    // damped run.
    while slip_only.state().transition_count == 0 {
        for sim in [&mut slip_only, &mut undamped, &mut always] {
            sim.step().unwrap();
        }
        if slip_only.state().transition_count == 0 {
            assert_eq!(
                slip_only.state().kinematics,
                undamped.state().kinematics,
                "t = {}",
                slip_only.state().time
            );
        }
    }
    let breakaway = slip_only.state().time;
    assert_ne!(
        tip_displacement(&always),
        tip_displacement(&slip_only),
        "the always-damped stick differs"
    );
    // The step after breakaway is the first damped one: it leaves the undamped run.
    undamped.step().unwrap();
    slip_only.step().unwrap();
    assert_ne!(
        slip_only.state().kinematics,
        undamped.state().kinematics,
        "damped from the step after breakaway ({breakaway} s)"
    );
    // The first slip ends in a re-stick, after which the steps take the undamped
    // factorisation again (`phase_damping` of the state at each step's start).
    while slip_only.state().contact == ContactState::Slip {
        slip_only.step().unwrap();
    }
    assert!(slip_only.state().time < 0.8, "the first slip ends");
}

#[test]
fn the_preload_starts_from_the_static_tip_deflection_and_breaks_away_on_time() {
    for level in [
        FidelityLevel::Modal,
        FidelityLevel::Beam,
        FidelityLevel::PlaneStress,
    ] {
        for preset in [true, false] {
            let mut scene = ScenePreset::PaperAuthors.scene();
            if !preset {
                // The default contact (the reaction as holding force, the quasi-static
                // velocity field) with only the preload and the slip-only damping.
                scene = Scene::default();
                scene.contact.preload = 0.01;
                scene.contact.damping_phase = DampingPhase::Slip;
            }
            scene.fidelity.level = level;
            scene.time.end = 0.42;
            let checked: CheckedScene = scene.clone().check().unwrap();
            let k = checked.euler_bernoulli_tip_stiffness();
            let limit = checked.friction.static_coefficient * checked.loading.normal_force;
            let load = 0.01 * limit;
            let mut sim = simulator(scene);
            let u0 = tip_displacement(&sim);
            // P L^3 / (3 EI): the beam elements are exact for a tip load, the modal
            // model holds the static correction, and the plane-stress mesh is +0.002 %
            // off beam theory (docs/measurements.md); 1e-4 covers the three.
            assert!(
                (u0 * k / load - 1.0).abs() < 1e-4,
                "{level:?}: u_0 = {u0} against P / k = {}",
                load / k
            );
            while sim.state().transition_count == 0 && sim.state().time < 0.42 {
                sim.step().unwrap();
            }
            // The closed form, with u_0 = P / k: (mu_s F_n - P) / (k v_b).
            let t_b = (limit - load) / (k * checked.loading.belt_speed);
            // t_b = 0.396 s; the switch is detected at the end of the step in which
            // the holding force passes F_crit, so up to one step late; two steps
            // allow for the plane-stress stiffness' 2e-5 (0.4 s x 2e-5 = 8e-6 s) and
            // the reaction's dynamic part in the quasi-static start (undamped in stick,
            // it carries no c v_b term).
            let dt = checked.time.step;
            assert!(
                (sim.state().time - t_b).abs() <= 2.0 * dt,
                "{level:?} preset {preset}: breakaway {} s against {t_b} s",
                sim.state().time
            );
            assert!((t_b - 0.396).abs() < 1e-9);
        }
    }
}

#[test]
fn the_finite_difference_velocity_is_the_integrators_to_first_order_in_dt() {
    let scene = ScenePreset::PaperAuthors.scene();
    let mut scene = scene;
    scene.fidelity.level = FidelityLevel::Beam;
    scene.time.end = 0.8;
    let checked = scene.clone().check().unwrap();
    let Coefficients::GeneralizedAlpha { gamma, beta, .. } = Coefficients::from_scene(&checked)
    else {
        panic!("generalised-alpha");
    };
    assert_eq!(checked.contact.tip_velocity, TipVelocity::FiniteDifference);
    let dt = checked.time.step;
    let vb = checked.loading.belt_speed;
    let mut sim = simulator(scene);
    let model_tip = |sim: &Simulator, v: &[f64]| sim.model().tip_value(v);
    let mut slip_steps = 0;
    while sim.state().time < 0.8 {
        let a_n = model_tip(&sim, &sim.state().kinematics.acceleration);
        sim.step().unwrap();
        let a_next = model_tip(&sim, &sim.state().kinematics.acceleration);
        let v_int = sim.sample().tip_velocity;
        let v_fd = vb - sim.state().relative_velocity;
        // Newmark: u_n+1 - u_n = dt v_n + dt^2 ((1/2 - beta) a_n + beta a_n+1) and
        // v_n+1 = v_n + dt ((1 - gamma) a_n + gamma a_n+1), so
        // (u_n+1 - u_n) / dt - v_n+1 = dt ((gamma - beta - 1/2) a_n + (beta - gamma) a_n+1):
        // O(dt), exactly.
        let expected = dt * ((gamma - beta - 0.5) * a_n + (beta - gamma) * a_next);
        let scale = v_int.abs().max(vb);
        assert!(
            (v_fd - v_int - expected).abs() < 1e-9 * scale,
            "t = {}: v_fd - v = {} against {expected}",
            sim.state().time,
            v_fd - v_int
        );
        if sim.state().contact == ContactState::Slip {
            slip_steps += 1;
        }
    }
    assert!(slip_steps > 1000, "the run slips ({slip_steps} steps)");
}

#[test]
fn the_new_options_are_checked_at_construction() {
    for preload in [-0.01, 1.0, f64::NAN] {
        let mut s = Scene::default();
        s.contact.preload = preload;
        let error = s.check().unwrap_err();
        assert_eq!(error.field(), Some("contact.preload"), "{preload}");
    }
    // Moreau-Jean's stick holds the tip velocity itself; a difference of displacements
    // cannot stand in for it.
    let mut s = Scene::default();
    s.contact.tip_velocity = TipVelocity::FiniteDifference;
    s.integrator.scheme = stickslip::scene::Scheme::MoreauJean;
    let error = s.check().unwrap_err();
    assert_eq!(error.field(), Some("contact.tip_velocity"));
    assert!(error.to_string().contains("Moreau-Jean"), "{error}");
}
