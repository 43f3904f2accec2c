//! The paper's exponential law (Vater, Stender & Hoffmann 2023, Eq. 6): the friction
//! coefficient falls from mu_s at rest to mu_k at high speed with decay alpha (s/m).

use super::kind::FrictionLawKind;
use super::law::FrictionLaw;
use super::registry::{Coefficients, LawBuild, LawDescription};
use crate::choice::Choice;
use crate::elementary::{self, signum_or_zero};
use crate::jacobian::{magnitude_slope, LawJacobian};
use std::sync::Arc;

/// The exponential law in the registry: the friction coefficients are its parameters;
/// NeuralFriction evaluates it as `law = exponential`.
pub static LAW: LawDescription = LawDescription {
    neural_friction_code: Some(2),
    ..LawDescription::plain(
        FrictionLawKind::Exponential,
        LawBuild::Analytical(|coefficients, _| Arc::new(ExponentialLaw::from(*coefficients))),
    )
};

/// The paper's exponential law (Eq. 6):
/// F(v) = sign(v) [mu_k + (mu_s - mu_k) exp(-alpha |v|)] F_n.
#[derive(Clone, Debug, PartialEq)]
pub struct ExponentialLaw {
    /// mu_s (1), the limit at v -> 0.
    pub static_coefficient: f64,
    /// mu_k (1), the limit at |v| -> infinity.
    pub kinetic_coefficient: f64,
    /// alpha (s/m).
    pub decay: f64,
}

impl From<Coefficients> for ExponentialLaw {
    fn from(c: Coefficients) -> Self {
        Self {
            static_coefficient: c.static_coefficient,
            kinetic_coefficient: c.kinetic_coefficient,
            decay: c.decay,
        }
    }
}

impl ExponentialLaw {
    /// Friction coefficient mu(|v|) (1).
    pub fn coefficient(&self, speed: f64) -> f64 {
        self.kinetic_coefficient
            + (self.static_coefficient - self.kinetic_coefficient)
                * elementary::exp(-self.decay * speed.abs())
    }

    /// mu(|v|) (1) and its slope d mu / d|v| = -alpha (mu_s - mu_k) exp(-alpha |v|)
    /// (s/m), sharing the one `exp`; the coefficient is the same number as
    /// [`ExponentialLaw::coefficient`]'s.
    pub fn coefficient_and_slope(&self, speed: f64) -> (f64, f64) {
        let drop = (self.static_coefficient - self.kinetic_coefficient)
            * elementary::exp(-self.decay * speed.abs());
        (self.kinetic_coefficient + drop, -self.decay * drop)
    }

    /// dF/dv (N s/m) of the law at sliding velocity `sliding_velocity` (m/s) under
    /// `normal_force` (N): F = sign(v) mu(|v|) F_n is odd, so
    /// dF/dv = mu'(|v|) F_n = -alpha (mu_s - mu_k) exp(-alpha |v|) F_n on either side of
    /// v = 0. The jump of 2 mu_s F_n at v = 0 itself has no slope; there this is the
    /// one-sided limit.
    pub fn slope(&self, sliding_velocity: f64, normal_force: f64) -> f64 {
        -self.decay
            * (self.static_coefficient - self.kinetic_coefficient)
            * elementary::exp(-self.decay * sliding_velocity.abs())
            * normal_force
    }
}

impl ExponentialLaw {
    /// The Jacobian over (v, F_n) of F = sign(v) mu(|v|) F_n with
    /// mu(|v|) = mu_k + (mu_s - mu_k) exp(-alpha |v|) (the paper's Eq. 6):
    /// - dF/dv = mu'(|v|) F_n = S, dF/dF_n = sign(v) mu(|v|);
    /// - dS/dv = mu''(|v|) sign(v) F_n with mu'' = alpha^2 (mu_s - mu_k) exp(-alpha |v|),
    ///   dS/dF_n = mu'(|v|).
    ///
    /// The force is the number `FrictionLaw::sliding_force` gives, the slope the one
    /// [`ExponentialLaw::slope`] gives (to an ulp the slope of
    /// `FrictionLaw::sliding_force_and_slope`): the numbers NeuralFriction has always
    /// output for this law.
    pub fn jacobian(&self, sliding_velocity: f64, normal_force: f64) -> LawJacobian {
        let (mu, mu_slope) = self.coefficient_and_slope(sliding_velocity);
        let mu_curvature = -self.decay * mu_slope;
        let sign = signum_or_zero(sliding_velocity);
        LawJacobian {
            force: sign * mu * normal_force,
            slope: self.slope(sliding_velocity, normal_force),
            force_gradient: vec![mu_slope * normal_force, sign * mu],
            slope_gradient: vec![
                mu_curvature * magnitude_slope(sliding_velocity) * normal_force,
                mu_slope,
            ],
        }
    }
}

