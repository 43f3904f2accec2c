//! The switch: which of the stick reaction and the slip force a step takes, by
//! Karnopp/Leine at displacement level (generalised-alpha) or by the impulse clamp at
//! velocity level (Moreau-Jean); see the module notes of `contact`.

use super::stick::StickReaction;
use super::{Contact, ContactState, Kinetic, Previous, Resolution};
use crate::integrator::TrialStep;

impl Contact {
    /// Karnopp/Leine at displacement level. In slip the slip solve comes first, since
    /// re-stick looks at the v_rel it gives; in stick it is needed only on breakaway.
    pub(super) fn resolve_generalized_alpha(
        &self,
        trial: &TrialStep,
        previous: Previous,
        belt_speed: f64,
        static_limit: f64,
        mut kinetic: Kinetic<'_>,
        alpha_f: f64,
    ) -> Resolution {
        let stick = StickReaction::displacement_level(trial, belt_speed);
        let holding_force = self.holding(&stick);
        let (state, force, slip) = match previous.state {
            ContactState::Stick => {
                match next_state(
                    ContactState::Stick,
                    holding_force,
                    static_limit,
                    0.0,
                    0.0,
                    0.0,
                ) {
                    ContactState::Stick => (ContactState::Stick, stick.force, None),
                    ContactState::Slip => {
                        let slip = self.slip(trial, previous, belt_speed, &mut kinetic, alpha_f);
                        (ContactState::Slip, slip.force, Some(slip.solve))
                    }
                }
            }
            ContactState::Slip => {
                let slip = self.slip(trial, previous, belt_speed, &mut kinetic, alpha_f);
                match next_state(
                    ContactState::Slip,
                    holding_force,
                    static_limit,
                    previous.relative_velocity,
                    slip.relative_velocity,
                    self.stick_threshold,
                ) {
                    ContactState::Stick => (ContactState::Stick, stick.force, Some(slip.solve)),
                    ContactState::Slip => (ContactState::Slip, slip.force, Some(slip.solve)),
                }
            }
        };
        Resolution {
            state,
            force,
            holding_force,
            slip,
        }
    }

    /// Acary's impulse-level contact: the clamp decides from the reaction alone.
    pub(super) fn resolve_moreau_jean(
        &self,
        trial: &TrialStep,
        previous: Previous,
        belt_speed: f64,
        static_limit: f64,
        mut kinetic: Kinetic<'_>,
    ) -> Resolution {
        let stick = StickReaction::velocity_level(trial, belt_speed);
        let holding_force = self.holding(&stick);
        let (state, force, slip) = match impulse_clamp(stick.force, static_limit) {
            ContactState::Stick => (ContactState::Stick, stick.force, None),
            ContactState::Slip => {
                // Moreau-Jean's law level is t_{n+1}: no weight on t_n.
                let slip = self.slip(trial, previous, belt_speed, &mut kinetic, 0.0);
                (ContactState::Slip, slip.force, Some(slip.solve))
            }
        };
        Resolution {
            state,
            force,
            holding_force,
            slip,
        }
    }
}

/// Leine's switch rule for one step.
///
/// `holding_force` (N) is what stick would need this step, `static_limit` = mu_s F_n (N),
/// `previous_relative_velocity` and `relative_velocity` (m/s) are v_rel at the start of
/// the step and at its end as a slip step would give it, `stick_threshold` = eps (m/s).
pub fn next_state(
    state: ContactState,
    holding_force: f64,
    static_limit: f64,
    previous_relative_velocity: f64,
    relative_velocity: f64,
    stick_threshold: f64,
) -> ContactState {
    let admissible = holding_force.abs() <= static_limit;
    match state {
        ContactState::Stick if admissible => ContactState::Stick,
        ContactState::Stick => ContactState::Slip,
        ContactState::Slip => {
            let slow = relative_velocity.abs() < stick_threshold;
            let reversed = relative_velocity * previous_relative_velocity < 0.0;
            if (slow || reversed) && admissible {
                ContactState::Stick
            } else {
                ContactState::Slip
            }
        }
    }
}

/// Moreau-Jean's switch for one step: stick when the impulse stick needs, P = F dt, lies
/// in [-mu_s F_n dt, mu_s F_n dt], compared here as |F| <= mu_s F_n (`reaction` and
/// `static_limit` in N), whatever the state before.
pub fn impulse_clamp(reaction: f64, static_limit: f64) -> ContactState {
    if reaction.abs() <= static_limit {
        ContactState::Stick
    } else {
        ContactState::Slip
    }
}
