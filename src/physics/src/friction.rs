//! Kinetic friction laws acting on the beam tip during slip.
//!
//! Every law maps a signed sliding velocity v (m/s) and a normal force F_n (N) to the
//! signed friction force (N) that acts in the direction of v. The contact passes the
//! belt-relative velocity v = v_b - v_tip, so the force drags the tip toward the belt.
//! The static limit mu_s F_n is not part of a law: it belongs to the contact. Which law
//! a run uses is `crate::law_source::LawSource`.

use crate::choice::Choice;
use crate::elementary;
use crate::memory::MemoryLaw;
use crate::scene::{Friction, FrictionLawKind};

crate::choice! {
    /// The law of a friction model evaluated on its own (the NeuralFriction FMU): the
    /// network, the paper's analytical law to compare it with, or a law with state.
    #[choice(name = "FrictionLaw", description = "Which law gives the friction force")]
    pub enum LawChoice {
        /// A trained network (see `neural`).
        Neural = "neural": "the network in weights",
        /// The paper's exponential law (Eq. 6), [`ExponentialLaw`].
        Exponential = "exponential": "mu(v) = mu_k + (mu_s - mu_k) exp(-alpha |v|) (paper, Eq. 6)",
        /// LuGre with the exponential law as g(v) ([`crate::memory::lugre`]).
        Lugre = "lugre": "LuGre bristle law, g(v) the exponential law (Canudas de Wit et al. 1995)",
        /// Rate-and-state friction ([`crate::memory::rate_state`]).
        RateAndState = "rate-and-state": "regularised Dieterich-Ruina rate-and-state law",
    }
}

/// A kinetic friction law F(v, F_n).
///
/// `&mut self` lets a law keep scratch buffers (the neural law evaluates without
/// allocating); a law carries no history, so the same inputs give the same force.
pub trait FrictionLaw: Send {
    /// Short name for summaries ("exponential", "coulomb", "neural").
    fn name(&self) -> &str;

    /// Signed kinetic friction force (N) in the direction of `sliding_velocity` (m/s),
    /// under `normal_force` (N).
    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64;

    /// The force of [`FrictionLaw::sliding_force`] (N, the same number) and its exact
    /// slope dF/dv (N s/m) at `sliding_velocity`, computed in the same pass: the slip
    /// solve's Newton iteration (`contact`) needs both at every iterate.
    ///
    /// A law that jumps at v = 0 (sign(v) times a magnitude) gives there its force 0 and
    /// the slope of its magnitude; the contact handles the jump itself.
    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64);

    /// The force difference (N) below which this law's values are rounding noise: a law
    /// evaluated in f32 moves in steps of ~1e-6 N as its inputs round. The slip solve
    /// resolves the force no finer (0, the default, for laws evaluated in f64).
    fn resolution(&self) -> f64 {
        0.0
    }

    /// This law as a law with internal state (`crate::memory`), if it is one; the time
    /// loop then steps its state instead of calling the methods above. `None` (the
    /// default) for a memoryless law.
    fn as_memory(&self) -> Option<&dyn MemoryLaw> {
        None
    }

    /// [`FrictionLaw::as_memory`], mutable.
    fn as_memory_mut(&mut self) -> Option<&mut dyn MemoryLaw> {
        None
    }
}

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

impl ExponentialLaw {
    /// The exponential law with a scene's coefficients, whatever law the scene names.
    pub fn of(friction: &Friction) -> Self {
        Self {
            static_coefficient: friction.static_coefficient,
            kinetic_coefficient: friction.kinetic_coefficient,
            decay: friction.decay,
        }
    }

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

impl FrictionLaw for ExponentialLaw {
    fn name(&self) -> &str {
        FrictionLawKind::Exponential.name()
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

/// sign(v) with sign(0) = 0, so that a law at exactly zero speed exerts no force.
pub fn signum_or_zero(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
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
        let mut coulomb = CoulombLaw {
            kinetic_coefficient: 0.2,
        };
        assert_eq!(coulomb.sliding_force_and_slope(-0.1, 100.0), (-20.0, 0.0));
    }

    #[test]
    fn coulomb_law_is_constant_in_speed() {
        let mut law = CoulombLaw {
            kinetic_coefficient: 0.2,
        };
        assert_eq!(law.sliding_force(0.001, 100.0), 20.0);
        assert_eq!(law.sliding_force(-7.0, 100.0), -20.0);
    }
}
