//! The kinetic law adapter: the scene's law or a coupled model's force, as the slip
//! solve evaluates it.

use crate::elementary::signum_or_zero;
use crate::friction::FrictionLaw;

/// Where the kinetic friction force of a step comes from.
pub enum Kinetic<'a> {
    /// The scene's law F_law(v, F_n) at normal force `normal_force` (N).
    Law {
        law: &'a mut dyn FrictionLaw,
        normal_force: f64,
    },
    /// A coupled friction model: magnitude `force` (N), held over the step, in the
    /// direction of the sliding velocity.
    External { force: f64 },
    /// A coupled friction model with a signed law F(v), known by its value `force` (N)
    /// and slope `slope` = dF/dv (N s/m) at the sliding velocity `velocity` (m/s) it was
    /// evaluated at, all held over the step. The step's force is the law's tangent
    /// F(v) ~ force + slope (v - velocity) at the step's own sliding velocity, solved
    /// implicitly like the scene's law, and acting along v_rel where the tangent points
    /// against it as `direction` says (see `tangent`). With slope 0 it is the held
    /// force, or its magnitude along v_rel.
    ExternalSigned {
        force: f64,
        slope: f64,
        velocity: f64,
        direction: Direction,
    },
}

/// Where a coupled tangent that points against the sliding velocity is turned along it
/// (friction dissipates; see `tangent`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Wherever it points against v_rel: for a memoryless law, whose force never
    /// opposes v_rel except in the smoothing of its jump (the `signed` coupling).
    AlongSlip,
    /// Only where v_rel has also crossed 0 since the velocity the model was evaluated
    /// at (sign(v_rel) = -sign(velocity)): a law with state may push against v_rel
    /// (LuGre's bristles after a reversal, F = sigma0 z with z not yet turned), and
    /// that force is the law's (the `step` coupling).
    AcrossZero,
}

impl Direction {
    /// Whether the tangent's `value` (N) at sliding velocity `x` (m/s), handed over at
    /// the evaluated velocity `velocity` (m/s), acts along v_rel instead.
    pub(super) fn flips(self, value: f64, x: f64, velocity: f64) -> bool {
        value * x < 0.0
            && match self {
                Direction::AlongSlip => true,
                Direction::AcrossZero => x * velocity < 0.0,
            }
    }
}

impl Kinetic<'_> {
    /// Signed kinetic force (N) at sliding velocity `v` (m/s).
    fn force(&mut self, v: f64) -> f64 {
        match self {
            Kinetic::Law { law, normal_force } => law.sliding_force(v, *normal_force),
            Kinetic::External { force } => signum_or_zero(v) * *force,
            Kinetic::ExternalSigned {
                force,
                slope,
                velocity,
                ..
            } => *force + *slope * (v - *velocity),
        }
    }

    /// The law's resolution (N, see [`FrictionLaw::resolution`]).
    pub(super) fn resolution(&self) -> f64 {
        match self {
            Kinetic::Law { law, .. } => law.resolution(),
            Kinetic::External { .. } | Kinetic::ExternalSigned { .. } => 0.0,
        }
    }

    /// The force (N) and its slope dF/dv (N s/m) at `v` (m/s).
    fn force_and_slope(&mut self, v: f64) -> (f64, f64) {
        match self {
            Kinetic::Law { law, normal_force } => law.sliding_force_and_slope(v, *normal_force),
            Kinetic::External { force } => (signum_or_zero(v) * *force, 0.0),
            Kinetic::ExternalSigned {
                force,
                slope,
                velocity,
                ..
            } => (*force + *slope * (v - *velocity), *slope),
        }
    }
}

/// The kinetic force of one slip solve, counting its evaluations.
pub(super) struct CountedLaw<'a, 'k> {
    pub(super) kinetic: &'a mut Kinetic<'k>,
    pub(super) evaluations: usize,
}

impl CountedLaw<'_, '_> {
    pub(super) fn force(&mut self, v: f64) -> f64 {
        self.evaluations += 1;
        self.kinetic.force(v)
    }

    pub(super) fn force_and_slope(&mut self, v: f64) -> (f64, f64) {
        self.evaluations += 1;
        self.kinetic.force_and_slope(v)
    }
}

/// `Kinetic::force` is private (the solvers reach it through `CountedLaw`), and only the
/// fixed-point solver calls it, so a step through `Contact::resolve` cannot pin it at
/// v = 0: its direction rule is checked here.
#[cfg(test)]
mod tests {
    use super::Kinetic;

    #[test]
    fn external_kinetic_force_acts_along_the_sliding_velocity() {
        assert_eq!(Kinetic::External { force: 7.0 }.force(0.3), 7.0);
        assert_eq!(Kinetic::External { force: 7.0 }.force(-0.3), -7.0);
        assert_eq!(Kinetic::External { force: 7.0 }.force(0.0), 0.0);
    }
}
