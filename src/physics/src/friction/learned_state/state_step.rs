//! One step of the learned law's state, as both evolutions (`aging`, `slip`) give it:
//! the new state and its derivatives, which the contact's slip solve and the trainer's
//! sensitivities need.

/// One step of the state psi and its derivatives (dimensionless psi; v in m/s; D_c in m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateStep {
    /// psi_{n+1} (1).
    pub state: f64,
    /// d psi_{n+1} / d psi_n (1), in (0, 1].
    pub d_state: f64,
    /// d psi_{n+1} / d v_{n+1} (s/m), odd in v (the step reads |v|); finite for every
    /// finite v (0 at v = 0 for the slip law, see `slip`).
    pub d_velocity: f64,
    /// d psi_{n+1} / d ln D_c (1) at fixed psi_n.
    pub d_log_slip: f64,
}

/// Checks shared by the steps' tests.
#[cfg(test)]
pub(super) mod checks {
    use crate::friction::learned_state::state_step::StateStep;

    /// A step's signature: (psi_n, v_{n+1}, h, D_c, V_0) -> the step.
    pub type Step = fn(f64, f64, f64, f64, f64) -> StateStep;

    /// Exact steps compose: ten steps of 0.1 ms at 0.02 m/s from `psi0` are one of
    /// 1 ms, to rounding (1e-12 in psi); returns the one step's state.
    pub fn steps_compose(step: Step, psi0: f64, d_c: f64, v0: f64) -> f64 {
        let mut psi = psi0;
        for _ in 0..10 {
            psi = step(psi, 0.02, 1e-4, d_c, v0).state;
        }
        let whole = step(psi0, 0.02, 1e-3, d_c, v0).state;
        assert!((psi - whole).abs() < 1e-12, "{psi} vs {whole}");
        whole
    }

    /// The step's derivatives against central differences at (psi0, v, h, D_c, V_0):
    /// in v with a step of `relative` |v| and the bound `bound` relative to
    /// max(|difference|, 1) (the caller says why); in psi and ln D_c with steps of 1e-6
    /// and the bound 1e-7 (truncation ~ 1e-12 psi''', rounding ~ 1e-16 / 1e-6).
    pub fn derivatives_match_differences(
        step: Step,
        (psi0, v, h, d_c, v0): (f64, f64, f64, f64, f64),
        (relative, bound): (f64, f64),
    ) {
        let s = step(psi0, v, h, d_c, v0);
        let dv = relative * v.abs();
        let fd_v = (step(psi0, v + dv, h, d_c, v0).state - step(psi0, v - dv, h, d_c, v0).state)
            / (2.0 * dv);
        assert!(
            (s.d_velocity - fd_v).abs() < bound * fd_v.abs().max(1.0),
            "v {v}: {} {fd_v}",
            s.d_velocity
        );
        let e: f64 = 1e-6;
        let fd_c = (step(psi0, v, h, d_c * crate::elementary::exp(e), v0).state
            - step(psi0, v, h, d_c * crate::elementary::exp(-e), v0).state)
            / (2.0 * e);
        assert!(
            (s.d_log_slip - fd_c).abs() < 1e-7,
            "v {v}: {} {fd_c}",
            s.d_log_slip
        );
        let fd_s =
            (step(psi0 + e, v, h, d_c, v0).state - step(psi0 - e, v, h, d_c, v0).state) / (2.0 * e);
        assert!((s.d_state - fd_s).abs() < 1e-7, "v {v}");
    }
}
