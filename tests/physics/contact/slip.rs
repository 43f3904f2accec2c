//! The slip force `Contact::resolve` takes: the law's fixed point at generalised-alpha's
//! level, a steep law's root, a law with a jump, and a coupled model's tangent.

use super::{alpha_f, contact, coulomb, level, previous, BELT, LIMIT, LOW_LIMIT, NEAR_ZERO, TRIAL};
use stickslip::contact::{ContactState::*, Direction, Kinetic, SlipSolver};
use stickslip::friction::{exponential::ExponentialLaw, FrictionLaw};
use stickslip::scene::{HoldingForce, Scheme};

#[test]
fn slip_force_is_the_fixed_point_of_the_law_at_the_alpha_f_level() {
    let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
    let alpha_f = alpha_f();
    let mut law = ExponentialLaw {
        static_coefficient: 0.5,
        kinetic_coefficient: 0.2,
        decay: 5.0,
    };
    // Fast slip (v_rel ~ -0.01 m/s at both ends): no re-stick.
    let kinetic = Kinetic::Law {
        law: &mut law,
        normal_force: 100.0,
    };
    let previous_relative_velocity = -0.012;
    let r = c.resolve(
        &TRIAL,
        previous(Slip, previous_relative_velocity, -40.0),
        BELT,
        LIMIT,
        kinetic,
    );
    assert_eq!(r.state, Slip);
    let v_rel = BELT - (TRIAL.free_tip_velocity + r.force * TRIAL.velocity_per_force);
    let level = (1.0 - alpha_f) * v_rel + alpha_f * previous_relative_velocity;
    let mut check = ExponentialLaw {
        static_coefficient: 0.5,
        kinetic_coefficient: 0.2,
        decay: 5.0,
    };
    let expected = check.sliding_force(level, 100.0);
    assert!(
        (r.force - expected).abs() < 1e-10,
        "{} vs {expected}",
        r.force
    );
}

/// F(v) = 50 N tanh(v / 1e-4 m/s): continuous, with dF/dv = 5e5 N s/m at v = 0,
/// steeper than the fixed-point iteration can follow at TRIAL's dv/dF (the safeguarded
/// Newton iteration solves it).
struct SteepLaw;

impl FrictionLaw for SteepLaw {
    fn name(&self) -> &str {
        "steep"
    }

    fn sliding_force(&mut self, v: f64, _normal_force: f64) -> f64 {
        50.0 * stickslip::elementary::tanh(v / 1e-4)
    }

    fn sliding_force_and_slope(&mut self, v: f64, _normal_force: f64) -> (f64, f64) {
        let t = stickslip::elementary::tanh(v / 1e-4);
        (50.0 * t, 50.0 / 1e-4 * (1.0 - t * t))
    }
}
#[test]
fn a_steep_continuous_law_gets_its_root_where_the_fixed_point_iteration_diverges() {
    let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
    // Gain |dF/dv| (1 - alpha_f) dv/dF = 5e5 x 0.56 x 2e-5 ~ 5.5 > 1: the plain
    // iteration swings between two forces.
    let gain = 5e5 * (1.0 - alpha_f()) * NEAR_ZERO.velocity_per_force;
    assert!(gain > 5.0, "{gain}");
    let mut law = SteepLaw;
    let kinetic = Kinetic::Law {
        law: &mut law,
        normal_force: 100.0,
    };
    let r = c.resolve(
        &NEAR_ZERO,
        previous(Slip, 0.0, 30.0),
        BELT,
        LOW_LIMIT,
        kinetic,
    );
    assert_eq!(r.state, Slip);
    let expected = SteepLaw.sliding_force(level(&NEAR_ZERO, 0.0, r.force), 100.0);
    // Safeguarded Newton to SLIP_TOLERANCE: the residual is the law's slope times
    // the last correction, times the gain, well below 1e-9 N.
    assert!(
        (r.force - expected).abs() < 1e-9,
        "F = {} N, law at its argument {expected} N",
        r.force
    );
    assert!(r.force.abs() > 1.0 && r.force.abs() < 49.0, "{}", r.force);
}

