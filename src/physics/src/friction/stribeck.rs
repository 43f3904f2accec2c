//! Stribeck friction with viscous friction (the Gaussian Stribeck curve of
//! Armstrong-Helouvry, Dupont & Canudas de Wit, Automatica 30 (1994) 1083; Olsson et al.,
//! Eur. J. Control 4 (1998) 176, Eq. 4):
//!
//!   F(v) = sign(v) [mu_k + (mu_s - mu_k) exp(-(v / v_s)^2)] F_n + sigma_v v,
//!
//! with the friction section's coefficients mu_s and mu_k (1), the Stribeck velocity v_s
//! (m/s) and the viscous coefficient sigma_v (N s/m). Unlike the paper's exponential law
//! (Eq. 6), whose slope at rest is -alpha (mu_s - mu_k) F_n, the Gaussian curve leaves
//! rest flat (dF/dv -> sigma_v as v -> 0) and falls fastest at |v| = v_s / sqrt(2); the
//! viscous term makes the force grow again at high speed.
//!
//! This law is also the example of how a law is added (docs/friction-laws.md): this file
//! and its two lines in `super` (the module and the `FrictionLawKind` variant with its
//! registry line) are all the code it needs.

use super::kind::FrictionLawKind;
use super::law::FrictionLaw;
use super::registry::{
    Coefficients, LawBuild, LawDescription, LawParameter, LawTables, ParameterKind, Range,
};
use crate::choice::Choice;
use crate::elementary::{self, signum_or_zero};
use crate::jacobian::{magnitude_slope, LawJacobian};
use std::sync::Arc;

/// v_s (m/s): where the Gaussian has fallen to 1/e of the way from mu_s to mu_k. The
/// default 0.1 m/s is five belt speeds of the paper scene (0.02 m/s), so that the tip
/// slips on the falling part of the curve.
pub const STRIBECK_VELOCITY: LawParameter = LawParameter {
    name: "friction.stribeck.stribeck_velocity",
    description: "Stribeck velocity v_s",
    kind: ParameterKind::Real {
        unit: Some("m/s"),
        range: Range::Positive,
    },
    default: 0.1,
    value_reference: 90,
    initial_force: true,
    initial_state: false,
};

/// sigma_v (N s/m): viscous friction, 0 by default (the paper's law has none).
pub const VISCOUS_COEFFICIENT: LawParameter = LawParameter {
    name: "friction.stribeck.viscous_coefficient",
    description: "Stribeck law viscous coefficient sigma_v",
    kind: ParameterKind::Real {
        unit: Some("N.s/m"),
        range: Range::NonNegative,
    },
    default: 0.0,
    value_reference: 91,
    initial_force: true,
    initial_state: false,
};

/// The Stribeck law in the registry: built from the coefficients and
/// `[friction.stribeck]`; NeuralFriction evaluates it as `law = stribeck`.
pub static LAW: LawDescription = LawDescription {
    parameters: &[STRIBECK_VELOCITY, VISCOUS_COEFFICIENT],
    neural_friction_code: Some(5),
    ..LawDescription::plain(
        FrictionLawKind::Stribeck,
        LawBuild::Analytical(|coefficients, values| {
            Arc::new(StribeckLaw::new(coefficients, values))
        }),
    )
};

/// F(v) = sign(v) [mu_k + (mu_s - mu_k) exp(-(v / v_s)^2)] F_n + sigma_v v.
#[derive(Clone, Debug, PartialEq)]
pub struct StribeckLaw {
    /// mu_s (1), the limit at v -> 0.
    pub static_coefficient: f64,
    /// mu_k (1), the Coulomb level at high speed.
    pub kinetic_coefficient: f64,
    /// v_s (m/s), > 0.
    pub stribeck_velocity: f64,
    /// sigma_v (N s/m), >= 0.
    pub viscous_coefficient: f64,
}

impl StribeckLaw {
    /// The law of the friction section's coefficients (mu_s, mu_k) and this law's values
    /// in the order of [`LAW`]'s parameters.
    pub fn new(coefficients: &Coefficients, values: &[f64]) -> Self {
        Self {
            static_coefficient: coefficients.static_coefficient,
            kinetic_coefficient: coefficients.kinetic_coefficient,
            stribeck_velocity: values[0],
            viscous_coefficient: values[1],
        }
    }

    /// The law of a checked friction section's coefficients and tables.
    pub fn of(coefficients: &Coefficients, tables: &LawTables) -> Self {
        Self::new(coefficients, tables.values(FrictionLawKind::Stribeck))
    }

    /// mu(|v|) (1) and its first two derivatives in |v|: with u = |v| / v_s and
    /// D = (mu_s - mu_k) exp(-u^2), mu = mu_k + D, mu' = -2 u D / v_s,
    /// mu'' = (4 u^2 - 2) D / v_s^2.
    fn coefficient(&self, speed: f64) -> (f64, f64, f64) {
        let u = speed.abs() / self.stribeck_velocity;
        let drop = (self.static_coefficient - self.kinetic_coefficient) * elementary::exp(-u * u);
        let scale = self.stribeck_velocity;
        (
            self.kinetic_coefficient + drop,
            -2.0 * u * drop / scale,
            (4.0 * u * u - 2.0) * drop / (scale * scale),
        )
    }
}

