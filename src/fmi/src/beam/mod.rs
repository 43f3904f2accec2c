//! StickSlipBeam: the scene's beam, contact and friction law as an FMU.
//!
//! Parameters are the scene's fields under the scene file's names (`geometry.length`,
//! `fidelity.level`, ...), checked together at fmi2ExitInitializationMode with the
//! scene's messages; the choices are the scene's choice enums, set by their codes. The
//! belt speed and normal force are inputs. `friction.law = external` takes the kinetic
//! force and the static limit (`external.static_limit`) from further inputs, held over
//! each communication step, so that the beam can be coupled to NeuralFriction.fmu or any
//! other friction FMU. How it reads the kinetic force is `external.coupling`:
//! - `magnitude` (the default): `external.kinetic_force` along v_rel, right for laws
//!   F(v) = sign(v) g(|v|) (exponential, Coulomb, the signed network), whose jump at
//!   v = 0 the beam places itself;
//! - `signed`: the law's tangent at the velocity the model was evaluated at,
//!   `external.friction_force` + `external.friction_slope` (v -
//!   `external.sliding_velocity`), solved within each internal step, for smooth signed
//!   laws such as the paper's plain network (see `stickslip::contact`, and docs/cosimulation.md
//!   for the coupling errors);
//! - `step`: the step-consistent tangent of a law with state, `external.step_force` +
//!   `external.step_slope` (v - `external.sliding_velocity`): the force after one
//!   communication step at the velocity held and its derivative with respect to that
//!   velocity, the state's response included (NeuralFriction's `step_friction_force`
//!   and `step_friction_slope`), solved as `signed`, turned along v_rel only where v_rel
//!   has crossed 0 since the evaluation.
//! - `table`: both curves of a law with state over the communication step, the
//!   instantaneous and the one-step one, as values at the fixed velocities
//!   `stickslip::friction::tabulated::TABLE_VELOCITIES` (`external.table_force_i`,
//!   `external.table_step_force_i`, NeuralFriction's `table_friction_force_i` and
//!   `table_step_friction_force_i`) and at `external.sliding_velocity`
//!   (`external.friction_force`, `external.step_force`), blended over the step and
//!   interpolated piecewise linearly, solved as an embedded law is (issue 36), with no
//!   set-valued stick (`external.static_limit` is not read: the curves at and around
//!   v = 0 hold the tip, as the embedded law's force does).
//!
//! `fidelity.level = auto` is resolved by the `auto` module at
//! fmi2ExitInitializationMode.
//!
//! The FMU steps at `time.step` and ends each communication step with one shorter step
//! when the communication point is not on that grid (`Simulator::advance_to`).
//!
//! Rooms: `variables`, the variable table (value references are part of saved states
//! and SSP files: never renumber); `build`, the simulation built from the parameters;
//! `saved`, the FMU state and the migration of versions 1 to 3; `model`, the `Model`
//! implementation that the FMI layer drives.

mod build;
pub mod exported;
mod model;
mod saved;
mod variables;

use crate::networks::{Networks, DEFAULT_WEIGHTS};
use serde::{Deserialize, Serialize};
use stickslip::contact::ContactState;
use stickslip::friction::tabulated::{StepCurves, TABLE_VELOCITIES};
use stickslip::friction::FrictionLawKind;
use stickslip::scene::Scene;
use stickslip::simulation::{
    ExternalCoupling, ExternalFriction, ExternalKinetic, Simulator, RECENT_TRANSITIONS,
};

/// Inputs of the beam (SI units).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamInputs {
    pub belt_speed: f64,
    pub normal_force: f64,
    pub kinetic_force: f64,
    pub static_limit: f64,
    /// The signed coupling's inputs; absent from states saved before it (version 3 and
    /// earlier), where they read as 0.
    #[serde(default)]
    pub friction_force: f64,
    #[serde(default)]
    pub friction_slope: f64,
    #[serde(default)]
    pub sliding_velocity: f64,
    /// `external.step_force` (N) and `external.step_slope` (N s/m): the
    /// step-consistent tangent of a law with state (`external.coupling = step`).
    #[serde(default)]
    pub step_force: f64,
    #[serde(default)]
    pub step_slope: f64,
    /// `external.table_force_i` and `external.table_step_force_i` (N): both force
    /// curves at `stickslip::friction::tabulated::TABLE_VELOCITIES`
    /// (`external.coupling = table`); absent from states saved before them (version 7
    /// and earlier), where they read as 0.
    #[serde(default)]
    pub table_force: [f64; TABLE_VELOCITIES.len()],
    #[serde(default)]
    pub table_step_force: [f64; TABLE_VELOCITIES.len()],
}

