//! Stick/slip contact of the beam tip on the belt: Karnopp's model with Leine's switch
//! logic (Leine, van Campen, de Kraker, van den Steen, Nonlinear Dynamics 16 (1998) 41).
//!
//! - Stick: the tip moves with the belt; the holding force is the constraint reaction of
//!   a trial stick step.
//! - Stick -> slip when |F_hold| > mu_s F_n.
//! - Slip -> stick when the relative velocity has fallen below eps, or changed sign, and
//!   the holding force that stick would need this step is admissible, |F_hold| <= mu_s F_n.
//!   Without that second condition the contact re-sticks the very step after breakaway,
//!   when v_rel is still ~0, and never slips (the paper's literal rule; see the notes).
//!
//! Both switches use the same holding force, the reaction of the same discrete balance, so
//! they cannot disagree and chatter.

use serde::{Deserialize, Serialize};

/// Contact state of the tip.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ContactState {
    Stick,
    Slip,
}

/// A change of contact state at time `time` (s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Transition {
    pub time: f64,
    pub to: ContactState,
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

#[cfg(test)]
mod tests {
    use super::*;
    use ContactState::*;

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
}
