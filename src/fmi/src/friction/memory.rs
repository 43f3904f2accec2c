//! NeuralFriction with a law that has state: the learned law with memory
//! (`stickslip::neural::memory`), chosen by `law = neural` with `weights` naming a file
//! of format `stickslip-state-friction` (the shipped `rate-and-state-learned.json`).
//!
//! - The state psi starts at the law's initial state (0: steady sliding at V_0) when
//!   initialisation ends.
//! - Each communication step from t to t + h advances it with the inputs held over the
//!   step (sliding velocity, normal force as set before the step): the law's step is
//!   exact for a velocity held over it, so no substeps are needed and any h is stable.
//! - Outputs are the force at the committed state and the current inputs: setting a
//!   new velocity between steps moves the force at once by the direct effect, and the
//!   state follows over the next steps. `friction_force_slope` is dF/dv at the committed
//!   state (the direct effect's slope), and the directional derivatives are those at
//!   fixed state.
//! - The state is part of the FMU state (state version 4: `{settings, law_state}`);
//!   states of versions 1 to 3, which NeuralFriction wrote before it had laws with state,
//!   are the plain settings and restore with the initial law state.

use super::{EvaluateError, NeuralFriction, Settings};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use stickslip::jacobian::LawJacobian;
use stickslip::neural::memory::LearnedStateLaw;

/// The first FMU state version whose NeuralFriction state holds the law's state.
pub(super) const LAW_STATE_VERSION: u32 = 4;

/// NeuralFriction's saved form from state version 4 on.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Saved {
    settings: Settings,
    /// The committed law state (empty for a law without state).
    law_state: Vec<f64>,
}

impl NeuralFriction {
    /// The learned law with state the settings choose, if they choose one.
    pub(super) fn state_law(&mut self) -> Result<Option<Arc<LearnedStateLaw>>, EvaluateError> {
        match self.settings.law {
            stickslip::friction::LawChoice::Neural => {
                Ok(self.networks.state_law(&self.settings.weights)?)
            }
            _ => Ok(None),
        }
    }

    /// The committed state psi (the initial 0 before any step).
    pub(super) fn psi(&self) -> f64 {
        self.law_state.first().copied().unwrap_or(0.0)
    }

    /// Force and slope at the committed state and the current inputs.
    pub(super) fn state_force(&self, law: &LearnedStateLaw) -> (f64, f64) {
        let s = &self.settings;
        let f = law.force(self.psi(), s.sliding_velocity, s.normal_force);
        (f.force, f.d_velocity)
    }

    /// The Jacobian at fixed state over (v, F_n).
    pub(super) fn state_jacobian(&self, law: &LearnedStateLaw) -> LawJacobian {
        let s = &self.settings;
        law.jacobian(self.psi(), s.sliding_velocity, s.normal_force)
    }

    /// Advances the state over the step of `size` (s) to `to` (s) with the inputs held;
    /// the initial state at the first step of a law with state. The step is `size`, the
    /// importer's communication step size, so that every master that gives the same
    /// sizes gets the same bits (`Model::do_step`).
    pub(super) fn advance_state(&mut self, to: f64, size: f64) -> Result<(), EvaluateError> {
        let step = size;
        self.time = to;
        let Some(law) = self.state_law()? else {
            self.law_state.clear();
            return Ok(());
        };
        let s = &self.settings;
        let next = law
            .step_state(self.psi(), s.sliding_velocity, step.max(0.0))
            .state;
        if !next.is_finite() {
            return Err(EvaluateError::NonFiniteState {
                sliding_velocity: s.sliding_velocity,
                state: next,
            });
        }
        self.law_state = vec![next];
        Ok(())
    }

    /// The saved form of the current version (`Model::save`).
    pub(super) fn saved(&self) -> serde_json::Value {
        serde_json::to_value(Saved {
            settings: self.settings.clone(),
            law_state: self.law_state.clone(),
        })
        .unwrap_or(serde_json::Value::Null)
    }

    /// Restores a saved NeuralFriction state of format `version`.
    pub(super) fn restore_saved(
        &mut self,
        saved: serde_json::Value,
        version: u32,
        time: f64,
    ) -> Result<(), String> {
        let (settings, law_state) = if version >= LAW_STATE_VERSION {
            let saved: Saved = serde_json::from_value(saved)
                .map_err(|e| format!("saved NeuralFriction state is malformed: {e}"))?;
            (saved.settings, saved.law_state)
        } else {
            let settings: Settings = serde_json::from_value(saved)
                .map_err(|e| format!("saved NeuralFriction state is malformed: {e}"))?;
            (settings, Vec::new())
        };
        if law_state.len() > 1 || law_state.iter().any(|x| !x.is_finite()) {
            return Err(format!(
                "saved NeuralFriction law state {law_state:?} is not one finite value"
            ));
        }
        // Plain data: the outputs are evaluated when next read, so a state saved before
        // its parameters were checked restores too.
        self.settings = settings;
        self.law_state = law_state;
        self.time = time;
        Ok(())
    }
}
