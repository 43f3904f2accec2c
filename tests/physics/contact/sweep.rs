//! Safeguarded Newton against the fixed-point reference (`SlipSolver`) over many slip
//! steps, through `Contact::resolve`: a static limit below zero makes every holding
//! force inadmissible, so each step slips with the force its solver found.

use super::{previous, BELT};
use stickslip::contact::{Contact, ContactState, Kinetic, Resolution, SlipSolver, SLIP_TOLERANCE};
use stickslip::elementary::signum_or_zero;
use stickslip::friction::{coulomb::CoulombLaw, exponential::ExponentialLaw, FrictionLaw};
use stickslip::integrator::{Coefficients, TrialStep};
use stickslip::neural::NeuralLaw;
use stickslip::scene::{CheckedScene, Scheme, SlidingVelocity};

/// No holding force is admissible below a negative limit: the step slips.
const SLIPS: f64 = -1.0;

/// What the sweep below met, per law.
#[derive(Default, Debug)]
struct Met {
    /// Both converged (to each other).
    agreed: usize,
    /// No solution: Newton kept the fixed-point iteration's number.
    jump: usize,
    /// Of these, with sliding_velocity = "relative" (with "tip" the law's argument
    /// jumps from |v_tip| to -|v_tip| at the reversal, whatever the law).
    relative_jump: usize,
    /// The fixed-point iteration did not converge, Newton found the root.
    rescued: usize,
    /// Both converged, to different roots (sliding_velocity = "tip" only).
    ambiguous: usize,
}

/// The paper scene's contact under `scheme` with `sliding_velocity`, solving by `solver`.
fn contact(scheme: Scheme, sliding_velocity: SlidingVelocity, solver: SlipSolver) -> Contact {
    let mut scene = CheckedScene::paper().into_scene();
    scene.integrator.scheme = scheme;
    scene.contact.sliding_velocity = sliding_velocity;
    let scene = scene.check().unwrap();
    let mut contact = Contact::new(&scene, Coefficients::from_scene(&scene));
    contact.set_slip_solver(solver);
    contact
}

/// A slip step, and the law's argument x(F) in it as the contact's notes define it:
/// v_rel at the law's level (1 - alpha_f) v_rel,n+1 + alpha_f v_rel,n, or |v_tip| at that
/// level in v_rel's direction; v_tip,n+1 = v_free + F dv/dF.
struct Step {
    trial: TrialStep,
    /// Generalised-alpha's alpha_f, 0 for Moreau-Jean (the law at t_{n+1}).
    alpha_f: f64,
    previous_relative_velocity: f64,
    sliding_velocity: SlidingVelocity,
}

impl Step {
    /// x (m/s), dx/dF (m/(s N)) and the direction of sliding at tip force `force` (N);
    /// `side` = Some(above) takes the limit from above or below the reversal force, with
    /// |x| at least the smallest normal number so that the law sees the direction.
    fn argument(&self, force: f64, side: Option<bool>) -> (f64, f64, f64) {
        let a = self.alpha_f;
        let rate = (1.0 - a) * self.trial.velocity_per_force;
        let v_tip = self.trial.free_tip_velocity + force * self.trial.velocity_per_force;
        let level = (1.0 - a) * (BELT - v_tip) + a * self.previous_relative_velocity;
        let (direction, least) = match side {
            None => (signum_or_zero(level), 0.0),
            // v_rel at the law's level falls with F at the rate (1 - alpha_f) dv/dF.
            Some(above) => (
                if above { -rate.signum() } else { rate.signum() },
                f64::MIN_POSITIVE,
            ),
        };
        match self.sliding_velocity {
            SlidingVelocity::Relative if side.is_some() => (direction * least, -rate, direction),
            SlidingVelocity::Relative => (level, -rate, direction),
            SlidingVelocity::Tip => {
                let tip = (1.0 - a) * v_tip + a * self.trial.start_tip_velocity;
                let x = direction * tip.abs().max(least);
                (x, direction * signum_or_zero(tip) * rate, direction)
            }
        }
    }

    /// The force (N) at which the direction of sliding reverses, if it does.
    fn reversal(&self) -> Option<f64> {
        let a = self.alpha_f;
        let rate = (1.0 - a) * self.trial.velocity_per_force;
        let force = ((1.0 - a) * (BELT - self.trial.free_tip_velocity)
            + a * self.previous_relative_velocity)
            / rate;
        (rate != 0.0 && force.is_finite()).then_some(force)
    }

