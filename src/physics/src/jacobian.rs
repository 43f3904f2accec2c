//! The input Jacobian of a kinetic friction law: the force F and its velocity slope
//! S = dF/dv at one point, with their first derivatives with respect to every input.
//! Co-simulation masters and training tools that wrap a friction FMU (FMIFlux) ask for
//! these instead of finite differences; S is itself a derivative, so its gradient holds
//! the law's second derivatives d2F/dv dx_k.
//!
//! The neural network's Jacobian is in `neural::jacobian`; the exponential law's closed
//! form is here.
//!
//! # Conventions at the kinks
//! Both laws are F = sign(v) g(|v|, ...), with a jump at v = 0. The derivatives there are
//! those of the branch v > 0 (the one-sided limits, as `FrictionLaw::sliding_force_and_slope`
//! gives the slope): dF/dv = g'(0+) and dS/dv = g''(0+), while the derivatives with respect
//! to the other inputs are 0, since F(0, ...) = 0 for every value of them.

use crate::friction::{exponential::ExponentialLaw, signum_or_zero};

/// A law's force and slope at one point, and their gradients over the law's inputs (in the
/// law's input order: for the exponential law (v, F_n), for a network its features).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LawJacobian {
    /// F (N).
    pub force: f64,
    /// S = dF/dv (N s/m), the slope the law reports (0 where v is clamped).
    pub slope: f64,
    /// dF/dx_k, one per input (N per unit of input k).
    pub force_gradient: Vec<f64>,
    /// dS/dx_k = d2F/dv dx_k, one per input.
    pub slope_gradient: Vec<f64>,
}

/// d|v|/dv with the branch v > 0 at v = 0 (see the module notes).
pub fn magnitude_slope(sliding_velocity: f64) -> f64 {
    if sliding_velocity < 0.0 {
        -1.0
    } else {
        1.0
    }
}

impl ExponentialLaw {
    /// The Jacobian over (v, F_n) of F = sign(v) mu(|v|) F_n with
    /// mu(|v|) = mu_k + (mu_s - mu_k) exp(-alpha |v|) (the paper's Eq. 6):
    /// - dF/dv = mu'(|v|) F_n = S, dF/dF_n = sign(v) mu(|v|);
    /// - dS/dv = mu''(|v|) sign(v) F_n with mu'' = alpha^2 (mu_s - mu_k) exp(-alpha |v|),
    ///   dS/dF_n = mu'(|v|).
    ///
    /// Force and slope are the numbers `FrictionLaw::sliding_force_and_slope` gives.
    pub fn jacobian(&self, sliding_velocity: f64, normal_force: f64) -> LawJacobian {
        let (mu, mu_slope) = self.coefficient_and_slope(sliding_velocity);
        let mu_curvature = -self.decay * mu_slope;
        let sign = signum_or_zero(sliding_velocity);
        LawJacobian {
            force: sign * mu * normal_force,
            slope: mu_slope * normal_force,
            force_gradient: vec![mu_slope * normal_force, sign * mu],
            slope_gradient: vec![
                mu_curvature * magnitude_slope(sliding_velocity) * normal_force,
                mu_slope,
            ],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::friction::FrictionLaw;

    /// Central differences of the closed form. Step h = 1e-5 (m/s, N): truncation
    /// h^2/6 |f'''| <= 1e-10 * 7^3 * 50 / 6 < 3e-7 for the paper's alpha = 7 s/m and forces
    /// of 50 N (per m/s), rounding 2 eps |f| / (2 h) < 2e-9; 1e-6 relative to the
    /// derivative's scale (mu_s F_n alpha ~ 350) covers both with room.
    #[test]
    fn exponential_law_matches_central_differences() {
        let law = ExponentialLaw {
            static_coefficient: 0.5,
            kinetic_coefficient: 0.3,
            decay: 7.0,
        };
        let h = 1e-5;
        let f = |v: f64, n: f64| law.clone().sliding_force_and_slope(v, n);
        for &(v, n) in &[(0.01, 100.0), (-0.2, 95.0), (0.35, 110.0), (-0.003, 0.5)] {
            let j = law.jacobian(v, n);
            let (force, slope) = f(v, n);
            assert_eq!((j.force, j.slope), (force, slope));
            let dv = |k: usize| {
                let (a, b) = (f(v + h, n), f(v - h, n));
                [a.0 - b.0, a.1 - b.1][k] / (2.0 * h)
            };
            let dn = |k: usize| {
                let (a, b) = (f(v, n + h), f(v, n - h));
                [a.0 - b.0, a.1 - b.1][k] / (2.0 * h)
            };
            let tolerance = 1e-6 * 350.0;
            for (exact, numeric) in [
                (j.force_gradient[0], dv(0)),
                (j.force_gradient[1], dn(0)),
                (j.slope_gradient[0], dv(1)),
                (j.slope_gradient[1], dn(1)),
            ] {
                assert!(
                    (exact - numeric).abs() < tolerance,
                    "v {v}, F_n {n}: {exact} vs {numeric}"
                );
            }
        }
    }

    /// At v = 0 the force is 0 for every F_n, and the v-derivatives are those of v > 0.
    #[test]
    fn at_zero_velocity_the_branch_v_positive_holds() {
        let law = ExponentialLaw {
            static_coefficient: 0.5,
            kinetic_coefficient: 0.3,
            decay: 7.0,
        };
        let zero = law.jacobian(0.0, 100.0);
        let right = law.jacobian(1e-300, 100.0);
        assert_eq!(zero.force_gradient[1], 0.0);
        assert_eq!(zero.force_gradient[0], right.force_gradient[0]);
        assert_eq!(zero.slope_gradient, right.slope_gradient);
    }
}
