//! The switch rules: which of the stick reaction and the slip force a step takes, by
//! Leine's rule (generalised-alpha, at displacement level) or by the impulse clamp
//! (Moreau-Jean, at velocity level); `Contact::resolve` applies them (see the module
//! notes of `contact`).

use super::state::ContactState;

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
