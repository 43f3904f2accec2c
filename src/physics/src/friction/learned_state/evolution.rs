//! The learned law's state evolution, a choice between the two laws of rate-and-state
//! friction (`crate::friction::rate_and_state::StateEvolution`, the scene's names):
//!
//! ```text
//! aging (Dieterich 1979):  d theta/dt = 1 - |v| theta / D_c                  (`aging`)
//! slip  (Ruina 1983):      d theta/dt = -(|v| theta / D_c) ln(|v| theta / D_c) (`slip`)
//! ```
//!
//! both in the log state psi = ln(theta V_0 / D_c) and both advanced over a step exactly
//! for the step's end velocity held over the step, so that the step is implicit in
//! v_{n+1} (the contact's slip solve differentiates it: [`StateStep::d_velocity`]) with
//! no time-step error for piecewise-constant speed. Both have the steady state
//! theta_ss = D_c / |v|, psi_ss = ln(V_0 / |v|). They differ at rest: the aging law heals
//! (theta grows by the time at rest), the slip law is frozen (no slip, no change).

pub use crate::friction::rate_and_state::StateEvolution;

pub use super::state_step::StateStep;
use super::{aging, slip};

/// The steady state psi_ss = ln(V_0 / V) at sliding speed `speed` > 0 (m/s), the same
/// for both evolutions.
pub fn steady_state(speed: f64, reference_velocity: f64) -> f64 {
    crate::elementary::ln(reference_velocity / speed)
}

/// Advances psi by `evolution` over a step of `step` seconds ending at sliding velocity
/// `velocity` (m/s), with characteristic slip `slip` (D_c, m) and reference velocity
/// `reference_velocity` (V_0, m/s).
pub fn step(
    evolution: StateEvolution,
    state: f64,
    velocity: f64,
    step: f64,
    slip: f64,
    reference_velocity: f64,
) -> StateStep {
    match evolution {
        StateEvolution::Aging => aging::step(state, velocity, step, slip, reference_velocity),
        StateEvolution::Slip => slip::step(state, velocity, step, slip, reference_velocity),
    }
}