/// Everything set from outside: parameters and inputs. The friction model and the
/// fidelity level (`auto` included) are the scene's own fields.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Settings {
    scene: Scene,
    weights: String,
    /// Absent from states saved before it: the magnitude coupling they ran.
    #[serde(default)]
    coupling: ExternalCoupling,
    inputs: BeamInputs,
}

/// Start value of fidelity.tolerance (m): the physics crate's default, which a scene
/// file or the command line without a tolerance gets as well.
pub const DEFAULT_FIDELITY_TOLERANCE: f64 = stickslip::auto::DEFAULT_TOLERANCE;

impl Default for Settings {
    fn default() -> Self {
        let mut scene = Scene::default();
        scene.fidelity.tolerance = Some(DEFAULT_FIDELITY_TOLERANCE);
        let f = &scene.friction;
        let inputs = BeamInputs {
            belt_speed: scene.loading.belt_speed,
            normal_force: scene.loading.normal_force,
            kinetic_force: f.kinetic_coefficient * scene.loading.normal_force,
            static_limit: f.static_coefficient * scene.loading.normal_force,
            friction_force: 0.0,
            friction_slope: 0.0,
            sliding_velocity: 0.0,
            step_force: 0.0,
            step_slope: 0.0,
            table_force: [0.0; TABLE_VELOCITIES.len()],
            table_step_force: [0.0; TABLE_VELOCITIES.len()],
        };
        Self {
            scene,
            weights: DEFAULT_WEIGHTS.into(),
            coupling: ExternalCoupling::default(),
            inputs,
        }
    }
}

/// The running simulation and the settings it was built from.
struct Running {
    built_from: Settings,
    simulator: Simulator,
    /// Time (s) at which the simulation's t = 0 lies.
    start_time: f64,
    /// The mean sliding velocity (m/s) over the last step that advanced time (output
    /// `mean_relative_velocity`): v_b - (u(t_k+1) - u(t_k)) / (t_k+1 - t_k) with u
    /// the tip deflection, the distance slid over the step divided by its length,
    /// exact for any motion within it (the belt speed is an input, held over the
    /// step). Before the first step, v_rel at the start. A law with state in a
    /// coupled friction model commits its state with it (issue 36,
    /// `friction::state_velocity`).
    mean_relative_velocity: f64,
}

pub struct StickSlipBeam {
    settings: Settings,
    /// The start values, which `reset` returns to: the defaults, or an exported scene's
    /// (`exported`).
    start: Settings,
    networks: Networks,
    /// `auto` choices not yet logged.
    auto_log: Vec<String>,
    running: Option<Running>,
    /// fmi2ExitInitializationMode has built the simulation the steps use.
    initialized: bool,
    /// An exported scene's sensors as outputs (`exported`): displacement and velocity
    /// of each, in the section's order; none for StickSlipBeam itself.
    sensors: Vec<crate::variables::DynamicOutput>,
}

impl StickSlipBeam {
    /// How many networks this instance has read: zero unless a law needed one.
    pub fn networks_read(&self) -> usize {
        self.networks.read_count()
    }

