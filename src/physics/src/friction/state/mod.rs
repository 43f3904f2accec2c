//! What the friction laws with internal state share: the force depends on the sliding
//! history through state variables that evolve with the slip, not on the current
//! velocity alone ("memory"). [`StatefulLaw`] is the interface; `super::lugre`
//! (Canudas de Wit et al. 1995) and `super::rate_and_state` (Dieterich 1979, Ruina 1983)
//! are the analytical laws, and the learned law (`super::learned_state`) implements the
//! same trait. Here too: the exact step of a linear relaxation both analytical laws
//! advance their state with (`relaxation`), and the velocity-step response of any law
//! with state ([`response`]).
//!
//! # How the time loop uses a law with state
//!
//! Over one step [t_n, t_n + dt] the sliding velocity v is held constant (the contact's
//! slip argument: v_rel at the scheme's law level, see `contact`), and the law advances
//! its state implicitly over the step from the state it last committed. The contact
//! solves F = F_step(v(F)) with the step force and its exact total slope dF/dv, state
//! update included ([`StatefulLaw::step_force_and_slope`], which must not change the
//! committed state: the slip solve evaluates it many times), and then commits the
//! step at the accepted velocity ([`StatefulLaw::commit`]). A law that integrates its
//! state exactly for constant v over the step (both analytical laws do) is stable for
//! any stiffness and any dt.
//!
//! # Example
//!
//! ```
//! use stickslip::friction::state::{LawStep, StatefulLaw};
//! use stickslip::friction::lugre::{LuGreLaw, LuGreParameters};
//! use stickslip::friction::exponential::ExponentialLaw;
//!
//! let g = ExponentialLaw { static_coefficient: 0.5, kinetic_coefficient: 0.2, decay: 5.0 };
//! let mut law = LuGreLaw::new(LuGreParameters::default(), g);
//! let step = LawStep { dt: 1e-4, sliding_velocity: 0.01, normal_force: 100.0 };
//! let (force, slope) = law.step_force_and_slope(step); // trial: state unchanged
//! assert_eq!(law.state(), &[0.0]);
//! law.commit(step); // accept the step at this velocity
//! assert!(law.state()[0] > 0.0 && force > 0.0 && slope > 0.0);
//! ```

pub(crate) mod relaxation;
pub mod response;

/// One time step of a law with state: the sliding velocity `sliding_velocity` (m/s),
/// held over the step of length `dt` (s), under the normal force `normal_force` (N).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LawStep {
    /// Step length (s), > 0.
    pub dt: f64,
    /// Signed sliding velocity v (m/s) over the step, the same convention as
    /// `FrictionLaw::sliding_force`: the force acts in its direction.
    pub sliding_velocity: f64,
    /// Normal force F_n (N).
    pub normal_force: f64,
}

/// A law's force at a held state and its derivatives over its inputs (v, F_n), in that
/// order: what `jacobian::LawJacobian` holds for a memoryless law (kept apart from it so
/// that this module does not depend on `jacobian`, which depends on `friction`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ForceAtState {
    /// F (N).
    pub force: f64,
    /// S = dF/dv (N s/m).
    pub slope: f64,
    /// (dF/dv, dF/dF_n) (N s/m, 1).
    pub force_gradient: [f64; 2],
    /// (dS/dv, dS/dF_n) = (d2F/dv2, d2F/dv dF_n) (N s^2/m^2, s/m).
    pub slope_gradient: [f64; 2],
}

/// One component of a law's state, for names in the FMU and in messages.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StateVariable {
    /// Short name ("bristle_deflection", "state_theta").
    pub name: &'static str,
    /// SI unit ("m", "s", "1").
    pub unit: &'static str,
    /// Whether the value must be strictly positive (rate-and-state's theta).
    pub positive: bool,
    /// What it is, for a variable's description ("LuGre bristle deflection z").
    pub description: &'static str,
}

/// LuGre's state: the bristle deflection z (m).
pub const BRISTLE_DEFLECTION: StateVariable = StateVariable {
    name: "bristle_deflection",
    unit: "m",
    positive: false,
    description: "LuGre bristle deflection z",
};

/// Rate-and-state's state theta (s): D_c / V in steady sliding at V.
pub const STATE_THETA: StateVariable = StateVariable {
    name: "state_theta",
    unit: "s",
    positive: true,
    description: "rate-and-state state theta (D_c / V in steady sliding at V)",
};

/// The learned law's state psi = ln(theta V_0 / D_c) (1): 0 in steady sliding at V_0.
pub const STATE_PSI: StateVariable = StateVariable {
    name: "state_psi",
    unit: "1",
    positive: false,
    description: "learned law's state psi = ln(theta V_0 / D_c)",
};

