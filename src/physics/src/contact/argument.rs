//! The law's argument x(F) during one slip step, and where the direction of sliding
//! reverses.

use crate::elementary::signum_or_zero;
use crate::scene::SlidingVelocity;

/// The law's argument x during one slip step as a function of the tip force F: the
/// tip responds linearly, v_tip,n+1 = v_free + F dv/dF.
pub(super) struct SlipArgument {
    pub(super) belt_speed: f64,
    pub(super) free_tip_velocity: f64,
    pub(super) velocity_per_force: f64,
    pub(super) alpha_f: f64,
    /// v_rel,n (m/s).
    pub(super) previous_relative_velocity: f64,
    /// v_tip,n (m/s).
    pub(super) start_tip_velocity: f64,
    pub(super) sliding_velocity: SlidingVelocity,
}

impl SlipArgument {
    /// v_rel at t_{n+1} (m/s) under the tip force `force` (N).
    pub(super) fn relative_velocity(&self, force: f64) -> f64 {
        self.belt_speed - (self.free_tip_velocity + force * self.velocity_per_force)
    }

    /// The law's argument at t_n, as the previous step left it (m/s): v_rel,n, or with
    /// `sliding_velocity = "tip"` |v_tip,n| in the direction of v_rel,n. What the
    /// lagged slip force evaluates the law at.
    pub(super) fn at_start(&self) -> f64 {
        match self.sliding_velocity {
            SlidingVelocity::Relative => self.previous_relative_velocity,
            SlidingVelocity::Tip => {
                signum_or_zero(self.previous_relative_velocity) * self.start_tip_velocity.abs()
            }
        }
    }

    /// The law's argument under `force` (N).
    pub(super) fn at(&self, force: f64) -> Point {
        let alpha_f = self.alpha_f;
        let v_tip = self.free_tip_velocity + force * self.velocity_per_force;
        let v_rel = self.belt_speed - v_tip;
        let rel_eval = (1.0 - alpha_f) * v_rel + alpha_f * self.previous_relative_velocity;
        let direction = signum_or_zero(rel_eval);
        match self.sliding_velocity {
            SlidingVelocity::Relative => Point {
                force,
                x: rel_eval,
                slope: -(1.0 - alpha_f) * self.velocity_per_force,
                direction,
            },
            SlidingVelocity::Tip => {
                let tip = (1.0 - alpha_f) * v_tip + alpha_f * self.start_tip_velocity;
                Point {
                    force,
                    x: direction * tip.abs(),
                    slope: direction
                        * signum_or_zero(tip)
                        * (1.0 - alpha_f)
                        * self.velocity_per_force,
                    direction,
                }
            }
        }
    }

    /// The direction of sliding, sign(v_rel) at the law's level, where F is above the
    /// reversal force: d v_rel / dF = -(1 - alpha_f) dv/dF.
    pub(super) fn direction_above(&self) -> f64 {
        -((1.0 - self.alpha_f) * self.velocity_per_force).signum()
    }

    /// The force (N) at which the direction of sliding reverses (v_rel at the law's
    /// level is 0), where the law jumps; None if the direction does not depend on F.
    pub(super) fn reversal(&self) -> Option<f64> {
        let alpha_f = self.alpha_f;
        let rate = (1.0 - alpha_f) * self.velocity_per_force;
        let force = ((1.0 - alpha_f) * (self.belt_speed - self.free_tip_velocity)
            + alpha_f * self.previous_relative_velocity)
            / rate;
        (rate != 0.0 && force.is_finite()).then_some(force)
    }

    /// The argument just beside the reversal force `reversal` (N), on the side where F
    /// is `above` it or below: the magnitude the law sees there (0 for the relative
    /// velocity, as the smallest normal number so that the law sees the direction),
    /// with that side's direction.
    pub(super) fn beside_reversal(&self, reversal: f64, above: bool) -> Point {
        let alpha_f = self.alpha_f;
        let rate = (1.0 - alpha_f) * self.velocity_per_force;
        let direction = if above {
            self.direction_above()
        } else {
            -self.direction_above()
        };
        match self.sliding_velocity {
            SlidingVelocity::Relative => Point {
                force: reversal,
                x: direction * f64::MIN_POSITIVE,
                slope: -rate,
                direction,
            },
            SlidingVelocity::Tip => {
                let v_tip = self.free_tip_velocity + reversal * self.velocity_per_force;
                let tip = (1.0 - alpha_f) * v_tip + alpha_f * self.start_tip_velocity;
                Point {
                    force: reversal,
                    x: direction * tip.abs().max(f64::MIN_POSITIVE),
                    slope: direction * signum_or_zero(tip) * rate,
                    direction,
                }
            }
        }
    }
}

/// The law's argument at one tip force.
#[derive(Clone, Copy, Debug)]
pub(super) struct Point {
    /// Tip force F (N).
    pub(super) force: f64,
    /// x (m/s).
    pub(super) x: f64,
    /// dx/dF (m/(s N)) where x is differentiable.
    pub(super) slope: f64,
    /// Direction of sliding, sign(v_rel) at the law's level (0 exactly at the reversal).
    pub(super) direction: f64,
}
