//! LuGre and rate-and-state on their own, against closed forms. Both laws advance their
//! state exactly for a velocity held over a step, so at constant velocity they match
//! the closed forms to rounding whatever the step; the tolerances below are rounding
//! (a few hundred ulps over thousands of steps) unless a comment says otherwise.

use stickslip::elementary::{exp, ln};
use stickslip::friction::lugre::LuGreLaw;
use stickslip::friction::lugre::LuGreParameters;
use stickslip::friction::rate_and_state::RateStateLaw;
use stickslip::friction::rate_and_state::{RateStateParameters, StateEvolution};
use stickslip::friction::state::{LawStep, StatefulLaw};
use stickslip::friction::{exponential::ExponentialLaw, FrictionLaw};

const NORMAL: f64 = 100.0;

fn exponential() -> ExponentialLaw {
    ExponentialLaw {
        static_coefficient: 0.5,
        kinetic_coefficient: 0.2,
        decay: 5.0,
    }
}

fn lugre(sigma1: f64, sigma2: f64) -> LuGreLaw {
    LuGreLaw::new(
        LuGreParameters {
            bristle_stiffness: 1e7,
            bristle_damping: sigma1,
            viscous_damping: sigma2,
        },
        exponential(),
    )
}

fn step(dt: f64, v: f64) -> LawStep {
    LawStep {
        dt,
        sliding_velocity: v,
        normal_force: NORMAL,
    }
}

/// Holds `v` for `steps` steps of `dt`, committing each; the force of the last.
fn hold(law: &mut dyn StatefulLaw, dt: f64, v: f64, steps: usize) -> f64 {
    let mut force = f64::NAN;
    for _ in 0..steps {
        force = law.step_force_and_slope(step(dt, v)).0;
        law.commit(step(dt, v));
    }
    force
}

/// At constant v the bristles settle at z = sign(v) g(v) / sigma0 and the force at
/// g(v) sign(v) + sigma2 v, from either side and through a reversal. The relaxation
/// rate is c = sigma0 |v| / g >= 200 1/s here, so 0.5 s leaves exp(-100) of the
/// transient: what remains is rounding.
#[test]
fn lugre_converges_to_the_steady_law_at_constant_velocity() {
    let mut law = lugre(1e3, 40.0);
    for v in [0.05, -0.03, 0.2, -1e-3] {
        let force = hold(&mut law, 1e-4, v, 5000);
        let g = exponential().coefficient(v) * NORMAL;
        let expected = g * v.signum() + 40.0 * v;
        assert!(
            (force - expected).abs() < 1e-9 * expected.abs(),
            "v {v}: {force} vs {expected}"
        );
        assert!((law.state()[0] - v.signum() * g / 1e7).abs() < 1e-15);
        assert_eq!(law.sliding_force(v, NORMAL), expected);
    }
}

/// From rest, a small displacement x at a constant slow velocity gives the closed form
/// z(x) = (g / sigma0)(1 - exp(-sigma0 x / g)) (dz/dx = 1 - sigma0 z / g at constant
/// g), which is sigma0 x to second order: F = sigma0 x (1 - sigma0 x / (2 g) + ...).
/// With sigma1 = sigma2 = 0 the force is sigma0 z. At x = 1e-8 m the second-order term
/// is sigma0 x / (2 g) = 1e-3: the presliding force is sigma0 x within 1.1e-3, and
/// the closed form within rounding.
#[test]
fn lugre_presliding_force_is_the_bristle_stiffness_times_the_displacement() {
    let mut law = lugre(0.0, 0.0);
    let (v, dt, steps) = (1e-6, 1e-4, 100);
    let force = hold(&mut law, dt, v, steps);
    let x = v * dt * steps as f64;
    let g = exponential().coefficient(v) * NORMAL;
    let closed = g * (1.0 - exp(-1e7 * x / g));
    assert!(
        (force - closed).abs() < 1e-12 * closed,
        "{force} vs {closed}"
    );
    let linear = 1e7 * x;
    assert!(
        ((force - linear) / linear).abs() < 1.1e-3,
        "{force} vs {linear}"
    );
    assert!(((force - linear) / linear).abs() > 0.9e-3); // the second-order term is seen
}

/// A trial step leaves the committed state alone; a commit moves it to the state the
/// trial used; get and set round-trip bit for bit; a bad state is refused unchanged.
#[test]
fn trials_do_not_move_the_state_and_states_round_trip() {
    let mut laws: Vec<Box<dyn StatefulLaw>> = vec![
        Box::new(lugre(1e3, 0.0)),
        Box::new(RateStateLaw::new(RateStateParameters::default())),
    ];
    for law in &mut laws {
        let start = law.state().to_vec();
        let (f1, _) = law.step_force_and_slope(step(1e-4, 0.01));
        law.step_force_and_slope(step(1e-4, -0.3));
        assert_eq!(law.state(), &start[..]);
        law.commit(step(1e-4, 0.01));
        let moved = law.state().to_vec();
        assert_ne!(moved, start);
        law.set_state(&start).unwrap();
        assert_eq!(law.step_force_and_slope(step(1e-4, 0.01)).0, f1);
        assert!(law.set_state(&[1.0, 2.0]).is_err());
        assert!(law.set_state(&[f64::NAN]).is_err());
        assert_eq!(law.state(), &start[..]);
        law.reset();
        assert_eq!(law.state(), &start[..]);
    }
    let mut rate_state = RateStateLaw::new(RateStateParameters::default());
    let error = rate_state.set_state(&[0.0]).unwrap_err().to_string();
    assert!(
        error.contains("state_theta") && error.contains("> 0"),
        "{error}"
    );
}

