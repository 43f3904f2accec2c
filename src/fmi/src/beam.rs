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
//!   laws such as the paper's plain network (see `stickslip::contact`, and the README's
//!   co-simulation section for the coupling errors).
//!
//! `fidelity.level = auto` is resolved by the `auto` module at
//! fmi2ExitInitializationMode.
//!
//! The FMU steps at `time.step` and ends each communication step with one shorter step
//! when the communication point is not on that grid (`Simulator::advance_to`).

use crate::model::{Model, ModelInfo};
use crate::networks::{weights_name, NetworkError, Networks, DEFAULT_WEIGHTS, WEIGHTS_RESOURCES};
use crate::variables::{
    choice_at, Access, Causality, ChoiceType, Dependencies, InitialDependencies, Variability,
    Variable,
};
use serde::{Deserialize, Serialize};
use std::path::Path;
use stickslip::auto::AutoError;
use stickslip::choice::Choice;
use stickslip::contact::ContactState;
use stickslip::friction::{CoulombLaw, ExponentialLaw};
use stickslip::neural::NeuralError;
use stickslip::scene::{
    CheckedScene, Clamp, FidelityLevel, FrictionLawKind, HoldingForce, Inference, InitialState,
    ModalBasis, Scene, SceneError, Scheme, SlidingVelocity,
};
use stickslip::simulation::{
    ExternalCoupling, ExternalFriction, ExternalKinetic, SimulationError, SimulationState,
    Simulator, RECENT_TRANSITIONS,
};
use stickslip::study::Configuration;

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
}

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

