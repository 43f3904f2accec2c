//! The velocity-step response of a law with rate-and-state memory, measured the way a
//! tribometer's record is read (Dieterich 1979; Marone 1998, "Laboratory-derived
//! friction laws", Fig. 4): slide at V_1 until steady, step to V_2, and read
//! - the direct effect: the jump of mu = F / F_n at the step, at unchanged state
//!   (a ln(V_2 / V_1) for the Dieterich-Ruina law);
//! - the decay length: the slip after the step over which the excess of mu over its
//!   new steady value falls to 1/e of its value at the step. For the aging law the
//!   excess is b ln(1 + (V_2/V_1 - 1) e^{-delta / D_c}), so this length is D_c times a
//!   function of V_2/V_1 alone: two laws' decay lengths at the same step are in the
//!   ratio of their D_c.

use super::law::LearnedStateLaw;

/// What a velocity step shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepResponse {
    /// Jump of mu at the step (1).
    pub direct_effect: f64,
    /// mu at steady sliding after the step minus before (1): (a - b) ln(V_2/V_1).
    pub steady_change: f64,
    /// Slip over which the excess falls to 1/e (m).
    pub decay_length: f64,
}

/// The response of `law` to a step V_1 -> V_2 (m/s, both > 0) at normal force
/// `normal_force` (N), stepped at `slip_step` (m) of slip per step (exact steps: the
/// stepping only samples the curve; the 1/e point is interpolated linearly between
/// samples, so its error is below `slip_step`).
pub fn velocity_step(
    law: &LearnedStateLaw,
    v1: f64,
    v2: f64,
    normal_force: f64,
    slip_step: f64,
) -> StepResponse {
    let mu = |state: f64, v: f64| law.force(state, v, normal_force).force / normal_force;
    let before = law.steady_state(v1);
    // Steady state after: step far (exact stepping: a step of 1e3 D_c / V_2 is steady).
    let far = law
        .step_state(before, v2, 1e3 * law.parameters.characteristic_slip / v2)
        .state;
    let (mu_before, mu_jump, mu_after) = (mu(before, v1), mu(before, v2), mu(far, v2));
    let excess0 = mu_jump - mu_after;
    let target = excess0 / std::f64::consts::E;
    let dt = slip_step / v2;
    let (mut state, mut slip, mut excess) = (before, 0.0, excess0);
    let mut decay_length = f64::NAN;
    for _ in 0..1_000_000 {
        let next_state = law.step_state(state, v2, dt).state;
        let next_excess = mu(next_state, v2) - mu_after;
        if (next_excess - target) * (excess - target) <= 0.0 {
            let share = (excess - target) / (excess - next_excess);
            decay_length = slip + share * slip_step;
            break;
        }
        (state, excess, slip) = (next_state, next_excess, slip + slip_step);
    }
    StepResponse {
        direct_effect: mu_jump - mu_before,
        steady_change: mu_after - mu_before,
        decay_length,
    }
}
