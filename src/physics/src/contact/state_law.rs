//! The step of a law with state (`crate::friction::state`): the slip solve with the law's trial
//! step, then the commit of its state (see the module notes of `contact` and
//! docs/friction-with-memory.md).

use super::kinetic::Kinetic;
use super::state::{ContactState, Previous};
use super::stick::StickReaction;
use super::{Contact, Formulation, Resolution};
use crate::friction::state::{LawStep, StatefulLaw};
use crate::friction::FrictionLaw;
use crate::integrator::TrialStep;

/// A law with state seen by the slip solve as a memoryless law over one step of length
/// `dt` (s): its force and slope are [`StatefulLaw::step_force_and_slope`] from the
/// committed state, so that the Newton iteration, which knows only `FrictionLaw`, solves
/// the implicit step unchanged.
struct StepLaw<'a> {
    law: &'a mut dyn StatefulLaw,
    dt: f64,
}

impl FrictionLaw for StepLaw<'_> {
    fn name(&self) -> &str {
        "law with state, one step"
    }

    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64 {
        self.sliding_force_and_slope(sliding_velocity, normal_force)
            .0
    }

    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64) {
        self.law.step_force_and_slope(LawStep {
            dt: self.dt,
            sliding_velocity,
            normal_force,
        })
    }

    fn resolution(&self) -> f64 {
        self.law.force_resolution()
    }
}

impl Contact {
    /// The step of a law with state (`crate::friction::state`): no set-valued stick, so every
    /// step solves the slip force F = F_step(x(F)) with the law's trial step over dt
    /// (its force and exact total slope, the state update included), then commits the
    /// law's state at the accepted x, v_rel at the scheme's law level. The state stays
    /// the contact's `Stick` while |v_rel,n+1| < eps (the stick threshold), `Slip`
    /// otherwise; the holding force is the stick reaction's, reported only.
    pub fn resolve_with_memory(
        &self,
        trial: &TrialStep,
        previous: Previous,
        belt_speed: f64,
        law: &mut dyn StatefulLaw,
        normal_force: f64,
    ) -> Resolution {
        let (alpha_f, stick) = match self.formulation {
            Formulation::GeneralizedAlpha { alpha_f } => (
                alpha_f,
                StickReaction::displacement_level(trial, belt_speed),
            ),
            Formulation::MoreauJean => (0.0, StickReaction::velocity_level(trial, belt_speed)),
        };
        let dt = trial.dt;
        let slip = {
            let mut step_law = StepLaw { law, dt };
            let mut kinetic = Kinetic::Law {
                law: &mut step_law,
                normal_force,
            };
            self.slip
                .solve(trial, previous, belt_speed, &mut kinetic, alpha_f)
        };
        let sliding_velocity =
            (1.0 - alpha_f) * slip.relative_velocity + alpha_f * previous.relative_velocity;
        law.commit(LawStep {
            dt,
            sliding_velocity,
            normal_force,
        });
        let state = if slip.relative_velocity.abs() < self.stick_threshold {
            ContactState::Stick
        } else {
            ContactState::Slip
        };
        Resolution {
            state,
            force: slip.force,
            holding_force: self.holding.force(&stick),
            slip: Some(slip.solve),
        }
    }
}