impl FrictionLaw for ExponentialLaw {
    fn name(&self) -> &str {
        FrictionLawKind::Exponential.name()
    }

    fn jacobian(&mut self, sliding_velocity: f64, normal_force: f64) -> Option<LawJacobian> {
        Some(ExponentialLaw::jacobian(
            self,
            sliding_velocity,
            normal_force,
        ))
    }

    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64 {
        signum_or_zero(sliding_velocity) * self.coefficient(sliding_velocity) * normal_force
    }

    /// dF/dv = d mu / d|v| F_n on either side of v = 0: F = sign(v) mu(|v|) F_n is odd,
    /// so its slope is even.
    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64) {
        let (mu, slope) = self.coefficient_and_slope(sliding_velocity);
        (
            signum_or_zero(sliding_velocity) * mu * normal_force,
            slope * normal_force,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exponential_law_limits_and_sign() {
        let mut law = ExponentialLaw {
            static_coefficient: 0.5,
            kinetic_coefficient: 0.2,
            decay: 5.0,
        };
        // v -> 0+: mu_s F_n; large v: mu_k F_n; odd in v.
        assert!((law.sliding_force(1e-12, 100.0) - 50.0).abs() < 1e-9);
        assert!((law.sliding_force(100.0, 100.0) - 20.0).abs() < 1e-9);
        assert_eq!(
            law.sliding_force(-0.1, 100.0),
            -law.sliding_force(0.1, 100.0)
        );
        // Eq. 6 at v = 0.2 m/s: 0.2 + 0.3 e^-1.
        let expected = (0.2 + 0.3 * elementary::exp(-1.0)) * 100.0;
        assert!((law.sliding_force(0.2, 100.0) - expected).abs() < 1e-12);
        assert_eq!(law.sliding_force(0.0, 100.0), 0.0);
    }

    /// The exact slope against a central difference, (F(v + h) - F(v - h)) / 2h, whose
    /// error is F^(3) h^2 / 6 + eps |F| / h ~ 1e-8 N s/m at h = 1e-6 m/s (F^(3) =
    /// alpha^3 (mu_s - mu_k) F_n), on either side of v = 0 (not across it: the jump).
    #[test]
    fn exponential_slope_is_the_derivative_of_the_force() {
        let mut law = ExponentialLaw {
            static_coefficient: 0.5,
            kinetic_coefficient: 0.2,
            decay: 5.0,
        };
        let h = 1e-6;
        for v in [-0.3, -0.05, -1e-4, 1e-4, 0.01, 0.2, 3.0] {
            for f_n in [90.0, 100.0] {
                let (force, slope) = law.sliding_force_and_slope(v, f_n);
                assert_eq!(force.to_bits(), law.sliding_force(v, f_n).to_bits());
                let difference =
                    (law.sliding_force(v + h, f_n) - law.sliding_force(v - h, f_n)) / (2.0 * h);
                assert!(
                    (slope - difference).abs() < 1e-6,
                    "v {v}: {slope} vs {difference}"
                );
            }
        }
        // At v = 0: force 0, and the slope of the magnitude, -alpha (mu_s - mu_k) F_n.
        assert_eq!(law.sliding_force_and_slope(0.0, 100.0), (0.0, -150.0));
    }

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
            assert_eq!(j.force, force);
            assert_eq!(j.force, law.clone().sliding_force(v, n));
            assert_eq!(j.slope, law.slope(v, n));
            // The two slopes associate the same product differently: an ulp apart.
            assert!((j.slope - slope).abs() <= 2.0 * f64::EPSILON * slope.abs());
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
