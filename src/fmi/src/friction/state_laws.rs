//! NeuralFriction with a law that has state (`stickslip::friction::state::StatefulLaw`), one path
//! for the three: `law = lugre` (bristle deflection z, g(v) the exponential law of
//! `static_coefficient`, `kinetic_coefficient`, `decay`), `law = rate-and-state` (theta),
//! and `law = neural` with `weights` naming a file of format `stickslip-state-friction`
//! (the learned law with memory, psi; `rate-and-state-learned.json` is shipped).
//!
//! - The state starts at the law's initial state (`StatefulLaw::reset`: z = 0,
//!   theta = D_c / V_0, psi = 0) when initialisation ends.
//! - Each communication step from t to t + h commits one law step over h with the
//!   inputs held (sliding velocity and normal force as set before the step): the laws
//!   integrate their state exactly for a velocity held over the step, so no substeps
//!   are needed and any h is stable. A step of h = 0 keeps the state.
//! - Outputs are the force at the committed state and the current inputs
//!   (`StatefulLaw::force_at_state`): setting a new velocity between steps moves the force
//!   at once by the direct effect, and the state follows over the next steps.
//!   `friction_force_slope` is dF/dv at the committed state, and the directional
//!   derivatives are those at fixed state.
//! - The step-consistent pair (`step_friction_force`, `step_friction_slope`): the
//!   force after one step of the master's h (the size of the last communication step)
//!   from the committed state at the current inputs held, F_h(v) = F(s_h(v), v), and
//!   dF_h/dv, the state's response included. It is the law's own trial step
//!   (`StatefulLaw::step_force_and_slope`, the one the embedded contact solves with:
//!   LuGre's and rate-and-state's exact step for v held and its exact derivative, so
//!   no difference quotient), so the beam solving its tangent sees over the coming
//!   step what the state will do: for LuGre near stick dF_h/dv ~ sigma_0 h, where the
//!   instantaneous slope holds the bristles rigid. Before the first step h is not
//!   known and the pair is the instantaneous one.
//! - The state is part of the FMU state (state version 4: `{settings, law_state}`);
//!   states of versions 1 to 3, which NeuralFriction wrote before it had laws with state,
//!   are the plain settings and restore with the initial law state. Version-4 states
//!   written before `lugre` and `rate-and-state` came have no parameters for them: they
//!   read with the defaults (`Settings`). From state version 6 the state carries the
//!   last communication step's size (`step_size`); a version-4 or -5 state of a law
//!   with state after a step that lacks it is refused (`step_size_of`).

use super::state_velocity::StateVelocity;
use super::{EvaluateError, InitialiseError, NeuralFriction, Outputs, Settings};
use crate::instance::{check_as_set, parse_saved};
use crate::model::{Model, Restoring};
use serde::{Deserialize, Serialize};
use stickslip::friction::state::{LawStep, StatefulLaw, STATE_VARIABLES};
use stickslip::friction::FrictionLaw;
use stickslip::jacobian::LawJacobian;
use stickslip::law_source::LawSource;

/// The first FMU state version whose NeuralFriction state holds the law's state.
pub(super) const LAW_STATE_VERSION: u32 = 4;

/// The first FMU state version whose NeuralFriction state must hold `step_size`.
pub(super) const STEP_SIZE_VERSION: u32 = 6;

/// NeuralFriction's saved form from state version 4 on.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Saved {
    settings: Settings,
    /// The committed law state (empty for a law without state, or before the first
    /// step: the initial state).
    law_state: Vec<f64>,
    /// The last communication step's size (s), which the step-consistent pair looks
    /// ahead over. Required from version 6 on; versions 4 and 5 may lack it (it came
    /// in version 5 without a bump): `step_size_of`.
    #[serde(default)]
    step_size: Option<f64>,
    /// `mean_sliding_velocity` has been set (`NeuralFriction::mean_linked`; from
    /// version 7 on; absent: not, as no earlier FMU had the input).
    #[serde(default)]
    mean_linked: bool,
}

/// The step size of a saved state of `version`: required from version 6 on; before,
/// absent reads as 0 (no step taken yet) where that restores the run as it was, and is
/// refused where it would not: a law with state after a step, whose step-consistent
/// pair looks ahead over h, would restore with the instantaneous pair instead.
fn step_size_of(saved: &Saved, version: u32) -> Result<f64, String> {
    match saved.step_size {
        Some(h) if h.is_finite() && h >= 0.0 => Ok(h),
        Some(h) => Err(format!(
            "step_size = {h}: the last communication step's size must be finite and >= 0 (s)"
        )),
        None if version >= STEP_SIZE_VERSION => Err(format!(
            "step_size is missing: states of version {STEP_SIZE_VERSION} and later carry the last communication step's size (s)"
        )),
        None if saved.law_state.is_empty() => Ok(0.0),
        None => Err(format!(
            "a state of version {version} of a law with state after a step has no step_size (the communication step the step-consistent pair looks ahead over, saved from version {STEP_SIZE_VERSION} on); it cannot restore the run as it was: save it again with this FMU"
        )),
    }
}

