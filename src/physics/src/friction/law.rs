//! The interface of a kinetic friction law, [`FrictionLaw`]: the force F(v, F_n) and its
//! slope, for the time loop's slip solve.

use super::state::StatefulLaw;
use crate::jacobian::LawJacobian;

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

    /// The force and slope with their gradients over (v, F_n) ([`LawJacobian`]), for a
    /// memoryless law that NeuralFriction evaluates on its own (its outputs' directional
    /// derivatives); `None` (the default) for the others. The registry's tests hold every
    /// law with a NeuralFriction code to it.
    fn jacobian(&mut self, _sliding_velocity: f64, _normal_force: f64) -> Option<LawJacobian> {
        None
    }

    /// This law as a law with internal state ([`state`]), if it is one; the time loop
    /// then steps its state instead of calling the methods above. `None` (the default)
    /// for a memoryless law.
    fn as_stateful(&self) -> Option<&dyn StatefulLaw> {
        None
    }

    /// [`FrictionLaw::as_stateful`], mutable.
    fn as_stateful_mut(&mut self) -> Option<&mut dyn StatefulLaw> {
        None
    }
}