/// The step's slope is the total derivative of the step's force, state update
/// included: against a central difference with h = 1e-3 |v| (the forces vary on the
/// scale |v| here, so truncation is ~(h / v)^2 = 1e-6 of the slope, and rounding
/// eps |F| / (h |F'|) is below 5e-5 at the smallest v, 1e-6 m/s: tolerance 1e-4) for both laws, both evolution
/// laws, from states away from and at steady state, away from v = 0 (LuGre's kink).
#[test]
fn step_slopes_are_the_derivatives_of_the_step_forces() {
    let mut laws: Vec<(&str, Box<dyn StatefulLaw>)> = vec![("lugre", Box::new(lugre(1e3, 30.0)))];
    for (name, evolution) in [
        ("aging", StateEvolution::Aging),
        ("slip", StateEvolution::Slip),
    ] {
        laws.push((
            name,
            Box::new(RateStateLaw::new(RateStateParameters {
                state_evolution: evolution,
                ..RateStateParameters::default()
            })),
        ));
    }
    for (name, law) in &mut laws {
        for (history, dt) in [(0.0, 1e-4), (0.02, 1e-4), (-0.01, 1e-3), (1e-5, 1e-5)] {
            law.reset();
            if history != 0.0 {
                hold(law.as_mut(), dt, history, 7);
            }
            for v in [1e-6, -2e-4, 3e-3, 0.02, -0.5] {
                let (_, slope) = law.step_force_and_slope(step(dt, v));
                let h = 1e-3 * v.abs();
                let up = law.step_force_and_slope(step(dt, v + h)).0;
                let down = law.step_force_and_slope(step(dt, v - h)).0;
                let difference = (up - down) / (2.0 * h);
                assert!(
                    (slope - difference).abs() <= 1e-4 * slope.abs().max(1e-3),
                    "{name} after {history} m/s, v {v}: {slope} vs {difference}"
                );
            }
        }
    }
}

fn rate_state(evolution: StateEvolution) -> RateStateLaw {
    RateStateLaw::new(RateStateParameters {
        state_evolution: evolution,
        ..RateStateParameters::default()
    })
}

/// The asinh form differs from the classical law by a asinh(w) - a ln(2 w) ~ a / (4 w^2)
/// with w ~ exp(mu / a) / 2 >= e^40 here: far below rounding. So the steady state is
/// mu_0 + (a - b) ln(V / V_0) to rounding once the transient exp(-V t / D_c) is gone
/// (held for a slip of 50 D_c: e^-50).
#[test]
fn rate_and_state_converges_to_its_steady_state_at_constant_velocity() {
    for evolution in [StateEvolution::Aging, StateEvolution::Slip] {
        let mut law = rate_state(evolution);
        let p = law.parameters().clone();
        for v in [0.02f64, -0.1, 1e-4, 3e-3] {
            let dt = 10.0 * p.characteristic_slip / v.abs();
            let force = hold(&mut law, dt, v, 5);
            let expected = v.signum() * p.steady_coefficient(v.abs()) * NORMAL;
            assert!(
                (force - expected).abs() < 1e-12 * NORMAL,
                "{evolution:?} v {v}: {force} vs {expected}"
            );
            assert!(
                (law.state()[0] - p.characteristic_slip / v.abs()).abs() < 1e-12 * law.state()[0]
            );
            assert!((law.sliding_force(v, NORMAL) - expected).abs() < 1e-12 * NORMAL);
        }
    }
}

/// A velocity step V1 -> V2 from steady sliding: the force jumps by a ln(V2 / V1) F_n
/// at once (theta has not moved yet), then relaxes to the new steady state over a slip
/// of D_c. In the classical form mu = mu_ss(V2) + b ln(V2 theta / D_c), and at constant
/// V2 the closed forms are
/// - aging: theta = D_c / V2 + (D_c / V1 - D_c / V2) exp(-delta / D_c),
/// - slip: ln(V2 theta / D_c) = ln(V2 / V1) exp(-delta / D_c),
///
/// with delta = V2 t the slip since the step. Checked along the relaxation, and the
/// e-folding slip of the slip law is D_c exactly.
#[test]
fn a_velocity_step_jumps_by_the_direct_effect_and_relaxes_over_the_characteristic_slip() {
    let (v1, v2) = (1e-3, 1e-2);
    for evolution in [StateEvolution::Aging, StateEvolution::Slip] {
        let mut law = rate_state(evolution);
        let p = law.parameters().clone();
        let (a, b, d_c) = (p.direct_effect, p.evolution_effect, p.characteristic_slip);
        let before = hold(&mut law, d_c / v1, v1, 60);
        // A first step of a slip of 1e-9 D_c sees the state unmoved to 1e-9 b F_n.
        let tiny = 1e-9 * d_c / v2;
        let jump = law.step_force_and_slope(step(tiny, v2)).0 - before;
        let direct = a * ln(v2 / v1) * NORMAL;
        assert!(
            (jump - direct).abs() < 1e-8 * NORMAL,
            "{evolution:?}: {jump} vs {direct}"
        );
        // Then the relaxation, at slips of 0.25 D_c to 5 D_c after the step.
        let dt = 0.25 * d_c / v2;
        for k in 1..=20 {
            let force = law.step_force_and_slope(step(dt, v2)).0;
            law.commit(step(dt, v2));
            let slip = k as f64 * 0.25 * d_c;
            let decay = exp(-slip / d_c);
            let log_excess = match evolution {
                StateEvolution::Aging => ln(1.0 + (v2 / v1 - 1.0) * decay),
                StateEvolution::Slip => ln(v2 / v1) * decay,
            };
            let expected = (p.steady_coefficient(v2) + b * log_excess) * NORMAL;
            assert!(
                (force - expected).abs() < 1e-11 * NORMAL,
                "{evolution:?} at {slip:e} m: {force} vs {expected}"
            );
        }
    }
}