/// Every state variable of the laws with state this crate has, one per law, in a fixed
/// order: the FMUs output each of them (0 where the run's law has not that variable).
/// Defined here, not in the laws' modules, so that this module imports none of them
/// (they import it).
pub const STATE_VARIABLES: [StateVariable; 3] = [BRISTLE_DEFLECTION, STATE_THETA, STATE_PSI];

/// A state that does not fit a law: wrong length, non-finite, or outside its domain.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("friction law state does not fit: {0}")]
pub struct StateError(pub String);

/// A friction law with internal state.
///
/// It also implements `FrictionLaw`, whose methods give the **steady-state** force F_ss(v) (and slope): the
/// force after sliding long at constant v, which is what a memoryless caller (a plot, a
/// comparison) can be given. The time loop never uses them: it asks
/// `FrictionLaw::as_stateful_mut` for this trait and steps the state.
///
/// The state is a short vector of f64 (one entry for both analytical laws); it is part
/// of a simulation's saved state, so it must round-trip through [`StatefulLaw::state`] and
/// [`StatefulLaw::set_state`] bit for bit.
pub trait StatefulLaw: Send {
    /// The state's components, in the order of [`StatefulLaw::state`].
    fn state_variables(&self) -> &[StateVariable];

    /// The committed state (after the last [`StatefulLaw::commit`]).
    fn state(&self) -> &[f64];

    /// Replaces the committed state. Refused with the reason (the law unchanged) if the
    /// length differs from [`StatefulLaw::state_variables`], a value is not finite, or a
    /// positive component is not; see [`check_state`].
    fn set_state(&mut self, state: &[f64]) -> Result<(), StateError>;

    /// Returns the state to the law's initial state (a run's t = 0).
    fn reset(&mut self);

    /// The force (N) at the end of `step` from the committed state, and its exact total
    /// derivative dF/dv (N s/m) with respect to the step's sliding velocity, the state
    /// update's dependence on v included. Does not change the committed state.
    fn step_force_and_slope(&mut self, step: LawStep) -> (f64, f64);

    /// Advances the committed state over `step`: the state
    /// [`StatefulLaw::step_force_and_slope`] used for the same step.
    fn commit(&mut self, step: LawStep);

    /// The force at the committed state, held, for the sliding velocity
    /// `sliding_velocity` (m/s) and normal force `normal_force` (N): F (N), S = dF/dv
    /// (N s/m) and their gradients over (v, F_n) ([`ForceAtState`]).
    /// The limit of [`StatefulLaw::step_force_and_slope`]'s force as dt -> 0 (its slope is
    /// the direct effect only: the state does not move). What NeuralFriction outputs
    /// between its steps, and its directional derivatives.
    fn force_at_state(&self, sliding_velocity: f64, normal_force: f64) -> ForceAtState;

    /// Puts the law in the state in which it carries `force` (N) at rest (v = 0) under
    /// `normal_force` (N), where it can: the start of a preloaded run, whose beam is
    /// held by that force at t = 0. The default keeps the initial state (a law whose
    /// force at rest is 0, like rate-and-state's creep law, cannot hold a force at v = 0).
    fn hold(&mut self, _force: f64, _normal_force: f64) {}

    /// The force difference (N) below which the step's force is rounding noise (see
    /// `FrictionLaw::resolution`; 0, the default, for laws evaluated in f64).
    fn force_resolution(&self) -> f64 {
        0.0
    }
}

/// Checks `state` against `variables`: the same length, finite values, and positive
/// where a variable must be.
pub fn check_state(variables: &[StateVariable], state: &[f64]) -> Result<(), StateError> {
    if state.len() != variables.len() {
        return Err(StateError(format!(
            "{} values for a state of {}",
            state.len(),
            variables.len()
        )));
    }
    for (variable, &value) in variables.iter().zip(state) {
        if !value.is_finite() || (variable.positive && value <= 0.0) {
            let requirement = if variable.positive {
                "finite and > 0"
            } else {
                "finite"
            };
            return Err(StateError(format!(
                "{} = {value:e} {}; it must be {requirement}",
                variable.name, variable.unit
            )));
        }
    }
    Ok(())
}

/// [`check_state`], then `state` copied into `target` (of the same length once checked):
/// a law's [`StatefulLaw::set_state`] in one call, the law unchanged on refusal.
pub fn set_checked(
    variables: &[StateVariable],
    target: &mut [f64],
    state: &[f64],
) -> Result<(), StateError> {
    check_state(variables, state)?;
    target.copy_from_slice(state);
    Ok(())
}

#[cfg(test)]
mod at_state_tests;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_list_of_state_variables_is_each_laws_own_and_names_are_unique() {
        let laws = at_state_tests::example_laws();
        for (law, listed) in laws.iter().zip(STATE_VARIABLES) {
            assert_eq!(law.state_variables(), &[listed]);
        }
        let mut names: Vec<&str> = STATE_VARIABLES.iter().map(|v| v.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), STATE_VARIABLES.len());
    }
}
