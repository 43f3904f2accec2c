//! The trained network as a friction law (`crate::neural` evaluates it): the network
//! itself, in f64 or f32 ([`NeuralLaw`]), or its table ([`TableLaw`]), each with the
//! force F(v, F_n) (N) and its slope dF/dv (N s/m) at the sliding velocity v (m/s) and
//! normal force F_n (N). Which one a run uses, as `friction.inference` asks, is
//! `crate::law_source`.

use super::kind::FrictionLawKind;
use super::law::FrictionLaw;
use super::registry::{LawBuild, LawDescription};
use crate::choice::Choice;
use crate::neural::table::TableLaw;
use crate::neural::{NeuralError, NeuralLaw};

/// The network in the registry: its weights are loaded by the caller
/// (`crate::law_source`); NeuralFriction evaluates it as `law = neural`.
pub static LAW: LawDescription = LawDescription {
    neural_friction_code: Some(1),
    ..LawDescription::plain(FrictionLawKind::Neural, LawBuild::Network)
};

impl NeuralLaw {
    /// The law as the beam's `FrictionLaw`, refused with a clear error if the beam cannot
    /// supply every feature (see the module documentation).
    pub fn into_friction_law(self) -> Result<Box<dyn FrictionLaw>, NeuralError> {
        match self.beam_problem() {
            Some(problem) => Err(NeuralError::NotAFrictionLaw(problem)),
            None => Ok(Box::new(self)),
        }
    }
}

impl FrictionLaw for NeuralLaw {
    fn name(&self) -> &str {
        FrictionLawKind::Neural.name()
    }

    /// Signed force (N) in the direction of `sliding_velocity` (m/s) under
    /// `normal_force` (N); NaN if the law was not checked with `into_friction_law`
    /// and lacks an input. Allocation-free.
    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64 {
        if !self.set_beam_features(sliding_velocity, normal_force) {
            return f64::NAN;
        }
        self.evaluate_scratch()
    }

    /// In f32, the largest deviation from the exact network over the training range
    /// (measured at build, [`NeuralLaw::f32_deviation`]): the slip solve does not resolve
    /// the force more finely than the law's own error; 0 in f64.
    fn resolution(&self) -> f64 {
        self.f32_deviation.unwrap_or(0.0)
    }

    /// [`NeuralLaw::force_and_slope`].
    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64) {
        self.force_and_slope(sliding_velocity, normal_force)
    }
}

impl FrictionLaw for TableLaw {
    fn name(&self) -> &str {
        FrictionLawKind::Neural.name()
    }

    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64 {
        self.sliding_force_and_slope(sliding_velocity, normal_force)
            .0
    }

    /// [`TableLaw::force_and_slope`].
    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64) {
        self.force_and_slope(sliding_velocity, normal_force)
    }
}
