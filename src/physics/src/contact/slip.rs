//! The slip solve: F = F_law(x(F)) for the step's kinetic force, by the solver the
//! contact was given (see the module notes of `contact`).

use super::argument::SlipArgument;
use super::fixed_point::fixed_point;
use super::kinetic::{CountedLaw, Kinetic};
use super::newton::newton;
use super::state::Previous;
use super::tangent::{tangent_newton, Tangent};
use crate::integrator::TrialStep;
use crate::scene::{SlidingVelocity, SlipForce};

/// How the slip force F = F_law(x(F)) is solved (see the module notes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SlipSolver {
    /// Safeguarded Newton with the law's exact slope: 1 to 3 evaluations per slip step.
    #[default]
    Newton,
    /// The fixed-point iteration F <- F_law(x(F)) of earlier versions, kept as the
    /// reference the Newton solve is tested against (tests/physics/slip_solve.rs).
    FixedPoint,
}

/// How the slip solve of a step went.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SlipSolve {
    /// Evaluations of the law (value, or value and slope: one pass each).
    pub evaluations: usize,
    /// Whether F = F_law(x(F)) was solved. False when it has no solution (zero in the
    /// law's jump; the force is then the reversal force, the set-valued law's solution,
    /// see `contact::jump`) or the solver stopped at its limit of evaluations.
    pub solved: bool,
}

/// How the contact solves its slip steps: the law's sliding velocity and the solver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SlipOptions {
    pub(super) sliding_velocity: SlidingVelocity,
    pub(super) solver: SlipSolver,
    /// Implicit (solved with the step) or lagged one step (explicit).
    pub(super) force: SlipForce,
}

impl SlipOptions {
    /// The slip force F = F_law(x(F)), solved from the last step's force, and v_rel at
    /// t_{n+1} under it; with `force = lagged`, F = F_law(x_n) instead, the law at the
    /// argument the previous step ended with.
    ///
    /// The law sees v_rel at t_{n+1-alpha_f}, (1 - alpha_f) v_rel,n+1 + alpha_f v_rel,n;
    /// with `sliding_velocity = "tip"` it sees |v_tip| at that level instead, in the
    /// direction of v_rel (otherwise there is no stick-slip).
    pub(super) fn solve(
        &self,
        trial: &TrialStep,
        previous: Previous,
        belt_speed: f64,
        kinetic: &mut Kinetic<'_>,
        alpha_f: f64,
    ) -> Slip {
        let argument = SlipArgument {
            belt_speed,
            free_tip_velocity: trial.free_tip_velocity,
            velocity_per_force: trial.velocity_per_force,
            alpha_f,
            previous_relative_velocity: previous.relative_velocity,
            start_tip_velocity: trial.start_tip_velocity,
            sliding_velocity: self.sliding_velocity,
        };
        let mut law = CountedLaw {
            kinetic,
            evaluations: 0,
        };
        if self.force == SlipForce::Lagged {
            // F_n+1 = F_law(x_n): known before the step, so nothing to solve; v_rel,n+1
            // follows from it linearly.
            let x = argument.at_start();
            let mut force = law.force(x);
            if let Kinetic::ExternalSigned {
                velocity,
                direction,
                ..
            } = *law.kinetic
            {
                // A coupled tangent pointing against the sliding velocity acts along
                // it, as in the implicit solve (`tangent`).
                if direction.flips(force, x, velocity) {
                    force = -force;
                }
            }
            return Slip {
                force,
                relative_velocity: argument.relative_velocity(force),
                solve: SlipSolve {
                    evaluations: law.evaluations,
                    solved: true,
                },
            };
        }
        let (force, solved) = match (&*law.kinetic, self.solver) {
            (
                Kinetic::ExternalSigned {
                    force,
                    slope,
                    velocity,
                    direction,
                },
                _,
            ) => {
                let tangent = Tangent {
                    force: *force,
                    slope: *slope,
                    velocity: *velocity,
                    direction: *direction,
                };
                tangent_newton(&argument, tangent, &mut law)
            }
            (_, SlipSolver::Newton) => newton(&argument, previous.force, &mut law),
            (_, SlipSolver::FixedPoint) => fixed_point(&argument, previous.force, &mut law),
        };
        Slip {
            force,
            relative_velocity: argument.relative_velocity(force),
            solve: SlipSolve {
                evaluations: law.evaluations,
                solved,
            },
        }
    }
}

/// The result of a slip solve.
pub(super) struct Slip {
    /// Tip force F (N).
    pub(super) force: f64,
    /// v_rel at t_{n+1} (m/s) under it.
    pub(super) relative_velocity: f64,
    pub(super) solve: SlipSolve,
}