/// Why the simulation could not be built from the parameters (the `Model` methods log
/// the message).
#[derive(Debug, thiserror::Error)]
enum BuildError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Auto(#[from] AutoError),
    #[error(transparent)]
    Network(#[from] NetworkError),
    /// The weights are not a friction law of the beam (wrong features).
    #[error("friction.weights = {name}: {source}")]
    NotAFrictionLaw { name: String, source: NeuralError },
    #[error(transparent)]
    Simulation(#[from] SimulationError),
}

pub struct StickSlipBeam {
    settings: Settings,
    networks: Networks,
    /// The last `auto` choice: (scene it was calibrated on, configuration).
    auto_cache: Option<(Scene, Configuration)>,
    /// `auto` choices not yet logged.
    auto_log: Vec<String>,
    running: Option<Running>,
    /// fmi2ExitInitializationMode has built the simulation the steps use.
    initialized: bool,
}

impl StickSlipBeam {
    /// fmi2DoStep / fmi3DoStep: advances the simulation to `to` (s, FMU clock), or,
    /// with `stop_at_switch`, until the end of the internal step in which the contact
    /// switched, returning that time (see `Simulator::advance_until_switch`). Every
    /// transition made is listed in `events`.
    fn advance(
        &mut self,
        _from: f64,
        to: f64,
        stop_at_switch: bool,
        events: &mut Vec<String>,
    ) -> Result<Option<f64>, String> {
        let Some(running) = &mut self.running else {
            return Err("the simulation was not initialised".into());
        };
        let before = running.simulator.state().transition_count;
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

    /// How many networks this instance has read: zero unless a law needed one.
    pub fn networks_read(&self) -> usize {
        self.networks.read_count()
    }

    fn checked_scene(
        &mut self,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<CheckedScene, BuildError> {
        let mut scene = self.settings.scene.clone();
        let inputs = &self.settings.inputs;
        scene.loading.belt_speed = inputs.belt_speed;
        scene.loading.normal_force = inputs.normal_force;
        if let Some(stop) = stop_time {
            scene.time.end = (stop - start_time).max(scene.time.step);
        }
        if scene.fidelity.level == FidelityLevel::Auto {
            scene = self.auto_choice(&scene)?.apply(&scene);
        }
        Ok(scene.check()?)
    }

    /// The `auto` choice for `scene` at its tolerance, computed once per scene: the
    /// calibration runs the scene several times.
    fn auto_choice(&mut self, scene: &Scene) -> Result<Configuration, BuildError> {
        // The calibration runs stand alone, without this FMU's inputs: with the external
        // model they run the exponential law of the scene's coefficients instead. With
        // the neural law they run the network of friction.weights, the one this FMU
        // will run (not the scene's default, the shipped plain network).
        let mut calibrated = scene.clone();
        match calibrated.friction.law {
            FrictionLawKind::External => calibrated.friction.law = FrictionLawKind::Exponential,
            FrictionLawKind::Neural => {
                let path = self.networks.path_of(&self.settings.weights)?;
                calibrated.friction.weights = Some(path.to_string_lossy().into_owned());
            }
            FrictionLawKind::Exponential | FrictionLawKind::Coulomb => {}
        }
        if let Some((cached_scene, choice)) = &self.auto_cache {
            if *cached_scene == calibrated {
                return Ok(*choice);
            }
        }
        let front = stickslip::auto::paper_front()?;
        let mut progress = Vec::new();
        let choice = stickslip::auto::choose_cached(&calibrated, &front, &mut |line| {
            progress.push(line.to_string())
        });
        // The progress lines are logged whether or not a choice came of them.
        self.auto_log.append(&mut progress);
        let choice = choice?;
        let tolerance = stickslip::auto::tolerance_of(&calibrated);
        self.auto_log
            .push(stickslip::auto::describe(&choice, tolerance));
        self.auto_cache = Some((calibrated, choice.configuration));
        Ok(choice.configuration)
    }

    /// Builds the simulation unless it is already built from the current settings.
    fn ensure_running(
        &mut self,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<(), BuildError> {
        if let Some(running) = &self.running {
            if running.built_from == self.settings {
                return Ok(());
            }
        }
        let scene = self.checked_scene(start_time, stop_time)?;
        let external = scene.friction.law == FrictionLawKind::External;
        let law: Box<dyn stickslip::friction::FrictionLaw> = match scene.friction.law {
            FrictionLawKind::Neural => {
                let name = self.settings.weights.clone();
                let network = self.networks.get(&name)?.clone();
                let (inference, normal_force) =
                    (scene.friction.inference, scene.loading.normal_force);
                stickslip::neural::inference::friction_law(network, inference, normal_force)
                    .map_err(|source| BuildError::NotAFrictionLaw { name, source })?
            }
            // The inputs replace the law while the external model is on; the simulator
            // still holds a law, the exponential one of the scene's coefficients.
            FrictionLawKind::External => Box::new(ExponentialLaw::of(&scene.friction)),
            FrictionLawKind::Exponential => Box::new(ExponentialLaw::of(&scene.friction)),
            FrictionLawKind::Coulomb => Box::new(CoulombLaw {
                kinetic_coefficient: scene.friction.kinetic_coefficient,
            }),
        };
        let mut simulator = Simulator::new(scene, law)?;
        if external {
            simulator.set_external_friction(Some(self.external_friction()));
        }
        self.running = Some(Running {
            built_from: self.settings.clone(),
            simulator,
            start_time,
        });
        Ok(())
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
            },
            static_limit: inputs.static_limit,
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

macro_rules! real_parameter {
    ($vr:expr, $name:expr, $unit:expr, $description:expr, |$s:ident| $field:expr) => {
        Variable {
            name: $name,
            value_reference: $vr,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            description: $description,
            access: Access::Real {
                unit: $unit,
                get: |m: &StickSlipBeam| {
                    let $s = &m.settings.scene;
                    $field
                },
                set: Some(|m: &mut StickSlipBeam, v: f64| {
                    let $s = &mut m.settings.scene;
                    $field = v;
                    Ok(())
                }),
            },
            depends_on: None,
        }
    };
}

/// A scene field holding a choice `$choice`: its codes, words and the value's code are
/// all read off the choice.
macro_rules! enum_parameter {
    ($vr:expr, $name:expr, $choice:ty, $description:expr, |$s:ident| $field:expr) => {
        Variable {
            name: $name,
            value_reference: $vr,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            description: $description,
            access: Access::Choice {
                kind: ChoiceType::of::<$choice>(),
                get: |m: &StickSlipBeam| {
                    let $s = &m.settings.scene;
                    $field.code()
                },
                set: Some(|m: &mut StickSlipBeam, v: i32| {
                    let $s = &mut m.settings.scene;
                    $field = choice_at::<$choice>(v)?;
                    Ok(())
                }),
            },
            depends_on: None,
        }
    };
}

macro_rules! count_parameter {
    ($vr:expr, $name:expr, $max:expr, $description:expr, $field:ident) => {
        Variable {
            name: $name,
            value_reference: $vr,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            description: $description,
            access: Access::Integer {
                min: 1,
                max: $max,
                get: |m: &StickSlipBeam| m.settings.scene.fidelity.$field as i32,
                set: Some(|m: &mut StickSlipBeam, v: i32| {
                    m.settings.scene.fidelity.$field = v as usize;
                    Ok(())
                }),
            },
            depends_on: None,
        }
    };
}

/// A Real input in unit `$unit`, with an optional check of the value before it is
/// applied.
macro_rules! input {
    ($vr:expr, $name:expr, $unit:expr, $description:expr, $field:ident $(, $check:expr)?) => {
        Variable {
            name: $name,
            value_reference: $vr,
            causality: Causality::Input,
            variability: Variability::Continuous,
            description: $description,
            access: Access::Real {
                unit: Some($unit),
                get: |m: &StickSlipBeam| m.settings.inputs.$field,
                set: Some(|m: &mut StickSlipBeam, v: f64| {
                    $(
                        let check: fn(f64) -> Result<(), String> = $check;
                        check(v)?;
                    )?
                    m.settings.inputs.$field = v;
                    m.apply_inputs();
                    Ok(())
                }),
            },
            depends_on: None,
        }
    };
}

macro_rules! real_output {
    ($vr:expr, $name:expr, $unit:expr, $description:expr, $read:expr) => {
        Variable {
            name: $name,
            value_reference: $vr,
            causality: Causality::Output,
            variability: Variability::Continuous,
            description: $description,
            access: Access::Real {
                unit: Some($unit),
                get: |m: &StickSlipBeam| m.output($read),
                set: None,
            },
            depends_on: Some(BEAM_OUTPUT),
        }
    };
}

fn non_negative(v: f64) -> Result<(), String> {
    if v < 0.0 {
        Err(format!("{v} must be >= 0"))
    } else {
        Ok(())
    }
}

const BELT_SPEED: u32 = 100;
const NORMAL_FORCE: u32 = 101;

/// What every output of the beam depends on. An output is read off the simulation
/// state, which only fmi2DoStep advances: an input set at a communication point acts on
/// the steps to come, so no output follows an input directly (`dependencies=""`, no
/// direct feedthrough, so no algebraic loop with a friction FMU that feeds the
/// external inputs). In Initialization Mode an output is the start state, built from
/// the scene: every parameter, and the two inputs that are scene fields. The
/// quasi-static start moves at `belt_speed`; with `fidelity.level = auto` the
/// calibration runs the scene, `normal_force` included, and the model it picks shapes
/// the start. The external inputs do not enter the start.
const BEAM_OUTPUT: Dependencies = Dependencies {
    inputs: &[],
    initial: InitialDependencies::AllParametersAnd(&[BELT_SPEED, NORMAL_FORCE]),
};

static VARIABLES: &[Variable<StickSlipBeam>] = &[
    real_parameter!(1, "geometry.length", Some("m"), "Beam length L", |s| s
        .geometry
        .length),
    real_parameter!(2, "geometry.height", Some("m"), "Beam height h", |s| s
        .geometry
        .height),
    real_parameter!(
        3,
        "geometry.width",
        Some("m"),
        "Out-of-plane width b",
        |s| s.geometry.width
    ),
    real_parameter!(4, "material.density", Some("kg/m3"), "Density rho", |s| s
        .material
        .density),
    real_parameter!(
        5,
        "material.youngs_modulus",
        Some("Pa"),
        "Young's modulus E",
        |s| s.material.youngs_modulus
    ),
    real_parameter!(
        6,
        "material.poisson_ratio",
        None,
        "Poisson's ratio nu",
        |s| s.material.poisson_ratio
    ),
    enum_parameter!(
        10,
        "friction.law",
        FrictionLawKind,
        "Kinetic friction law",
        |s| s.friction.law
    ),
    real_parameter!(
        11,
        "friction.static_coefficient",
        None,
        "Static coefficient mu_s",
        |s| s.friction.static_coefficient
    ),
    real_parameter!(
        12,
        "friction.kinetic_coefficient",
        None,
        "Kinetic coefficient mu_k",
        |s| s.friction.kinetic_coefficient
    ),
    real_parameter!(
        13,
        "friction.decay",
        Some("s/m"),
        "Decay alpha of the exponential law",
        |s| s.friction.decay
    ),
    real_parameter!(
        14,
        "friction.stick_threshold",
        Some("m/s"),
        "Stick threshold eps on |v_rel|",
        |s| s.friction.stick_threshold
    ),
    Variable {
        name: "friction.weights",
        value_reference: 15,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        description:
            "Network weights for friction.law = neural: a file in resources/ or an absolute path",
        access: Access::String {
            get: |m: &StickSlipBeam| m.settings.weights.clone(),
            set: Some(|m: &mut StickSlipBeam, v: &str| {
                m.settings.weights = weights_name(v)?;
                Ok(())
            }),
        },
        depends_on: None,
    },
    Variable {
        name: "external.coupling",
        value_reference: 16,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        description: "friction.law = external: how the kinetic force is read from the inputs",
        access: Access::Choice {
            kind: ChoiceType::of::<ExternalCoupling>(),
            get: |m: &StickSlipBeam| m.settings.coupling.code(),
            set: Some(|m: &mut StickSlipBeam, v: i32| {
                m.settings.coupling = choice_at::<ExternalCoupling>(v)?;
                Ok(())
            }),
        },
        depends_on: None,
    },
    enum_parameter!(
        17,
        "friction.inference",
        Inference,
        "Evaluation of the network for friction.law = neural",
        |s| s.friction.inference
    ),
    enum_parameter!(
        20,
        "contact.holding_force",
        HoldingForce,
        "Stick holding force",
        |s| s.contact.holding_force
    ),
    enum_parameter!(
        21,
        "contact.sliding_velocity",
        SlidingVelocity,
        "Velocity argument of the law",
        |s| s.contact.sliding_velocity
    ),
    enum_parameter!(
        22,
        "contact.initial_state",
        InitialState,
        "State at t = 0",
        |s| s.contact.initial_state
    ),
    real_parameter!(
        30,
        "damping.mass_proportional",
        Some("1/s"),
        "Rayleigh damping a in C = a M + b K",
        |s| s.damping.mass_proportional
    ),
    real_parameter!(
        31,
        "damping.stiffness_proportional",
        Some("s"),
        "Rayleigh damping b in C = a M + b K",
        |s| s.damping.stiffness_proportional
    ),
    real_parameter!(
        40,
        "time.step",
        Some("s"),
        "Internal time step (the FMU sub-steps each communication step)",
        |s| s.time.step
    ),
    enum_parameter!(
        50,
        "fidelity.level",
        FidelityLevel,
        "Structural model; auto also picks the time step and integrator",
        |s| s.fidelity.level
    ),
    Variable {
        name: "fidelity.tolerance",
        value_reference: 57,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        description: "fidelity.level = auto: largest tip-deflection deviation allowed over the first stick-slip cycle",
        access: Access::Real {
            unit: Some("m"),
            // Some from the start value on; NaN stands for a tolerance never given.
            get: |m: &StickSlipBeam| m.settings.scene.fidelity.tolerance.unwrap_or(f64::NAN),
            set: Some(|m: &mut StickSlipBeam, v: f64| {
                if !(v.is_finite() && v > 0.0) {
                    return Err(format!("{v} must be finite and > 0"));
                }
                m.settings.scene.fidelity.tolerance = Some(v);
                Ok(())
            }),
        },
        depends_on: None,
    },
    count_parameter!(
        51,
        "fidelity.beam_elements",
        stickslip::scene::MAX_BEAM_ELEMENTS as i32,
        "Number of beam elements (beam level, and the modal level's beam basis)",
        beam_elements
    ),
    real_parameter!(
        52,
        "fidelity.element_size",
        Some("m"),
        "Plane-stress element size",
        |s| s.fidelity.element_size
    ),
    count_parameter!(
        53,
        "fidelity.modes",
        stickslip::scene::MAX_MODES as i32,
        "Number of modes of the modal level",
        modes
    ),
    enum_parameter!(
        54,
        "fidelity.modal_basis",
        ModalBasis,
        "Model whose modes the modal level keeps",
        |s| s.fidelity.modal_basis
    ),
    Variable {
        name: "fidelity.static_correction",
        value_reference: 55,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        description: "Add the static tip-load shape to the modal basis",
        access: Access::Boolean {
            get: |m: &StickSlipBeam| m.settings.scene.fidelity.static_correction,
            set: Some(|m: &mut StickSlipBeam, v: bool| {
                m.settings.scene.fidelity.static_correction = v;
                Ok(())
            }),
        },
        depends_on: None,
    },
    enum_parameter!(
        56,
        "fidelity.clamp",
        Clamp,
        "Support of the plane-stress mesh",
        |s| s.fidelity.clamp
    ),
    enum_parameter!(60, "integrator.scheme", Scheme, "Time integrator", |s| s
        .integrator
        .scheme),
    real_parameter!(
        61,
        "integrator.rho_inf",
        None,
        "Generalised-alpha spectral radius at infinite frequency",
        |s| s.integrator.rho_inf
    ),
    real_parameter!(62, "integrator.theta", None, "Moreau-Jean theta", |s| s
        .integrator
        .theta),
    // Any finite belt speed (either direction) is a valid input.
    input!(100, "belt_speed", "m/s", "Belt speed v_b", belt_speed),
    input!(
        NORMAL_FORCE,
        "normal_force",
        "N",
        "Normal force F_n",
        normal_force,
        non_negative
    ),
    input!(
        102,
        "external.kinetic_force",
        "N",
        "Kinetic friction force magnitude (friction.law = external)",
        kinetic_force,
        non_negative
    ),
    input!(
        103,
        "external.static_limit",
        "N",
        "Static limit, the largest holding force (friction.law = external)",
        static_limit,
        non_negative
    ),
    input!(
        104,
        "external.friction_force",
        "N",
        "Signed kinetic friction force F(v) at external.sliding_velocity (external.coupling = signed)",
        friction_force
    ),
    input!(
        105,
        "external.friction_slope",
        "N.s/m",
        "dF/dv at external.sliding_velocity (external.coupling = signed)",
        friction_slope
    ),
    input!(
        106,
        "external.sliding_velocity",
        "m/s",
        "Sliding velocity the friction model was evaluated at (external.coupling = signed)",
        sliding_velocity
    ),
    real_output!(
        200,
        "tip_deflection",
        "m",
        "Transverse tip deflection",
        |s| s.tip_deflection
    ),
    real_output!(201, "tip_velocity", "m/s", "Transverse tip velocity", |s| s
        .tip_velocity),
    real_output!(
        202,
        "relative_velocity",
        "m/s",
        "Sliding velocity v_rel = v_b - v_tip",
        |s| s.relative_velocity
    ),
    real_output!(
        203,
        "friction_force",
        "N",
        "Force of the contact on the tip",
        |s| s.friction_force
    ),
    real_output!(
        204,
        "holding_force",
        "N",
        "Force that stick needs (compared with the static limit)",
        |s| s.holding_force
    ),
    Variable {
        name: "stick",
        value_reference: 205,
        causality: Causality::Output,
        variability: Variability::Discrete,
        description: "True while the tip sticks to the belt",
        access: Access::Boolean {
            get: |m: &StickSlipBeam| m.sample().map(|s| s.stick).unwrap_or(true),
            set: None,
        },
        depends_on: Some(BEAM_OUTPUT),
    },
    Variable {
        name: "transitions",
        value_reference: 206,
        causality: Causality::Output,
        variability: Variability::Discrete,
        description: "Number of stick/slip transitions so far",
        access: Access::Integer {
            min: 0,
            max: i32::MAX,
            get: |m: &StickSlipBeam| {
                m.running
                    .as_ref()
                    .map(|r| r.simulator.state().transition_count.min(i32::MAX as u64) as i32)
                    .unwrap_or(0)
            },
            set: None,
        },
        depends_on: Some(BEAM_OUTPUT),
    },
];

impl Model for StickSlipBeam {
    const INFO: ModelInfo = ModelInfo {
        model_identifier: "StickSlipBeam",
        description: "Cantilever beam whose tip rides on a conveyor belt: stick-slip with an analytical, neural or external friction law (Vater, Stender and Hoffmann)",
        start_time: 0.0,
        stop_time: 1.2,
        step_size: 1e-3,
        resources: WEIGHTS_RESOURCES,
        returns_early_at_events: true,
    };

    fn variables() -> &'static [Variable<Self>] {
        VARIABLES
    }

    fn with_defaults() -> Self {
        Self {
            settings: Settings::default(),
            networks: Networks::default(),
            auto_cache: None,
            auto_log: Vec::new(),
            running: None,
            initialized: false,
        }
    }

    fn load_resources(&mut self, resources: &Path) -> Result<(), String> {
        self.networks.open(resources).map_err(|e| e.to_string())
    }

    fn reset(&mut self) {
        self.settings = Settings::default();
        self.running = None;
        self.initialized = false;
    }

    fn refresh_outputs(&mut self, start_time: f64, stop_time: Option<f64>) -> Result<(), String> {
        if !self.initialized {
            // Outputs asked for during initialisation: the state at the start time of
            // the current parameters and inputs.
            self.ensure_running(start_time, stop_time)
                .map_err(|e| e.to_string())?;
        }
        Ok(())
    }

    fn initialize(&mut self, start_time: f64, stop_time: Option<f64>) -> Result<(), String> {
        self.ensure_running(start_time, stop_time)
            .map_err(|e| e.to_string())?;
        if let Some(running) = &mut self.running {
            running.start_time = start_time;
        }
        self.initialized = true;
        Ok(())
    }

    fn do_step(&mut self, from: f64, to: f64, events: &mut Vec<String>) -> Result<(), String> {
        self.advance(from, to, false, events).map(|_| ())
    }

    fn do_step_until_event(
        &mut self,
        from: f64,
        to: f64,
        events: &mut Vec<String>,
    ) -> Result<Option<f64>, String> {
        self.advance(from, to, true, events)
    }

    fn take_notes(&mut self) -> Vec<String> {
        std::mem::take(&mut self.auto_log)
    }

    fn save(&self) -> serde_json::Value {
        let saved = Saved {
            settings: self.settings.clone(),
            initialized: self.initialized,
            running: self.running.as_ref().map(|r| SavedRun {
                built_from: r.built_from.clone(),
                start_time: r.start_time,
                state: r.simulator.state().clone(),
            }),
        };
        serde_json::to_value(saved).unwrap_or(serde_json::Value::Null)
    }

    fn restore(&mut self, saved: serde_json::Value, version: u32, time: f64) -> Result<(), String> {
        let malformed =
            |e: serde_json::Error| format!("saved StickSlipBeam state is malformed: {e}");
        let saved: Saved = match version {
            1 => Saved::try_from(serde_json::from_value::<SavedV1>(saved).map_err(malformed)?)?,
            2 => Saved::try_from(serde_json::from_value::<SavedV2>(saved).map_err(malformed)?)?,
            _ => serde_json::from_value(saved).map_err(malformed)?,
        };
        if let Some(run) = &saved.running {
            // fmi2DoStep lands the simulation exactly on each communication point, so the
            // two clocks agree to rounding; half a time step separates rounding from a
            // crafted gap that the next step would have to integrate through.
            let simulated = run.start_time + run.state.time;
            let half_step = 0.5 * run.built_from.scene.time.step;
            let agree = (simulated - time).abs() <= half_step;
            if !(simulated.is_finite() && half_step.is_finite() && agree) {
                return Err(format!(
                    "the state's simulation is at t = {simulated} s but its FMU time is {time} s; the two clocks must agree"
                ));
            }
        }
        let Some(run) = saved.running else {
            self.settings = saved.settings;
            self.running = None;
            self.initialized = false;
            return Ok(());
        };
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
