//! Leine's switch and the impulse clamp, as rules and as `Contact::resolve` decides
//! with them: the stick reaction, breakaway, the Euler-Bernoulli holding force, re-stick.

use super::{contact, coulomb, previous, BELT, LIMIT, MJ_TRIAL, TRIAL};
use stickslip::contact::ContactState::*;
use stickslip::contact::{impulse_clamp, next_state, Kinetic};
use stickslip::scene::{CheckedScene, HoldingForce, Scheme};

#[test]
fn stick_breaks_only_above_the_static_limit() {
    assert_eq!(next_state(Stick, 49.9, 50.0, 0.0, 0.0, 1e-3), Stick);
    assert_eq!(next_state(Stick, 50.0, 50.0, 0.0, 0.0, 1e-3), Stick);
    assert_eq!(next_state(Stick, -50.1, 50.0, 0.0, 0.0, 1e-3), Slip);
}

#[test]
fn slip_resticks_only_when_slow_or_reversed_and_admissible() {
    // Just after breakaway: slow, but the holding force is still above the limit.
    assert_eq!(next_state(Slip, 50.2, 50.0, 0.0, 1e-5, 1e-3), Slip);
    // Fast slip with an admissible force: keeps slipping.
    assert_eq!(next_state(Slip, 10.0, 50.0, 0.05, 0.04, 1e-3), Slip);
    // Slow and admissible: sticks.
    assert_eq!(next_state(Slip, 10.0, 50.0, 2e-3, 5e-4, 1e-3), Stick);
    // Sign change with eps = 0: sticks (the crossing is not missed).
    assert_eq!(next_state(Slip, 10.0, 50.0, 2e-3, -1e-2, 0.0), Stick);
    // Sign change but inadmissible: reverses direction and keeps slipping.
    assert_eq!(next_state(Slip, 80.0, 50.0, 2e-3, -1e-2, 0.0), Slip);
}

#[test]
fn impulse_clamp_holds_up_to_the_limit_in_either_direction() {
    assert_eq!(impulse_clamp(50.0, 50.0), Stick);
    assert_eq!(impulse_clamp(-50.0, 50.0), Stick);
    assert_eq!(impulse_clamp(50.1, 50.0), Slip);
    assert_eq!(impulse_clamp(-50.1, 50.0), Slip);
}

#[test]
fn generalized_alpha_sticks_with_the_reaction_that_puts_the_tip_on_the_belt() {
    let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
    let mut law = coulomb();
    let kinetic = Kinetic::Law {
        law: &mut law,
        normal_force: 100.0,
    };
    let r = c.resolve(&TRIAL, previous(Stick, 0.0, 0.0), BELT, LIMIT, kinetic);
    // (u_n + v_b dt - u_free) / (du/dF) = 1e-9 m / 1e-9 m/N = 1 N.
    assert_eq!(r.state, Stick);
    assert!((r.force - 1.0).abs() < 1e-6, "{}", r.force);
    assert_eq!(r.holding_force, r.force);
}

#[test]
fn generalized_alpha_breaks_away_with_the_law_force() {
    let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
    let mut law = coulomb();
    // A limit below the 1 N reaction: breakaway, and slip takes mu_k F_n along
    // v_rel = v_b - v_tip < 0 (the tip runs ahead of the belt).
    let kinetic = Kinetic::Law {
        law: &mut law,
        normal_force: 100.0,
    };
    let r = c.resolve(&TRIAL, previous(Stick, 0.0, 0.0), BELT, 0.5, kinetic);
    assert_eq!(r.state, Slip);
    assert_eq!(r.force, -20.0);
    assert!((r.holding_force - 1.0).abs() < 1e-6);
}

