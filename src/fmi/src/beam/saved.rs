//! The FMU state of StickSlipBeam (`Model::save`, `Model::restore`) and the states of
//! versions 1 and 2, migrated to the current form (version 3) when read.

use super::{BeamInputs, Settings, StickSlipBeam, DEFAULT_FIDELITY_TOLERANCE};
use crate::instance::{check_as_set, parse_saved};
use crate::model::{Model, Restoring};
use serde::{Deserialize, Serialize};
use stickslip::friction::FrictionLawKind;
use stickslip::scene::{FidelityLevel, Scene};
use stickslip::simulation::{set_law_state, ExternalCoupling, SimulationState};

/// Saved form (FMU state). Its size does not grow with simulated time: the
/// simulation's state is a fixed number of values for a given model, and the
/// transitions are kept as their count (`SimulationState::transition_count`).
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Saved {
    settings: Settings,
    initialized: bool,
    running: Option<SavedRun>,
}

#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SavedRun {
    built_from: Settings,
    start_time: f64,
    state: SimulationState,
    /// `Running::mean_relative_velocity`; from state version 7 on (`mean_of`).
    #[serde(default)]
    mean_relative_velocity: Option<f64>,
}

/// The first state version whose running beam carries `mean_relative_velocity`.
const MEAN_VELOCITY_VERSION: u32 = 7;

/// The mean sliding velocity over the last step of a saved run of state `version`:
/// required from version 7 on. An older state lacks it. Before its first step, or
/// with a law inside the beam (no coupled law commits its state with the mean), it
/// reads as v_rel at the restored point (`None`: the restored simulation's), which
/// only a read before the next step sees. After a step with `friction.law =
/// external` it is refused: the mean is lost, and a coupled law with state would
/// commit its next state with a wrong velocity.
fn mean_of(run: &SavedRun, version: u32) -> Result<Option<f64>, String> {
    match run.mean_relative_velocity {
        Some(v) if v.is_finite() => Ok(Some(v)),
        Some(v) => Err(format!(
            "running.mean_relative_velocity = {v}: it must be finite (m/s)"
        )),
        None if version >= MEAN_VELOCITY_VERSION => Err(format!(
            "running.mean_relative_velocity is missing: states of version {MEAN_VELOCITY_VERSION} and later carry the mean sliding velocity over the last step (m/s)"
        )),
        None if run.state.time > 0.0
            && run.built_from.scene.friction.law == FrictionLawKind::External =>
        {
            Err(format!(
                "a state of version {version} after a step with friction.law = external has no running.mean_relative_velocity (the mean sliding velocity over the last step, which a coupled law with state commits with, saved from version {MEAN_VELOCITY_VERSION} on); it cannot restore the run as it was: save it again with this FMU"
            ))
        }
        None => Ok(None),
    }
}

/// The transitions that state versions 1 and 2 listed beside the simulation state: every
/// one since the start, so that those states grew with simulated time. Version 3 keeps
/// only their count, which the list must agree with.
fn check_listed_transitions(
    state: &SimulationState,
    transitions: &[stickslip::contact::Transition],
) -> Result<(), String> {
    if transitions.len() as u64 == state.transition_count {
        Ok(())
    } else {
        Err(format!(
            "{} transitions listed, the count says {}",
            transitions.len(),
            state.transition_count
        ))
    }
}

/// The running simulation as state version 2 saved it.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SavedRunV2 {
    built_from: Settings,
    start_time: f64,
    state: SimulationState,
    transitions: Vec<stickslip::contact::Transition>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SavedV2 {
    settings: Settings,
    initialized: bool,
    running: Option<SavedRunV2>,
}

impl TryFrom<SavedV2> for Saved {
    type Error = String;

    fn try_from(v2: SavedV2) -> Result<Self, String> {
        let running = match v2.running {
            Some(run) => {
                check_listed_transitions(&run.state, &run.transitions)?;
                Some(SavedRun {
                    built_from: run.built_from,
                    start_time: run.start_time,
                    state: run.state,
                    mean_relative_velocity: None,
                })
            }
            None => None,
        };
        Ok(Saved {
            settings: v2.settings,
            initialized: v2.initialized,
            running,
        })
    }
}

