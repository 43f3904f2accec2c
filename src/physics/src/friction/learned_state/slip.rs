//! The slip law of rate-and-state friction (Ruina, J. Geophys. Res. 88 (1983) 10359),
//! d theta / dt = -(|v| theta / D_c) ln(|v| theta / D_c), advanced over one step exactly
//! for a sliding speed V = |v| held constant over the step, in the log state
//! psi = ln(theta V_0 / D_c).
//!
//! With x = ln(V theta / D_c) = psi + ln(V / V_0), the law reads dx/dt = -(V / D_c) x at
//! constant V: x decays exponentially over a slip of D_c, so one step of length h is
//!
//! ```text
//! x' = x e^{-s},   s = V h / D_c,   i.e.   psi' = psi - x (1 - e^{-s})
//! ```
//!
//! with the derivatives the slip solve and the trainer need:
//! d psi'/d psi = e^{-s}; d psi'/dV = -(1 - e^{-s}) / V - x e^{-s} h / D_c (from
//! dx/dV = 1/V and ds/dV = h/D_c); d psi'/d ln D_c = x s e^{-s} (at fixed psi, x does
//! not depend on D_c, and ds/d ln D_c = -s).
//!
//! At V = 0 there is no slip and the state does not change (the slip law does not heal
//! at rest); the step's slope there is 0, as in the analytical law
//! (`crate::friction::rate_and_state`): d psi'/dV grows only like ln V as V -> 0, while the
//! regularised force's dF/dpsi vanishes like V, so the total slope dF/dv_{n+1} is finite
//! for every v and continuous at 0.

use super::state_step::StateStep;

/// Advances psi over a step of `step` seconds ending at sliding velocity `velocity`
/// (m/s), with characteristic slip `slip` (D_c, m) and reference velocity
/// `reference_velocity` (V_0, m/s).
pub fn step(state: f64, velocity: f64, step: f64, slip: f64, reference_velocity: f64) -> StateStep {
    let speed = velocity.abs();
    if speed == 0.0 {
        return StateStep {
            state,
            d_state: 1.0,
            d_velocity: 0.0,
            d_log_slip: 0.0,
        };
    }
    let s = speed * step / slip;
    // ln(V / V_0) as a difference of logarithms where V / V_0 underflows (V = 5e-324
    // m/s with V_0 > 1e-2 m/s gave x = -inf and an infinite or NaN state).
    let x = state
        + crate::friction::rate_and_state::log_of_ratio(speed, reference_velocity, || {
            crate::elementary::ln(speed) - crate::elementary::ln(reference_velocity)
        });
    let decay = crate::elementary::exp(-s);
    // 1 - e^{-s} without cancellation for small s (a short step at low speed).
    let lost = -crate::elementary::exp_m1(-s);
    StateStep {
        state: state - x * lost,
        d_state: decay,
        d_velocity: crate::elementary::signum_or_zero(velocity)
            * (-lost / speed - x * decay * step / slip),
        d_log_slip: x * s * decay,
    }
}

#[cfg(test)]
mod tests {
    use super::super::evolution::steady_state;
    use super::super::state_step::checks::{derivatives_match_differences, steps_compose};
    use super::*;

    /// RK4 of the slip law in theta itself (not the closed form), n substeps.
    fn integrate(theta: f64, speed: f64, h: f64, d_c: f64, n: usize) -> f64 {
        let rate = |theta: f64| {
            let y = speed * theta / d_c;
            -y * crate::elementary::ln(y)
        };
        let dt = h / n as f64;
        let mut theta = theta;
        for _ in 0..n {
            let k1 = rate(theta);
            let k2 = rate(theta + 0.5 * dt * k1);
            let k3 = rate(theta + 0.5 * dt * k2);
            let k4 = rate(theta + dt * k3);
            theta += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        theta
    }

    /// The step against a fine explicit integration of the slip law at constant speed:
    /// RK4 with substeps of V dt / D_c <= 1e-3, whose error (~ (V dt / D_c)^4 per unit
    /// of slip, relative) is below 1e-12, so 1e-9 in psi leaves room for rounding over
    /// 10^4 substeps. Up- and down-steps, short and long steps (s = 0.02 to 20).
    #[test]
    fn the_step_is_the_slip_law_integrated_at_constant_speed() {
        let (d_c, v0) = (1e-5, 1e-3);
        for (psi0, v, h) in [
            (steady_state(1e-3, v0), 1e-2f64, 2e-5),
            (steady_state(1e-3, v0), -1e-2, 1e-3),
            (steady_state(1e-1, v0), 1e-2, 1e-2),
            (steady_state(1e-2, v0), 1e-3, 2e-3),
        ] {
            let s = v.abs() * h / d_c;
            let n = ((s / 1e-3).ceil() as usize).max(100);
            let theta0 = crate::elementary::exp(psi0) * d_c / v0;
            let theta = integrate(theta0, v.abs(), h, d_c, n);
            let want = crate::elementary::ln(theta * v0 / d_c);
            let got = step(psi0, v, h, d_c, v0).state;
            assert!((got - want).abs() < 1e-9, "v {v}, h {h}: {got} vs {want}");
        }
        let psi0 = steady_state(1e-3, v0);
        steps_compose(step, psi0, d_c, v0);
        // A long step reaches the steady state; at rest the state is frozen.
        let far = step(psi0, 0.02, 10.0, d_c, v0).state;
        assert!((far - steady_state(0.02, v0)).abs() < 1e-12);
        let rest = step(psi0, 0.0, 0.5, d_c, v0);
        assert_eq!(
            (rest.state, rest.d_state, rest.d_velocity),
            (psi0, 1.0, 0.0)
        );
    }

    /// The derivatives against central differences (relative steps 1e-6 in v, absolute
    /// 1e-6 in psi and ln D_c: truncation ~ 1e-12 psi''' and rounding ~ 1e-16 / 1e-6, so
    /// 1e-7 absolute / 1e-6 relative hold with margin), down to a speed of 1e-12 m/s.
    /// Below 1e-6 m/s psi' moves by less than 1e-12 over a relative step of 1e-6, which
    /// rounding (1e-15) would spoil, so the step is 1 % of v there: truncation
    /// (dv/V)^2 / (6 |1 + x|) ~ 2e-6 relative (x ~ -10), bound 1e-5. Finite at the
    /// smallest speeds.
    #[test]
    fn the_derivatives_match_differences_and_stay_finite_near_rest() {
        let (d_c, v0) = (2e-5, 1e-3);
        let psi0 = steady_state(3e-3, v0) + 0.7;
        for (v, h) in [
            (0.02f64, 1e-4),
            (-3e-3, 1e-3),
            (1e-7, 1e-5),
            (0.5, 1e-2),
            (1e-12, 1.0),
        ] {
            let accuracy = if v.abs() < 1e-6 {
                (1e-2, 1e-5)
            } else {
                (1e-6, 1e-6)
            };
            derivatives_match_differences(step, (psi0, v, h, d_c, v0), accuracy);
        }
        for v in [5e-324, -1e-300, 1e-200] {
            let s = step(psi0, v, 1e-3, d_c, v0);
            assert!(
                s.state.is_finite() && s.d_velocity.is_finite(),
                "v {v}: {s:?}"
            );
        }
    }
}