/// Whether `a` and `b` choose the same law with the same parameters (the inputs may
/// differ).
fn same_law(a: &Settings, b: &Settings) -> bool {
    a.law == b.law
        && a.static_coefficient.to_bits() == b.static_coefficient.to_bits()
        && a.kinetic_coefficient.to_bits() == b.kinetic_coefficient.to_bits()
        && a.decay.to_bits() == b.decay.to_bits()
        && a.laws == b.laws
        && a.weights == b.weights
}

impl Settings {
    /// The coefficient of `static_limit` = mu F_n (the static limit handed to a set-valued
    /// stick, `external.static_limit`): mu_s, except 0 for a law that models presliding
    /// itself (the registry's `presliding`: `law = lugre`). LuGre has no
    /// set-valued stick: its bristles hold the tip (presliding, F = sigma0 z) and let it
    /// creep, and its state moves only while v_rel does. Under the beam's set-valued stick
    /// v_rel is 0, z stays where stick began (0 at the start), the creep is lost and
    /// breakaway drops the force from mu_s F_n to sigma0 z ~ 0 for the bristles' rise
    /// time; the coupled run then converged (h = 1e-5, 2e-6 s) to a first drop 2.8 ms
    /// early and a period 4 % short of the embedded law's. With 0 the beam never sticks,
    /// every step is a slip solve under the law's tangent, as the embedded contact's
    /// (docs/friction-with-memory.md).
    pub(super) fn static_limit_coefficient(&self) -> f64 {
        if self.law.kind().entry().presliding {
            0.0
        } else {
            self.static_coefficient
        }
    }
}

/// What restoring a saved state replaced (`NeuralFriction::adopt_saved`).
struct Adopted {
    settings: Settings,
    law_state: Vec<f64>,
    step_size: f64,
    mean_linked: bool,
    outputs: Outputs,
}

impl NeuralFriction {
    /// Makes `built` the law the settings choose (`None` for the plain network, which
    /// `networks` evaluates). The law last built is rebuilt only when the settings choose
    /// another (or other parameters), so that a step or an output allocates nothing for
    /// it.
    fn refresh_law(&mut self) -> Result<(), EvaluateError> {
        let fresh = match &self.built {
            Some((settings, _)) => !same_law(settings, &self.settings),
            None => true,
        };
        if fresh {
            self.built = self.build_law()?.map(|law| (self.settings.clone(), law));
        }
        Ok(())
    }

    /// The law with state the settings choose, in its committed state (the initial one
    /// before the first step), or `None` for a memoryless law.
    fn memory_law(&mut self) -> Result<Option<&mut dyn StatefulLaw>, EvaluateError> {
        self.refresh_law()?;
        let Some(law) = self
            .built
            .as_mut()
            .and_then(|(_, law)| law.as_stateful_mut())
        else {
            return Ok(None);
        };
        if self.law_state.is_empty() {
            law.reset();
        } else {
            law.set_state(&self.law_state)
                .map_err(|e| EvaluateError::Parameter(e.to_string()))?;
        }
        Ok(Some(law))
    }

    /// A new law for the settings, built where every law is built (`LawSource`) from
    /// the settings as the scene's friction section, its parameters checked first
    /// (outputs may be read before initialisation, whose check has then not run). The
    /// neural law is built here only when its weights file is of the learned law's
    /// format; `None` for the plain network.
    fn build_law(&mut self) -> Result<Option<Box<dyn FrictionLaw>>, EvaluateError> {
        let s = &self.settings;
        let friction = s.friction();
        if let Some(problem) = friction.law_problem() {
            return Err(EvaluateError::Parameter(problem.to_string()));
        }
        let source = match LawSource::analytical(&friction) {
            Some(source) => source,
            None => match self.networks.state_law(&s.weights)? {
                Some(law) => LawSource::LearnedState(law),
                None => return Ok(None),
            },
        };
        let law = source
            .law()
            .map_err(|e| EvaluateError::Parameter(e.to_string()))?;
        Ok(Some(law))
    }

