//! The learned law as a law with state of the time loop (`crate::friction::state::StatefulLaw`):
//! the law's parameters with its committed state psi. The contact's slip solve asks for
//! the force after a step with its exact total slope (`LearnedStateLaw::after_step`),
//! then commits the step; NeuralFriction steps it over each communication step.

use std::sync::Arc;

use super::law::LearnedStateLaw;
use crate::friction::law::FrictionLaw;
use crate::friction::state::{
    set_checked, ForceAtState, LawStep, StateError, StateVariable, StatefulLaw,
};

/// This law's state variable, listed in `crate::friction::state::STATE_VARIABLES` (defined
/// there, so that the list imports no law).
pub use crate::friction::state::STATE_PSI;

const STATE: [StateVariable; 1] = [STATE_PSI];

/// A learned state law and its committed state psi = ln(theta V_0 / D_c), which starts
/// (and resets) at 0: steady sliding at V_0, as the analytical rate-and-state law
/// starts at theta = D_c / V_0.
#[derive(Clone, Debug)]
pub struct LearnedStateFriction {
    law: Arc<LearnedStateLaw>,
    state: [f64; 1],
}

impl LearnedStateFriction {
    pub fn new(law: Arc<LearnedStateLaw>) -> Self {
        Self { law, state: [0.0] }
    }

    pub fn law(&self) -> &LearnedStateLaw {
        &self.law
    }
}

impl FrictionLaw for LearnedStateFriction {
    fn name(&self) -> &str {
        "neural-memory"
    }

    /// The steady sliding force F(psi_ss(|v|), v) (0 at v = 0, where psi_ss is
    /// unbounded).
    fn sliding_force(&mut self, sliding_velocity: f64, normal_force: f64) -> f64 {
        self.sliding_force_and_slope(sliding_velocity, normal_force)
            .0
    }

    /// Its slope: dF/dv + dF/dpsi dpsi_ss/dv with dpsi_ss/dv = -1/v.
    fn sliding_force_and_slope(&mut self, sliding_velocity: f64, normal_force: f64) -> (f64, f64) {
        if sliding_velocity == 0.0 {
            return (0.0, 0.0);
        }
        let state = self.law.steady_state(sliding_velocity.abs());
        let f = self.law.force(state, sliding_velocity, normal_force);
        (f.force, f.d_velocity - f.d_state / sliding_velocity)
    }

    fn as_stateful(&self) -> Option<&dyn StatefulLaw> {
        Some(self)
    }

    fn as_stateful_mut(&mut self) -> Option<&mut dyn StatefulLaw> {
        Some(self)
    }
}

impl StatefulLaw for LearnedStateFriction {
    fn state_variables(&self) -> &[StateVariable] {
        &STATE
    }

    fn state(&self) -> &[f64] {
        &self.state
    }

    fn set_state(&mut self, state: &[f64]) -> Result<(), StateError> {
        set_checked(&STATE, &mut self.state, state)
    }

    fn reset(&mut self) {
        self.state = [0.0];
    }

    fn step_force_and_slope(&mut self, step: LawStep) -> (f64, f64) {
        let s = self.law.after_step(
            self.state[0],
            step.sliding_velocity,
            step.normal_force,
            step.dt,
        );
        (s.force, s.slope)
    }

    fn commit(&mut self, step: LawStep) {
        self.state[0] = self
            .law
            .step_state(self.state[0], step.sliding_velocity, step.dt)
            .state;
    }

    /// The learned law's Jacobian at the committed psi (`LearnedStateLaw::jacobian`).
    fn force_at_state(&self, sliding_velocity: f64, normal_force: f64) -> ForceAtState {
        let j = self
            .law
            .jacobian(self.state[0], sliding_velocity, normal_force);
        ForceAtState {
            force: j.force,
            slope: j.slope,
            force_gradient: [j.force_gradient[0], j.force_gradient[1]],
            slope_gradient: [j.slope_gradient[0], j.slope_gradient[1]],
        }
    }
}