/// Settings as FMU state version 1 saved them: the friction model, the auto flag and
/// the tolerance beside the scene instead of in it.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SettingsV1 {
    scene: Scene,
    friction_model: FrictionLawKind,
    weights: String,
    inputs: BeamInputs,
    #[serde(default)]
    fidelity_auto: bool,
    #[serde(default = "default_tolerance_v1")]
    fidelity_tolerance: f64,
}

fn default_tolerance_v1() -> f64 {
    DEFAULT_FIDELITY_TOLERANCE
}

impl From<SettingsV1> for Settings {
    /// The version-1 FMU ran `friction_model` whatever the scene's law said, and with
    /// `fidelity_auto` replaced the scene's level by the auto choice.
    fn from(v1: SettingsV1) -> Self {
        let mut scene = v1.scene;
        scene.friction.law = v1.friction_model;
        scene.fidelity.tolerance = Some(v1.fidelity_tolerance);
        if v1.fidelity_auto {
            scene.fidelity.level = FidelityLevel::Auto;
        }
        Settings {
            scene,
            weights: v1.weights,
            coupling: ExternalCoupling::default(),
            inputs: v1.inputs,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SavedV1 {
    settings: SettingsV1,
    initialized: bool,
    running: Option<SavedRunV1>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SavedRunV1 {
    built_from: SettingsV1,
    start_time: f64,
    state: SimulationState,
    transitions: Vec<stickslip::contact::Transition>,
}

impl TryFrom<SavedV1> for Saved {
    type Error = String;

    fn try_from(v1: SavedV1) -> Result<Self, String> {
        Saved::try_from(SavedV2 {
            settings: v1.settings.into(),
            initialized: v1.initialized,
            running: v1.running.map(|run| SavedRunV2 {
                built_from: run.built_from.into(),
                start_time: run.start_time,
                state: run.state,
                transitions: run.transitions,
            }),
        })
    }
}

impl StickSlipBeam {
    /// [`crate::model::Model::save`]: the settings and the running simulation's state.
    pub(super) fn saved(&self) -> serde_json::Value {
        let saved = Saved {
            settings: self.settings.clone(),
            initialized: self.initialized,
            running: self.running.as_ref().map(|r| SavedRun {
                built_from: r.built_from.clone(),
                start_time: r.start_time,
                state: r.simulator.state().clone(),
                mean_relative_velocity: Some(r.mean_relative_velocity),
            }),
        };
        serde_json::to_value(saved).unwrap_or(serde_json::Value::Null)
    }

    /// The saved form of format `version`, migrated to the current one.
    fn parse_saved_of_version(saved: serde_json::Value, version: u32) -> Result<Saved, String> {
        Ok(match version {
            1 => Saved::try_from(parse_saved::<SavedV1>(saved)?)?,
            2 => Saved::try_from(parse_saved::<SavedV2>(saved)?)?,
            _ => parse_saved(saved)?,
        })
    }

    /// The checks of a saved state that need no simulation built: every parameter and
    /// input as its setter checks it, the parts agreeing with each other and with the
    /// instance's mode and clocks, and a running simulation's settings as
    /// initialisation checks them (the scene's rules, the weights read and fitting the
    /// scene). The reason names the part and the parameter.
    fn check_parsed(&mut self, saved: &Saved, at: &Restoring) -> Result<(), String> {
        let as_set = |settings: &Settings, part: &str| {
            let mut from = StickSlipBeam::with_defaults();
            from.settings = settings.clone();
            check_as_set(&from, |m| &m.settings).map_err(|e| format!("{part}: {e}"))
        };
        as_set(&saved.settings, "settings")?;
        if let Some(run) = &saved.running {
            as_set(&run.built_from, "running.built_from")?;
        }
        if saved.initialized != at.initialized {
            return Err(format!(
                "initialized = {} disagrees with the state's mode (initialised: {})",
                saved.initialized, at.initialized
            ));
        }
        if saved.initialized {
            // After initialisation the parameters are fixed and every input set is
            // passed on to the simulation's settings (`apply_inputs`).
            let Some(run) = &saved.running else {
                return Err("initialized = true but no simulation is running".into());
            };
            if run.built_from != saved.settings {
                let field = first_difference_of(&run.built_from, &saved.settings);
                return Err(format!(
                    "running.built_from differs from settings at {field}; after initialisation they are the same"
                ));
            }
            if run.start_time != at.start_time {
                return Err(format!(
                    "running.start_time = {} s differs from the state's start time {} s",
                    run.start_time, at.start_time
                ));
            }
        }
        let Some(run) = &saved.running else {
            return Ok(());
        };
        mean_of(run, at.version)?;
        // fmi2DoStep lands the simulation exactly on each communication point, so the
        // two clocks agree to rounding; half a time step separates rounding from a
        // crafted gap that the next step would have to integrate through.
        let simulated = run.start_time + run.state.time;
        let half_step = 0.5 * run.built_from.scene.time.step;
        let agree = (simulated - at.time).abs() <= half_step;
        if !(simulated.is_finite() && half_step.is_finite() && agree) {
            return Err(format!(
                "the state's simulation is at t = {simulated} s but its FMU time is {} s; the two clocks must agree",
                at.time
            ));
        }
        let stop = Some(run.start_time + run.built_from.scene.time.end);
        let law = self
            .check_buildable(&run.built_from, run.start_time, stop)
            .map_err(|e| format!("running.built_from: {e}"))?;
        // The law state must fit the law, as the simulation's restore requires.
        let mut law = law.law().map_err(|e| e.to_string())?;
        set_law_state(law.as_mut(), &run.state.law_state)
            .map_err(|e| format!("running.state.law_state: {e}"))
    }

    /// [`crate::model::Model::check_saved`].
    pub(super) fn check_saved_state(
        &mut self,
        saved: &serde_json::Value,
        at: &Restoring,
    ) -> Result<(), String> {
        let saved = Self::parse_saved_of_version(saved.clone(), at.version)
            .and_then(|saved| self.check_parsed(&saved, at).map(|()| saved));
        saved
            .map(|_| ())
            .map_err(|e| format!("saved StickSlipBeam state: {e}"))
    }

    /// [`crate::model::Model::restore`]: a state of any version (1 to 3 migrated to the
    /// current form), checked as `check_saved_state` does, with the simulation rebuilt
    /// (or kept) and its state loaded (which checks its vectors against the model).
    pub(super) fn restore_saved(
        &mut self,
        saved: serde_json::Value,
        at: &Restoring,
    ) -> Result<(), String> {
        let saved = Self::parse_saved_of_version(saved, at.version)
            .and_then(|saved| self.check_parsed(&saved, at).map(|()| saved))
            .map_err(|e| format!("saved StickSlipBeam state: {e}"))?;
        let Some(run) = saved.running else {
            self.settings = saved.settings;
            self.running = None;
            self.initialized = false;
            return Ok(());
        };
        let mean =
            mean_of(&run, at.version).map_err(|e| format!("saved StickSlipBeam state: {e}"))?;
        // Build (or keep) the simulation of the saved settings, then load its state; on
        // failure the model is left as it was.
        let previous_settings = std::mem::replace(&mut self.settings, run.built_from.clone());
        let mut previous_running = self.running.take();
        let reusable = previous_running.as_ref().is_some_and(|r| {
            r.built_from.scene == run.built_from.scene
                && r.built_from.weights == run.built_from.weights
        });
        let built = if reusable {
            self.running = previous_running.take();
            Ok(())
        } else {
            let stop = Some(run.start_time + run.built_from.scene.time.end);
            self.ensure_running(run.start_time, stop)
                .map_err(|e| e.to_string())
        };
        let restored = built.and_then(|()| {
            let running = self.running.as_mut().ok_or("no simulation")?;
            running
                .simulator
                .restore(run.state)
                .map_err(|e| e.to_string())?;
            running.start_time = run.start_time;
            running.mean_relative_velocity =
                mean.unwrap_or_else(|| running.simulator.sample().relative_velocity);
            Ok::<(), String>(())
        });
        match restored {
            Ok(()) => {
                self.initialized = saved.initialized;
                self.settings = saved.settings;
                if let Some(running) = &mut self.running {
                    running.built_from = run.built_from;
                }
                self.apply_inputs();
                Ok(())
            }
            Err(reason) => {
                self.settings = previous_settings;
                if !reusable {
                    self.running = previous_running;
                }
                Err(reason)
            }
        }
    }
}

/// The first field (dotted path) where `a` and `b` differ.
fn first_difference_of(a: &Settings, b: &Settings) -> String {
    let (a, b) = (
        serde_json::to_value(a).unwrap_or_default(),
        serde_json::to_value(b).unwrap_or_default(),
    );
    crate::instance::first_difference(&a, &b)
}