    /// The force of a memoryless law built from its parameters (not the network) at the
    /// current inputs, with its Jacobian over (v, F_n); `None` for the network and for a
    /// law with state.
    pub(super) fn memoryless_jacobian(&mut self) -> Result<Option<LawJacobian>, EvaluateError> {
        let (v, normal) = (self.settings.sliding_velocity, self.settings.normal_force);
        self.refresh_law()?;
        let Some((_, law)) = self.built.as_mut() else {
            return Ok(None);
        };
        if law.as_stateful().is_some() {
            return Ok(None);
        }
        law.jacobian(v, normal).map(Some).ok_or_else(|| {
            EvaluateError::Parameter(format!(
                "law {} gives no Jacobian, which NeuralFriction needs",
                law.name()
            ))
        })
    }

    /// The force at the committed state and the current inputs with its Jacobian over
    /// (v, F_n), and the state outputs, or `None` for a memoryless law.
    pub(super) fn state_jacobian(
        &mut self,
    ) -> Result<Option<(LawJacobian, [f64; STATE_VARIABLES.len()])>, EvaluateError> {
        let (v, normal) = (self.settings.sliding_velocity, self.settings.normal_force);
        let Some(law) = self.memory_law()? else {
            return Ok(None);
        };
        let mut outputs = [0.0; STATE_VARIABLES.len()];
        for (variable, value) in law.state_variables().iter().zip(law.state()) {
            if let Some(k) = STATE_VARIABLES.iter().position(|s| s == variable) {
                outputs[k] = *value;
            }
        }
        let at = law.force_at_state(v, normal);
        let jacobian = LawJacobian {
            force: at.force,
            slope: at.slope,
            force_gradient: at.force_gradient.to_vec(),
            slope_gradient: at.slope_gradient.to_vec(),
        };
        Ok(Some((jacobian, outputs)))
    }

    /// The step-consistent pair (module notes) at the committed state and the current
    /// inputs, or `None` for a memoryless law and before the first step (h = 0).
    pub(super) fn step_pair(&mut self) -> Result<Option<(f64, f64)>, EvaluateError> {
        let step = LawStep {
            dt: self.step_size,
            sliding_velocity: self.settings.sliding_velocity,
            normal_force: self.settings.normal_force,
        };
        if step.dt <= 0.0 {
            return Ok(None);
        }
        let Some(law) = self.memory_law()? else {
            return Ok(None);
        };
        Ok(Some(law.step_force_and_slope(step)))
    }

    /// Commits one law step over `size` (s) to `to` (s) with the inputs held. The step
    /// is `size`, the importer's communication step size, so that every master that
    /// gives the same sizes gets the same bits (`Model::do_step`).
    pub(super) fn advance_state(&mut self, to: f64, size: f64) -> Result<(), EvaluateError> {
        self.time = to;
        let step = LawStep {
            dt: size,
            sliding_velocity: self.state_commit_velocity(),
            normal_force: self.settings.normal_force,
        };
        let Some(law) = self.memory_law()? else {
            self.law_state.clear();
            return Ok(());
        };
        // dt = 0 (an event iteration's step): nothing slides, the state stays.
        if size > 0.0 {
            law.commit(step);
        }
        // The law just used (disjoint from `law_state`, so both borrows may live).
        let state = self
            .built
            .as_ref()
            .and_then(|(_, law)| law.as_stateful())
            .map_or(&[][..], |law| law.state());
        if let Some(&value) = state.iter().find(|x| !x.is_finite()) {
            return Err(EvaluateError::NonFiniteState {
                sliding_velocity: step.sliding_velocity,
                state: value,
            });
        }
        self.law_state.clear();
        self.law_state.extend_from_slice(state);
        Ok(())
    }

    /// The saved form of the current version (`Model::save`).
    pub(super) fn saved(&self) -> serde_json::Value {
        serde_json::to_value(Saved {
            settings: self.settings.clone(),
            law_state: self.law_state.clone(),
            step_size: Some(self.step_size),
            mean_linked: self.mean_linked,
        })
        .unwrap_or(serde_json::Value::Null)
    }