    /// |r| / |r'| at `force` for r(F) = F - F_law(x(F)) under F_n = 100 N, Newton's
    /// estimate of its distance to the root (N). A root at the edge of the jump (F =
    /// F_law(0+) or F_law(0-)) solves the equation from that side.
    fn root_error(&self, force: f64, law: &mut dyn FrictionLaw) -> f64 {
        let sides = if self.argument(force, None).2 == 0.0 {
            vec![Some(false), Some(true)]
        } else {
            vec![None]
        };
        sides
            .into_iter()
            .map(|side| {
                let (x, slope, _) = self.argument(force, side);
                let (value, law_slope) = law.sliding_force_and_slope(x, 100.0);
                (force - value).abs() / (1.0 - law_slope * slope).abs()
            })
            .fold(f64::INFINITY, f64::min)
    }
}

/// The slip force `contact` resolves for `step` from the last force `start` (N) with
/// `law` at F_n = 100 N.
fn resolve(contact: &Contact, step: &Step, law: &mut dyn FrictionLaw, start: f64) -> Resolution {
    let previous = previous(ContactState::Slip, step.previous_relative_velocity, start);
    let kinetic = Kinetic::Law {
        law,
        normal_force: 100.0,
    };
    let r = contact.resolve(&step.trial, previous, BELT, SLIPS, kinetic);
    assert_eq!(r.state, ContactState::Slip);
    r
}

/// Newton against the fixed-point reference over slip steps near the paper's scale:
/// tip compliances of the paper's step and of a 10x step, both schemes' law levels,
/// both sliding velocities, arguments from -0.05 to 0.05 m/s (reversals included)
/// and starting forces on either side.
///
/// Where the fixed-point iteration converges, both stop within SLIP_TOLERANCE of the
/// root: the fixed point returns F_law(x(F_k)) with |F_law(x(F_k)) - F_k| <= tol, so
/// its error is q tol / (1 - q) at contraction q < 1/2, and Newton's correction
/// bounds its own; they agree to 2 tol (1 + |F|). Where it does not converge, the
/// equation has no solution (the residuals just beside the reversal have opposite
/// signs, and both return the reversal force, bit for bit: `contact::jump`) or Newton
/// found a root, |r| / r' <= tol.
fn sweep(law: &mut dyn FrictionLaw) -> Met {
    let mut met = Met::default();
    let alpha_f = super::alpha_f();
    for velocity_per_force in [2e-5, 2e-4] {
        for (scheme, alpha) in [
            (Scheme::MoreauJean, 0.0),
            (Scheme::GeneralizedAlpha, alpha_f),
        ] {
            for sliding_velocity in [SlidingVelocity::Relative, SlidingVelocity::Tip] {
                let newton = contact(scheme, sliding_velocity, SlipSolver::Newton);
                let reference = contact(scheme, sliding_velocity, SlipSolver::FixedPoint);
                for k in -50..=50 {
                    for (start, previous_relative_velocity) in [
                        (-50.0, -1e-3),
                        (-20.0, -0.01),
                        (0.0, 0.0),
                        (30.0, 2e-3),
                        (50.0, 0.02),
                    ] {
                        let step = Step {
                            trial: TrialStep {
                                dt: 1e-4,
                                start_tip_displacement: 7e-3,
                                start_tip_velocity: 0.01,
                                free_tip_displacement: 7.002e-3,
                                // x0 = (1 - alpha_f) (v_b - v_free) + ..., from -0.05 to
                                // 0.05 m/s, densest near 0.
                                free_tip_velocity: BELT - 0.05 * (k as f64 / 50.0).powi(3),
                                displacement_per_force: 1e-9,
                                velocity_per_force,
                            },
                            alpha_f: alpha,
                            previous_relative_velocity,
                            sliding_velocity,
                        };
                        let fixed = resolve(&reference, &step, &mut *law, start);
                        let (fixed, fixed_converged) = (fixed.force, fixed.slip.unwrap().solved);
                        let r = resolve(&newton, &step, &mut *law, start);
                        let (force, solved) = (r.force, r.slip.unwrap().solved);
                        let case = format!(
                            "k {k}, start {start}, dv/dF {velocity_per_force}, alpha_f {alpha}, {sliding_velocity:?}: Newton {force}, fixed point {fixed}"
                        );
                        let bound = 2.0 * SLIP_TOLERANCE * (1.0 + force.abs());
                        if fixed_converged && (force - fixed).abs() <= bound {
                            assert!(solved, "{case}");
                            met.agreed += 1;
                        } else if fixed_converged {
                            // Several solutions: |v_tip| can run against v_rel, and
                            // where the law is steep r' = 1 - F_law' x' < 0.
                            assert!(solved, "{case}");
                            assert_eq!(sliding_velocity, SlidingVelocity::Tip, "{case}");
                            assert!(step.root_error(force, &mut *law) <= bound / 2.0);
                            met.ambiguous += 1;
                        } else if !solved {
                            assert_eq!(force.to_bits(), fixed.to_bits(), "{case}");
                            let reversal = step.reversal().expect(&case);
                            let mut side = |above| {
                                let x = step.argument(reversal, Some(above)).0;
                                reversal - law.sliding_force(x, 100.0)
                            };
                            assert!(side(false) * side(true) < 0.0, "{case}");
                            // This test's reversal force, computed its own way: to
                            // rounding.
                            assert!(
                                (force - reversal).abs() <= 1e-12 * (1.0 + reversal.abs()),
                                "{case}: reversal {reversal}"
                            );
                            met.jump += 1;
                            if sliding_velocity == SlidingVelocity::Relative {
                                met.relative_jump += 1;
                            }
                        } else {
                            let error = step.root_error(force, &mut *law);
                            assert!(error <= bound / 2.0, "{case}: |r| / |r'| = {error}");
                            met.rescued += 1;
                        }
                    }
                }
            }
        }
    }
    met
}