/// Coulomb's law jumps by 2 mu_k F_n = 40 N at v = 0, and the force-free step ends at
/// v_rel = -1e-4 m/s: -20 N gives v_rel > 0, +20 N gives v_rel < 0. There is no root;
/// the set-valued law's solution is the force at which the law's argument is 0,
/// v_rel(F) = -1e-4 - 2e-5 F = 0 at F = -5 N, inside the jump. The fixed-point
/// iteration swings between the two sides, and its last iterate (either side's 20 N,
/// by parity) put the full force of one side on a tip that only reached the belt's
/// speed (issue 37); both solvers now take -5 N, bit for bit the same.
#[test]
fn a_law_with_a_jump_takes_the_reversal_force_when_the_step_crosses_it() {
    let mut forces = Vec::new();
    for solver in [SlipSolver::Newton, SlipSolver::FixedPoint] {
        let mut c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
        c.set_slip_solver(solver);
        let mut law = coulomb();
        let r = c.resolve(
            &NEAR_ZERO,
            previous(Slip, 0.0, 20.0),
            BELT,
            LOW_LIMIT,
            Kinetic::Law {
                law: &mut law,
                normal_force: 100.0,
            },
        );
        // LOW_LIMIT makes re-stick inadmissible: the step slips with that force.
        assert_eq!(r.state, Slip, "{solver:?}");
        assert_eq!(r.slip.map(|s| s.solved), Some(false), "{solver:?}");
        // -5 N to rounding: 1e-4 / 2e-5 carries a relative error of a few ulp.
        assert!(
            (r.force + 5.0).abs() < 1e-12,
            "{solver:?}: F = {} N",
            r.force
        );
        // The argument at that force is 0 to the rounding of 1e-4 m/s.
        assert!(level(&NEAR_ZERO, 0.0, r.force).abs() < 1e-18, "{solver:?}");
        forces.push(r.force);
    }
    assert_eq!(forces[0], forces[1]);
}

#[test]
fn the_external_tangent_is_solved_implicitly_where_the_held_force_would_overshoot() {
    let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
    // A tangent of the steep law at v_k = 0: F(0) = 0, S = 5e5 N s/m.
    let (held, slope, velocity) = (0.0, 5e5, 0.0);
    let r = c.resolve(
        &NEAR_ZERO,
        previous(Slip, 0.0, 30.0),
        BELT,
        LOW_LIMIT,
        Kinetic::ExternalSigned {
            force: held,
            slope,
            velocity,
            direction: Direction::AlongSlip,
        },
    );
    let v = level(&NEAR_ZERO, 0.0, r.force);
    assert!(
        (r.force - (held + slope * (v - velocity))).abs() < 1e-9,
        "F = {} N at v = {v} m/s",
        r.force
    );
    // The root of F = S (1 - alpha_f) (-1e-4 - 2e-5 F): F = -S a 1e-4 / (1 + S a 2e-5)
    // with a = 1 - alpha_f.
    let a = 1.0 - alpha_f();
    let closed_form = -slope * a * 1e-4 / (1.0 + slope * a * 2e-5);
    assert!(
        (r.force - closed_form).abs() < 1e-9,
        "{} vs {closed_form}",
        r.force
    );
}

#[test]
fn the_held_signed_force_acts_as_given_along_the_sliding_velocity_and_as_its_magnitude_against_it()
{
    let c = contact(Scheme::GeneralizedAlpha, HoldingForce::Reaction);
    // TRIAL in fast slip, v_rel ~ -0.01 m/s: a held -7 N (slope 0) points along it
    // and acts as given.
    let signed = |force| Kinetic::ExternalSigned {
        force,
        slope: 0.0,
        velocity: 0.3,
        direction: Direction::AlongSlip,
    };
    let r = c.resolve(
        &TRIAL,
        previous(Slip, -0.012, -40.0),
        BELT,
        LIMIT,
        signed(-7.0),
    );
    assert_eq!((r.state, r.force), (Slip, -7.0));
    // A held +7 N points against it (the model saw the other side of v = 0): its
    // magnitude acts along v_rel, as the magnitude coupling would apply it.
    let r = c.resolve(
        &TRIAL,
        previous(Slip, -0.012, -40.0),
        BELT,
        LIMIT,
        signed(7.0),
    );
    assert_eq!((r.state, r.force), (Slip, -7.0));
    let r = c.resolve(
        &TRIAL,
        previous(Slip, -0.012, -40.0),
        BELT,
        LIMIT,
        Kinetic::External { force: 7.0 },
    );
    assert_eq!(r.force, -7.0);
}