    /// Puts the saved state's settings and law state in place, checked as setting them
    /// and initialising would check them (`Model::check_saved`); on refusal the model
    /// is left as it was and the reason names the parameter. Returns what was replaced.
    fn adopt_saved(&mut self, saved: serde_json::Value, at: &Restoring) -> Result<Adopted, String> {
        const WHAT: &str = "NeuralFriction";
        let parsed = if at.version >= LAW_STATE_VERSION {
            parse_saved::<Saved>(saved).and_then(|saved| {
                let step_size = step_size_of(&saved, at.version)?;
                Ok((
                    saved.settings,
                    saved.law_state,
                    step_size,
                    saved.mean_linked,
                ))
            })
        } else {
            parse_saved::<Settings>(saved).map(|settings| (settings, Vec::new(), 0.0, false))
        };
        let (settings, law_state, step_size, mean_linked) =
            parsed.map_err(|e| format!("saved {WHAT} state: {e}"))?;
        let mut candidate = NeuralFriction::with_defaults();
        candidate.settings = settings;
        check_as_set(&candidate, |m| &m.settings)
            .map_err(|e| format!("saved {WHAT} state: {e}"))?;
        let previous = Adopted {
            settings: std::mem::replace(&mut self.settings, candidate.settings),
            law_state: std::mem::replace(&mut self.law_state, law_state),
            step_size: std::mem::replace(&mut self.step_size, step_size),
            mean_linked: std::mem::replace(&mut self.mean_linked, mean_linked),
            outputs: self.outputs,
        };
        let checked = if at.initialized {
            self.check_initialised_law_state(at)
        } else if self.law_state.is_empty() {
            Ok(())
        } else {
            // Initialisation starts the law at its initial state, so no state before it.
            Err(format!(
                "law_state = {:?}: a state saved before initialisation has no law state",
                self.law_state
            ))
        };
        match checked {
            Ok(()) => Ok(previous),
            Err(reason) => {
                self.put_back(previous);
                Err(format!("saved {WHAT} state: {reason}"))
            }
        }
    }

    /// An initialised state: its parameters pass initialisation's checks (the same
    /// `initialise_outputs`), with its law state in place of the initial one, which
    /// must fit the law.
    fn check_initialised_law_state(&mut self, at: &Restoring) -> Result<(), String> {
        self.initialise_outputs().map_err(|e| match e {
            // The law refused the law state (length, finite, theta > 0).
            InitialiseError::Evaluate(EvaluateError::Parameter(reason))
                if !self.law_state.is_empty() =>
            {
                format!("law_state = {:?}: {reason}", self.law_state)
            }
            other => other.to_string(),
        })?;
        // Evaluating built the law the settings choose; a law built earlier for other
        // settings (`built` is a cache) does not count.
        let has_state = self.built.as_ref().is_some_and(|(built_for, law)| {
            same_law(built_for, &self.settings) && law.as_stateful().is_some()
        });
        if !has_state && !self.law_state.is_empty() {
            return Err(format!(
                "law_state = {:?}: the law {} has no state",
                self.law_state,
                stickslip::choice::Choice::name(self.settings.law)
            ));
        }
        // From version 4 on the law state is saved with every step (`advance_state`);
        // empty, the initial state, holds only before the first step.
        if has_state
            && self.law_state.is_empty()
            && at.version >= LAW_STATE_VERSION
            && at.time != at.start_time
        {
            return Err(format!(
                "law_state = []: the law {} has a state, which a state saved after a step (t = {} s, start {} s) carries",
                stickslip::choice::Choice::name(self.settings.law),
                at.time,
                at.start_time
            ));
        }
        Ok(())
    }

    fn put_back(&mut self, previous: Adopted) {
        self.settings = previous.settings;
        self.law_state = previous.law_state;
        self.step_size = previous.step_size;
        self.mean_linked = previous.mean_linked;
        self.outputs = previous.outputs;
    }

    /// `Model::check_saved`: as `restore_saved`, with the model put back afterwards.
    pub(super) fn check_saved_state(
        &mut self,
        saved: &serde_json::Value,
        at: &Restoring,
    ) -> Result<(), String> {
        let previous = self.adopt_saved(saved.clone(), at)?;
        self.put_back(previous);
        Ok(())
    }

    /// Restores a saved NeuralFriction state (`Model::restore`). Its outputs are
    /// evaluated when next read.
    pub(super) fn restore_saved(
        &mut self,
        saved: serde_json::Value,
        at: &Restoring,
    ) -> Result<(), String> {
        self.adopt_saved(saved, at)?;
        self.time = at.time;
        Ok(())
    }
}

/// The velocity a law's state is committed with (`state_velocity`, module notes of
/// `super::state_velocity`).
impl NeuralFriction {
    /// The velocity (m/s) the coming step commits the law's state with: the step's
    /// mean where the settings choose it and a master has set `mean_sliding_velocity`
    /// (one without that link gets `sliding_velocity`, as before the input existed).
    pub(super) fn state_commit_velocity(&self) -> f64 {
        let s = &self.settings;
        if self.mean_linked && self.commits_at_mean() {
            s.mean_sliding_velocity
        } else {
            s.sliding_velocity
        }
    }

    /// Whether `state_velocity` chooses the mean for the current law (`auto`: for
    /// every law, module notes of `super::state_velocity`).
    fn commits_at_mean(&self) -> bool {
        let s = &self.settings;
        match s.state_velocity {
            StateVelocity::End => false,
            StateVelocity::Mean => true,
            StateVelocity::Auto => true,
        }
    }
}