impl FrictionLaw for StribeckLaw {
    fn name(&self) -> &str {
        FrictionLawKind::Stribeck.name()
    }

    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64 {
        self.sliding_force_and_slope(sliding_velocity, normal_force)
            .0
    }

    /// dF/dv = mu'(|v|) F_n + sigma_v on either side of v = 0.
    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64) {
        let (mu, mu_slope, _) = self.coefficient(sliding_velocity);
        (
            signum_or_zero(sliding_velocity) * mu * normal_force
                + self.viscous_coefficient * sliding_velocity,
            mu_slope * normal_force + self.viscous_coefficient,
        )
    }

    /// Over (v, F_n): dF/dv = S = mu' F_n + sigma_v, dF/dF_n = sign(v) mu;
    /// dS/dv = mu'' sign(v) F_n, dS/dF_n = mu' (at v = 0 the branch v > 0).
    fn jacobian(&mut self, sliding_velocity: f64, normal_force: f64) -> Option<LawJacobian> {
        let (mu, mu_slope, mu_curvature) = self.coefficient(sliding_velocity);
        let (force, slope) = self.sliding_force_and_slope(sliding_velocity, normal_force);
        Some(LawJacobian {
            force,
            slope,
            force_gradient: vec![slope, signum_or_zero(sliding_velocity) * mu],
            slope_gradient: vec![
                mu_curvature * magnitude_slope(sliding_velocity) * normal_force,
                mu_slope,
            ],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn law() -> StribeckLaw {
        StribeckLaw {
            static_coefficient: 0.5,
            kinetic_coefficient: 0.2,
            stribeck_velocity: 0.1,
            viscous_coefficient: 40.0,
        }
    }

    /// The limits of the curve: mu_s F_n at rest, mu_k F_n + sigma_v v far from it, 1/e
    /// of the drop at v_s; odd in v.
    #[test]
    fn the_curve_has_its_limits_and_is_odd() {
        let mut law = law();
        assert!((law.sliding_force(1e-12, 100.0) - 50.0).abs() < 1e-9);
        assert!((law.sliding_force(10.0, 100.0) - (20.0 + 400.0)).abs() < 1e-9);
        let at_vs = (0.2 + 0.3 * elementary::exp(-1.0)) * 100.0 + 40.0 * 0.1;
        assert!((law.sliding_force(0.1, 100.0) - at_vs).abs() < 1e-12);
        assert_eq!(
            law.sliding_force(-0.05, 100.0),
            -law.sliding_force(0.05, 100.0)
        );
        assert_eq!(law.sliding_force(0.0, 100.0), 0.0);
        // Flat at rest: only the viscous slope is left.
        assert_eq!(law.sliding_force_and_slope(0.0, 100.0).1, 40.0);
    }

    /// The Jacobian against central differences. h = 1e-6 (m/s, N): the truncation
    /// h^2 / 6 |d^3 g| of a difference of g = F or S is below 1e-12 / 6 * 4e6 ~ 1e-6 (the
    /// fourth derivative of the Gaussian part is at most ~12 (mu_s - mu_k) F_n / v_s^4 =
    /// 4e6 N s^3/m^3 here), the rounding eps |g| / h below 1e-7; 1e-5 (1 + |exact|)
    /// covers both.
    #[test]
    fn the_jacobian_is_the_derivative_of_the_force() {
        let law = law();
        let h = 1e-6;
        let f = |v: f64, n: f64| law.clone().sliding_force_and_slope(v, n);
        for &(v, n) in &[(0.01, 100.0), (-0.07, 95.0), (0.25, 110.0), (-0.003, 0.5)] {
            let j = law.clone().jacobian(v, n).unwrap();
            assert_eq!((j.force, j.slope), f(v, n));
            let dv = |k: usize| {
                let (a, b) = (f(v + h, n), f(v - h, n));
                [a.0 - b.0, a.1 - b.1][k] / (2.0 * h)
            };
            let dn = |k: usize| {
                let (a, b) = (f(v, n + h), f(v, n - h));
                [a.0 - b.0, a.1 - b.1][k] / (2.0 * h)
            };
            for (exact, numeric) in [
                (j.force_gradient[0], dv(0)),
                (j.force_gradient[1], dn(0)),
                (j.slope_gradient[0], dv(1)),
                (j.slope_gradient[1], dn(1)),
            ] {
                let tolerance = 1e-5 * (1.0 + exact.abs());
                assert!(
                    (exact - numeric).abs() < tolerance,
                    "v {v}, F_n {n}: {exact} vs {numeric}"
                );
            }
        }
    }

    /// The steepest fall of the curve is at |v| = v_s / sqrt(2), where mu'' = 0.
    #[test]
    fn the_curve_falls_fastest_at_vs_over_root_two() {
        let law = law();
        let v = 0.1 / 2f64.sqrt();
        let (_, slope, curvature) = law.coefficient(v);
        assert!(curvature.abs() < 1e-12 * slope.abs() / v);
        assert!(law.coefficient(0.9 * v).1 > slope && law.coefficient(1.1 * v).1 > slope);
    }
}
