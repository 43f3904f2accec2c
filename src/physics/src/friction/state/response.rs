//! The velocity-step response of a law with state, measured the way a tribometer's
//! record is read (Dieterich 1979; Marone 1998, "Laboratory-derived friction laws",
//! Fig. 4): slide at V_1 until steady, step to V_2, and read
//! - the direct effect: the jump of mu = F / F_n at the step, at unchanged state
//!   (a ln(V_2 / V_1) for the Dieterich-Ruina law);
//! - the decay length: the slip after the step over which the excess of mu over its
//!   new steady value falls to 1/e of its value at the step. For the aging law the
//!   excess is b ln(1 + (V_2/V_1 - 1) e^{-delta / D_c}), so this length is D_c times a
//!   function of V_2/V_1 alone: two laws' decay lengths at the same step are in the
//!   ratio of their D_c. For the slip law the excess is b ln(V_2/V_1) e^{-delta / D_c}
//!   (x = ln(V theta / D_c) decays exponentially in slip), so the length is D_c itself.
//!
//! Any [`StatefulLaw`] is measured through its trait alone, so a learned law and the
//! analytical law that generated its data are read by the same code.

use crate::friction::state::{LawStep, StatefulLaw};

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

/// A step so short that the state does not move (x = V dt / D_c ~ 1e-10 for D_c >=
/// 1e-6 m at V <= 1 m/s): the force at the committed state.
const INSTANT: f64 = 1e-16;

/// The response of `law` (reset first) to a step V_1 -> V_2 (m/s, both > 0) at normal
/// force `normal_force` (N). `settle_slip` (m) is slid at constant speed to reach a
/// steady state (one exact step; thousands of D_c); the curve after the step is sampled
/// every `slip_step` (m), and the 1/e point interpolated linearly between samples, so
/// its error is below `slip_step`.
pub fn velocity_step(
    law: &mut dyn StatefulLaw,
    (v1, v2): (f64, f64),
    normal_force: f64,
    settle_slip: f64,
    slip_step: f64,
) -> StepResponse {
    let at = |dt: f64, v: f64| LawStep {
        dt,
        sliding_velocity: v,
        normal_force,
    };
    let mu = |law: &mut dyn StatefulLaw, v: f64| {
        law.step_force_and_slope(at(INSTANT, v)).0 / normal_force
    };
    law.reset();
    law.commit(at(settle_slip / v1, v1));
    let before = law.state().to_vec();
    let (mu_before, mu_jump) = (mu(law, v1), mu(law, v2));
    law.commit(at(settle_slip / v2, v2));
    let mu_after = mu(law, v2);
    // The state was taken from this law: it fits.
    let _ = law.set_state(&before);
    let excess0 = mu_jump - mu_after;
    let target = excess0 / std::f64::consts::E;
    let (mut slip, mut excess) = (0.0, excess0);
    let mut decay_length = f64::NAN;
    for _ in 0..10_000_000 {
        law.commit(at(slip_step / v2, v2));
        let next = mu(law, v2) - mu_after;
        if (next - target) * (excess - target) <= 0.0 {
            decay_length = slip + (excess - target) / (excess - next) * slip_step;
            break;
        }
        (excess, slip) = (next, slip + slip_step);
    }
    StepResponse {
        direct_effect: mu_jump - mu_before,
        steady_change: mu_after - mu_before,
        decay_length,
    }
}

/// The curve of a velocity step V_1 -> V_2 (m/s) at `normal_force` (N): (slip (m), mu)
/// from `before` (m) of slip at V_1 up to the step (slip < 0) to `after` (m) beyond it,
/// every `slip_step` (m); `law` is reset and settled over `settle_slip` (m) first.
pub fn velocity_step_curve(
    law: &mut dyn StatefulLaw,
    (v1, v2): (f64, f64),
    normal_force: f64,
    settle_slip: f64,
    (before, after, slip_step): (f64, f64, f64),
) -> Vec<(f64, f64)> {
    let at = |dt: f64, v: f64| LawStep {
        dt,
        sliding_velocity: v,
        normal_force,
    };
    law.reset();
    law.commit(at(settle_slip / v1, v1));
    let mut curve = Vec::new();
    let mut slip = -before;
    let mut v = v1;
    while slip <= after {
        if slip >= 0.0 {
            v = v2;
        }
        curve.push((
            slip,
            law.step_force_and_slope(at(INSTANT, v)).0 / normal_force,
        ));
        law.commit(at(slip_step / v, v));
        slip += slip_step;
    }
    curve
}