    /// fmi2DoStep / fmi3DoStep: advances the simulation to `to` (s, FMU clock), or,
    /// with `stop_at_switch`, until the end of the internal step in which the contact
    /// switched, returning that time (see `Simulator::advance_until_switch`). Every
    /// transition made is listed in `events`. `size` (s) is the master's step.
    fn advance(
        &mut self,
        to: f64,
        size: f64,
        stop_at_switch: bool,
        events: &mut Vec<String>,
    ) -> Result<Option<f64>, String> {
        let Some(running) = &mut self.running else {
            return Err("the simulation was not initialised".into());
        };
        let before = running.simulator.state().transition_count;
        let (t_before, tip_before) = {
            let s = running.simulator.sample();
            (s.time, s.tip_deflection)
        };
        let target = to - running.start_time;
        let result = if stop_at_switch {
            running.simulator.advance_until_switch(target)
        } else {
            running.simulator.advance_to(target).map(|()| None)
        };
        // The simulator keeps at least the last RECENT_TRANSITIONS transitions, so a step
        // that made no more than that lists them all.
        let made = running.simulator.state().transition_count - before;
        let kept = running.simulator.transitions();
        let listed = kept.len().min(usize::try_from(made).unwrap_or(usize::MAX));
        if made > listed as u64 {
            events.push(format!(
                "{} transitions of this step before t = {:.6} s are not listed: the simulation keeps only its last {} to {} transitions",
                made - listed as u64,
                kept[kept.len() - listed].time + running.start_time,
                RECENT_TRANSITIONS,
                2 * RECENT_TRANSITIONS
            ));
        }
        for t in &kept[kept.len() - listed..] {
            let to_state = match t.to {
                ContactState::Stick => "stick",
                ContactState::Slip => "slip",
            };
            events.push(format!(
                "t = {:.6} s: {to_state}",
                t.time + running.start_time
            ));
        }
        let switched = result.map_err(|e| e.to_string())?;
        let after = running.simulator.sample();
        // Divided by the master's step, not by the simulation's clock difference: the
        // simulation lands on `to` as each master computes it, so its clock differs in
        // the last bits between masters (k h or a running sum, libcosim's nanoseconds;
        // Ecos's bits differed), where the steps, and so the distance slid, are the
        // same. A step that ended early at a switch is divided by the time it advanced.
        let advanced = match switched {
            Some(at) if at < target => at - t_before,
            _ => size,
        };
        if advanced > 0.0 && after.time > t_before {
            running.mean_relative_velocity =
                self.settings.inputs.belt_speed - (after.tip_deflection - tip_before) / advanced;
        }
        // The switch time on the FMU's clock; a switch in the step landing on `to` ends
        // there exactly, as a step without one does.
        Ok(switched.map(|at| {
            if at == target {
                to
            } else {
                at + running.start_time
            }
        }))
    }

    fn external_friction(&self) -> ExternalFriction {
        let inputs = &self.settings.inputs;
        ExternalFriction {
            kinetic: match self.settings.coupling {
                ExternalCoupling::Magnitude => ExternalKinetic::Magnitude(inputs.kinetic_force),
                ExternalCoupling::Signed => ExternalKinetic::Signed {
                    force: inputs.friction_force,
                    slope: inputs.friction_slope,
                    velocity: inputs.sliding_velocity,
                },
                ExternalCoupling::Step => ExternalKinetic::Step {
                    force: inputs.friction_force,
                    slope: inputs.friction_slope,
                    step_force: inputs.step_force,
                    step_slope: inputs.step_slope,
                    velocity: inputs.sliding_velocity,
                },
                ExternalCoupling::Table => ExternalKinetic::Table(StepCurves {
                    force: inputs.table_force,
                    step_force: inputs.table_step_force,
                    velocity: inputs.sliding_velocity,
                    force_at_velocity: inputs.friction_force,
                    step_force_at_velocity: inputs.step_force,
                }),
            },
            // No set-valued stick under `table`: the tabulated curves hold the law's
            // force at and around v = 0, which holds the tip as the embedded law's does;
            // a stick at mu_s F_n (`external.static_limit`, NeuralFriction's for the
            // `step` coupling) ended the slip law's stick where the law's force holds
            // on: 0.152 mm, -2.8 % of period at h = 1e-3 s (docs/cosimulation.md).
            static_limit: match self.settings.coupling {
                ExternalCoupling::Table => 0.0,
                _ => inputs.static_limit,
            },
        }
    }

    /// Passes the current inputs to a running simulation.
    fn apply_inputs(&mut self) {
        let external = (self.settings.scene.friction.law == FrictionLawKind::External)
            .then(|| self.external_friction());
        let inputs = self.settings.inputs.clone();
        if let Some(running) = &mut self.running {
            let s = &mut running.simulator;
            s.set_belt_speed(inputs.belt_speed);
            s.set_normal_force(inputs.normal_force);
            s.set_external_friction(external);
            // After initialisation inputs only drive the steps to come. Before it, they
            // also shape the start (the quasi-static start moves at the belt speed), so
            // the simulation is rebuilt from them at fmi2ExitInitializationMode.
            if self.initialized {
                running.built_from.inputs = inputs;
            }
        }
    }

    fn sample(&self) -> Option<stickslip::simulation::Sample> {
        self.running.as_ref().map(|r| r.simulator.sample())
    }

    fn output(&self, read: fn(&stickslip::simulation::Sample) -> f64) -> f64 {
        self.sample().map(|s| read(&s)).unwrap_or(0.0)
    }
}
