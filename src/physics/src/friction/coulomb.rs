//! Plain Coulomb friction: a coefficient mu_k independent of speed.

use super::kind::FrictionLawKind;
use super::law::FrictionLaw;
use super::registry::{LawBuild, LawDescription};
use crate::choice::Choice;
use crate::elementary::signum_or_zero;
use std::sync::Arc;

/// Coulomb in the registry: mu_k is its one parameter.
pub static LAW: LawDescription = LawDescription::plain(
    FrictionLawKind::Coulomb,
    LawBuild::Analytical(|coefficients, _| {
        Arc::new(CoulombLaw {
            kinetic_coefficient: coefficients.kinetic_coefficient,
        })
    }),
);

/// Plain Coulomb friction: F(v) = sign(v) mu_k F_n.
#[derive(Clone, Debug, PartialEq)]
pub struct CoulombLaw {
    /// mu_k (1).
    pub kinetic_coefficient: f64,
}

impl FrictionLaw for CoulombLaw {
    fn name(&self) -> &str {
        FrictionLawKind::Coulomb.name()
    }

    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64 {
        signum_or_zero(sliding_velocity) * self.kinetic_coefficient * normal_force
    }

    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64) {
        (self.sliding_force(sliding_velocity, normal_force), 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coulomb_law_is_constant_in_speed() {
        let mut law = CoulombLaw {
            kinetic_coefficient: 0.2,
        };
        assert_eq!(law.sliding_force(0.001, 100.0), 20.0);
        assert_eq!(law.sliding_force(-7.0, 100.0), -20.0);
        // No slope: the force is constant on either side of v = 0.
        assert_eq!(law.sliding_force_and_slope(-0.1, 100.0), (-20.0, 0.0));
    }
}