#[test]
fn newton_agrees_with_the_fixed_point_where_it_converges_and_keeps_it_where_nothing_does() {
    let mut exponential = ExponentialLaw {
        static_coefficient: 0.5,
        kinetic_coefficient: 0.2,
        decay: 5.0,
    };
    // Laws with a jump at v = 0 meet steps without solution (the sweep crowds its
    // arguments near 0). The fixed point also cycles across the jump in some steps
    // that have a solution (at the edge of the jump, F = F_law(0-), or with
    // sliding_velocity = "tip" at the larger step), which Newton finds.
    let met = sweep(&mut exponential);
    assert!(
        met.agreed > 1000 && met.jump > 50 && met.ambiguous == 0,
        "{met:?}"
    );
    let met = sweep(&mut CoulombLaw {
        kinetic_coefficient: 0.2,
    });
    assert!(
        met.agreed > 1000 && met.jump > 50 && met.ambiguous == 0,
        "{met:?}"
    );
    let mut signed = NeuralLaw::paper_signed().unwrap();
    let met = sweep(&mut signed);
    assert!(
        met.agreed > 1000 && met.jump > 50 && met.ambiguous == 0,
        "{met:?}"
    );
    // The plain network is continuous: every step on the relative velocity has a
    // solution, and where the network is steep (|F_law' x'| > 1) only Newton finds
    // it.
    let mut plain = NeuralLaw::paper_default().unwrap();
    let met = sweep(&mut plain);
    assert!(
        met.agreed > 1000 && met.relative_jump == 0 && met.rescued > 10,
        "{met:?}"
    );
}

#[test]
fn a_solution_in_the_continuous_part_takes_newton_two_evaluations_at_most_three() {
    // Slip at the paper's scale away from a reversal, the start the last step's
    // force: F moves by a few N at most per step. Moreau-Jean's law level is t_{n+1}.
    let contact = contact(
        Scheme::MoreauJean,
        SlidingVelocity::Relative,
        SlipSolver::Newton,
    );
    let mut law = ExponentialLaw {
        static_coefficient: 0.5,
        kinetic_coefficient: 0.2,
        decay: 5.0,
    };
    // |v_b - v_free| > 50 N x dv/dF = 1e-3 m/s: no reversal within the step.
    for v_free in [0.015, 0.025, 0.04, 0.1, -0.05] {
        for shift in [0.0, 0.01, 0.5, 3.0] {
            let step = Step {
                trial: TrialStep {
                    dt: 1e-4,
                    start_tip_displacement: 7e-3,
                    start_tip_velocity: v_free,
                    free_tip_displacement: 7.002e-3,
                    free_tip_velocity: v_free,
                    displacement_per_force: 1e-9,
                    velocity_per_force: 2e-5,
                },
                alpha_f: 0.0,
                previous_relative_velocity: BELT - v_free,
                sliding_velocity: SlidingVelocity::Relative,
            };
            let root = resolve(&contact, &step, &mut law, 0.0).force;
            let r = resolve(&contact, &step, &mut law, root + shift);
            let solve = r.slip.unwrap();
            assert!(solve.solved);
            assert!((r.force - root).abs() <= 2.0 * SLIP_TOLERANCE * (1.0 + root.abs()));
            assert!(
                (1..=3).contains(&solve.evaluations),
                "v_free {v_free}, start root + {shift}: {} evaluations",
                solve.evaluations
            );
        }
    }
}
