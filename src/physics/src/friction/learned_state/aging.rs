//! The aging law of rate-and-state friction (Dieterich 1979; Ruina 1983),
//! d theta / dt = 1 - |v| theta / D_c, advanced over one step exactly for a sliding
//! speed |v| held constant over the step, in the log state psi = ln(theta V_0 / D_c).
//!
//! Under constant V the aging law is linear in theta, so one step of length h is
//! (the closed form theta(t) = D_c/V + (theta_0 - D_c/V) exp(-V t / D_c)):
//!
//! ```text
//! theta' = theta e^{-x} + h phi(x),   x = V h / D_c,   phi(x) = (1 - e^{-x}) / x
//! ```
//!
//! and in the log state, u = e^{psi'} = e^{psi - x} + K phi(x) with K = V_0 h / D_c.
//! The update reads the velocity at the end of the step, v_{n+1}, as backward Euler
//! does (it is implicit in v, so the slip solve differentiates it), but it has no
//! time-step error for piecewise-constant speed and is unconditionally stable: for
//! V h / D_c = 0.1 backward Euler's decay rate is already 5 % slow (ln(1 + x) / x),
//! which a trained D_c would absorb. No Newton iteration is needed: the update is
//! explicit in psi_n given v_{n+1}. Why the state is psi rather than theta: theta
//! spans decades (it grows like the time at rest), psi is O(1) at steady sliding
//! (psi_ss = ln(V_0 / V)) and does not depend on D_c there.

use super::state_step::StateStep;

/// phi(x) = (1 - e^{-x}) / x and phi'(x) = (e^{-x} (1 + x) - 1) / x^2 for x >= 0;
/// below x = 1e-2 their Taylor series (phi' = -1/2 + x/3 - x^2/8 + x^3/30, error
/// x^4 / 144 < 1e-10), where the closed form of phi' cancels.
fn phi_and_slope(x: f64) -> (f64, f64) {
    if x < 1e-2 {
        let phi = 1.0 - x / 2.0 + x * x / 6.0 - x * x * x / 24.0;
        let slope = -0.5 + x / 3.0 - x * x / 8.0 + x * x * x / 30.0;
        (phi, slope)
    } else {
        let decay = crate::elementary::exp(-x);
        ((1.0 - decay) / x, (decay * (1.0 + x) - 1.0) / (x * x))
    }
}

/// Advances psi over a step of `step` seconds ending at sliding velocity `velocity`
/// (m/s), with characteristic slip `slip` (D_c, m) and reference velocity
/// `reference_velocity` (V_0, m/s). At v = 0 the contact ages: theta' = theta + h.
pub fn step(state: f64, velocity: f64, step: f64, slip: f64, reference_velocity: f64) -> StateStep {
    let speed = velocity.abs();
    let x = speed * step / slip;
    let k = reference_velocity * step / slip;
    let (phi, phi_slope) = phi_and_slope(x);
    // u = e^{psi - x} + K phi(x), computed relative to the larger term's exponent so
    // that a long stick (psi large) neither overflows nor loses the other term.
    let kept = state - x;
    let gained = crate::elementary::ln(k) + crate::elementary::ln(phi);
    let top = kept.max(gained);
    let (kept_share, gained_share) = (
        crate::elementary::exp(kept - top),
        crate::elementary::exp(gained - top),
    );
    let scale = kept_share + gained_share;
    let new_state = top + crate::elementary::ln(scale);
    // Shares of u: w_kept = e^{psi - x} / u, w_gained = K phi / u.
    let (w_kept, w_gained) = (kept_share / scale, gained_share / scale);
    // du/dx / u = -w_kept + w_gained phi'/phi.
    let du_dx = -w_kept + w_gained * phi_slope / phi;
    let dx_dv = crate::elementary::signum_or_zero(velocity) * step / slip;
    StateStep {
        state: new_state,
        d_state: w_kept,
        d_velocity: du_dx * dx_dv,
        // x and K both scale with 1 / D_c: d/d ln D_c = -x d/dx - K d/dK.
        d_log_slip: -x * du_dx - w_gained,
    }
}

#[cfg(test)]
mod tests {
    use super::super::evolution::steady_state;
    use super::super::state_step::checks::{derivatives_match_differences, steps_compose};
    use super::*;

    /// The step is the closed form theta(t) = D_c/V + (theta_0 - D_c/V) e^{-V t/D_c}:
    /// ten steps of h equal one of 10 h to rounding (1e-12 in psi), and the derivatives
    /// match central differences (error ~ h^2 psi''' + eps/h ~ 1e-8).
    #[test]
    fn steps_compose_to_the_closed_form_and_derivatives_are_exact() {
        let (d_c, v0) = (2e-5, 1e-6);
        let psi0 = steady_state(1e-3, v0);
        let whole = steps_compose(step, psi0, d_c, v0);
        let theta = |t: f64, v: f64| {
            d_c / v + (d_c / 1e-3 - d_c / v) * crate::elementary::exp(-v * t / d_c)
        };
        let closed = crate::elementary::ln(theta(1e-3, 0.02) * v0 / d_c);
        assert!((whole - closed).abs() < 1e-12, "{whole} vs {closed}");
        // Long steps converge to the steady state; v = 0 ages theta by h.
        let far = step(psi0, 0.02, 10.0, d_c, v0).state;
        assert!((far - steady_state(0.02, v0)).abs() < 1e-12);
        let aged = step(psi0, 0.0, 0.5, d_c, v0).state;
        assert!(((crate::elementary::exp(aged) * d_c / v0) - (d_c / 1e-3 + 0.5)).abs() < 1e-12);
        for (v, h) in [(0.02f64, 1e-4), (-3e-3, 1e-3), (1e-7, 1e-5), (0.5, 1e-2)] {
            // Relative steps; 10 % at the smallest speed, where psi is linear in v to
            // O(x) = 5e-8 and a smaller step would drown in rounding.
            let relative = if v.abs() < 1e-5 { 0.1 } else { 1e-6 };
            derivatives_match_differences(step, (psi0, v, h, d_c, v0), (relative, 1e-6));
        }
    }
}