#[test]
fn euler_bernoulli_holding_force_is_the_tip_stiffness_times_the_stick_deflection() {
    let scene = CheckedScene::paper();
    let k = scene.euler_bernoulli_tip_stiffness();
    // Generalised-alpha: the stick deflection is u_n + v_b dt = 7.002 mm; 6250 N/m
    // times that is 43.76 N < 50 N, so the tip holds with the 1 N reaction.
    let c = contact(Scheme::GeneralizedAlpha, HoldingForce::EulerBernoulli);
    let mut law = coulomb();
    let kinetic = Kinetic::Law {
        law: &mut law,
        normal_force: 100.0,
    };
    let r = c.resolve(&TRIAL, previous(Stick, 0.0, 0.0), BELT, LIMIT, kinetic);
    assert_eq!(r.holding_force, k * (7e-3 + BELT * 1e-4));
    assert_eq!(r.state, Stick);
    assert!((r.force - 1.0).abs() < 1e-6);
    // ... and breaks away once k delta exceeds the limit, although the reaction is
    // small: the switch compares the Euler-Bernoulli force.
    let r = c.resolve(
        &TRIAL,
        previous(Stick, 0.0, 0.0),
        BELT,
        40.0,
        Kinetic::External { force: 20.0 },
    );
    assert_eq!(r.state, Slip);
}

#[test]
fn slow_slip_resticks_only_when_the_holding_force_is_admissible() {
    let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
    // External kinetic force 0.5 N along v_rel: v_rel,n+1 = 0.02 - (0.03 - 0.5 * 2e-5)
    // < 0 after v_rel,n > 0, a sign change, though |v_rel| stays above eps.
    let kinetic = || Kinetic::External { force: 0.5 };
    let r = c.resolve(&TRIAL, previous(Slip, 1e-4, 0.5), BELT, LIMIT, kinetic());
    assert_eq!(r.state, Stick);
    assert!((r.force - 1.0).abs() < 1e-6);
    // The same crossing with the 1 N reaction above a 0.9 N limit: keeps slipping.
    let r = c.resolve(&TRIAL, previous(Slip, 1e-4, 0.5), BELT, 0.9, kinetic());
    assert_eq!(r.state, Slip);
    assert_eq!(r.force, -0.5);
}

#[test]
fn moreau_jean_sticks_at_belt_velocity_whatever_the_state_before() {
    let c = contact(Scheme::MoreauJean, HoldingForce::Reaction);
    // (v_b - v_free) / (dv/dF) = -2e-5 / 2e-5 = -1 N, inside the clamp: stick, from
    // slip too, with no look at eps or at v_rel before.
    for state in [Stick, Slip] {
        let r = c.resolve(
            &MJ_TRIAL,
            previous(state, 0.5, 3.0),
            BELT,
            LIMIT,
            Kinetic::External { force: 20.0 },
        );
        assert_eq!(r.state, Stick);
        assert!((r.force + 1.0).abs() < 1e-6);
        assert_eq!(r.holding_force, r.force);
        let r = c.resolve(
            &MJ_TRIAL,
            previous(state, 0.5, 3.0),
            BELT,
            0.9,
            Kinetic::External { force: 0.5 },
        );
        assert_eq!(r.state, Slip);
        assert_eq!(r.force, -0.5);
    }
}

#[test]
fn moreau_jean_clamps_the_reaction_and_reports_the_euler_bernoulli_force() {
    let c = contact(Scheme::MoreauJean, HoldingForce::EulerBernoulli);
    let k = CheckedScene::paper().euler_bernoulli_tip_stiffness();
    let r = c.resolve(
        &MJ_TRIAL,
        previous(Stick, 0.0, 0.0),
        BELT,
        LIMIT,
        Kinetic::External { force: 20.0 },
    );
    // The stick deflection is u_free + F du/dF with F = -1 N: 43.76 N reported,
    // while the clamp holds the -1 N reaction.
    let deflection = MJ_TRIAL.free_tip_displacement + r.force * MJ_TRIAL.displacement_per_force;
    assert_eq!(r.state, Stick);
    assert_eq!(r.holding_force, k * deflection);
    let r = c.resolve(
        &MJ_TRIAL,
        previous(Stick, 0.0, 0.0),
        BELT,
        40.0,
        Kinetic::External { force: 20.0 },
    );
    assert_eq!(
        r.state, Stick,
        "the clamp compares the reaction, not k delta"
    );
}
