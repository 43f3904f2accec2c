//! StickSlipBeam: the scene's beam, contact and friction law as an FMU.
//!
//! Parameters are the scene's fields under the scene file's names (`geometry.length`,
//! `fidelity.level`, ...), checked together at fmi2ExitInitializationMode with the
//! scene's messages. The belt speed and normal force are inputs. `friction.model =
//! external` takes the kinetic force magnitude and the static limit from two more
//! inputs, held over each communication step, so that the beam can be coupled to
//! NeuralFriction.fmu or any other friction FMU.
//!
//! The FMU steps at `time.step` and ends each communication step with one shorter step
//! when the communication point is not on that grid (`Simulator::advance_to`).

use crate::networks::{weights_name, NetworkError, Networks, DEFAULT_WEIGHTS, WEIGHTS_RESOURCES};
use crate::variables::{Access, Causality, EnumerationType, Variability, Variable};
use crate::{Model, ModelInfo};
use serde::{Deserialize, Serialize};
use std::path::Path;
use stickslip::auto::AutoError;
use stickslip::contact::ContactState;
use stickslip::neural::NeuralError;
use stickslip::scene::{CheckedScene, FrictionLawKind, Scene, SceneError};
use stickslip::simulation::{ExternalFriction, SimulationError, SimulationState, Simulator};
use stickslip::study::Configuration;

/// Where the kinetic friction force comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrictionModel {
    Exponential,
    Coulomb,
    Neural,
    External,
}

/// Inputs of the beam (SI units).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BeamInputs {
    pub belt_speed: f64,
    pub normal_force: f64,
    pub kinetic_force: f64,
    pub static_limit: f64,
}

/// Everything set from outside: parameters and inputs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Settings {
    scene: Scene,
    friction_model: FrictionModel,
    weights: String,
    inputs: BeamInputs,
    /// fidelity.level = auto: the fidelity, time step and integrator of `scene` are
    /// replaced by the `auto` choice at fmi2ExitInitializationMode.
    #[serde(default)]
    fidelity_auto: bool,
    /// RMS tip-deflection error that `auto` must meet (m).
    #[serde(default = "default_fidelity_tolerance")]
    fidelity_tolerance: f64,
}

/// Default of fidelity.tolerance (m): 0.1 mm RMS, about 1 % of the paper scene's
/// deflection corridor.
fn default_fidelity_tolerance() -> f64 {
    1e-4
}

impl Default for Settings {
    fn default() -> Self {
        let scene = Scene::default();
        let f = &scene.friction;
        let inputs = BeamInputs {
            belt_speed: scene.loading.belt_speed,
            normal_force: scene.loading.normal_force,
            kinetic_force: f.kinetic_coefficient * scene.loading.normal_force,
            static_limit: f.static_coefficient * scene.loading.normal_force,
        };
        Self {
            scene,
            friction_model: FrictionModel::Exponential,
            weights: DEFAULT_WEIGHTS.into(),
            inputs,
            fidelity_auto: false,
            fidelity_tolerance: default_fidelity_tolerance(),
        }
    }
}

/// The running simulation and the settings it was built from.
struct Running {
    built_from: Settings,
    simulator: Simulator,
    /// Time (s) at which the simulation's t = 0 lies.
    start_time: f64,
    transitions_reported: usize,
}

/// Saved form (FMU state).
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
    transitions: Vec<stickslip::contact::Transition>,
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
    #[error("no analytical law for this scene")]
    NoAnalyticalLaw,
    #[error(transparent)]
    Simulation(#[from] SimulationError),
}

pub struct StickSlipBeam {
    settings: Settings,
    networks: Networks,
    /// The last `auto` choice: (scene, tolerance, configuration).
    auto_cache: Option<(Scene, f64, Configuration)>,
    /// `auto` choices not yet logged.
    auto_log: Vec<String>,
    running: Option<Running>,
    /// fmi2ExitInitializationMode has built the simulation the steps use.
    initialized: bool,
}

impl StickSlipBeam {
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
        scene.friction.law = match self.settings.friction_model {
            FrictionModel::Coulomb => FrictionLawKind::Coulomb,
            FrictionModel::Neural => FrictionLawKind::Neural,
            // The external model replaces the law; the exponential parameters stay checked.
            FrictionModel::Exponential | FrictionModel::External => FrictionLawKind::Exponential,
        };
        if let Some(stop) = stop_time {
            scene.time.end = (stop - start_time).max(scene.time.step);
        }
        if self.settings.fidelity_auto {
            scene.clone().check()?;
            scene = self.auto_choice(&scene)?.apply(&scene);
        }
        Ok(scene.check()?)
    }

    /// The `auto` choice for `scene`, computed once per scene and tolerance: the
    /// calibration runs the scene several times.
    fn auto_choice(&mut self, scene: &Scene) -> Result<Configuration, BuildError> {
        let tolerance = self.settings.fidelity_tolerance;
        if let Some((cached_scene, cached_tolerance, choice)) = &self.auto_cache {
            if cached_scene == scene && *cached_tolerance == tolerance {
                return Ok(*choice);
            }
        }
        let front = stickslip::auto::paper_front()?;
        let choice = stickslip::auto::choose(scene, tolerance, &front)?;
        self.auto_log
            .push(stickslip::auto::describe(&choice, tolerance));
        self.auto_cache = Some((scene.clone(), tolerance, choice.configuration));
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
        let law: Box<dyn stickslip::friction::FrictionLaw> = match self.settings.friction_model {
            FrictionModel::Neural => {
                let name = self.settings.weights.clone();
                self.networks
                    .get(&name)?
                    .clone()
                    .into_friction_law()
                    .map_err(|source| BuildError::NotAFrictionLaw { name, source })?
            }
            _ => stickslip::friction::analytical_law(&scene).ok_or(BuildError::NoAnalyticalLaw)?,
        };
        let mut simulator = Simulator::new(scene, law)?;
        if self.settings.friction_model == FrictionModel::External {
            simulator.set_external_friction(Some(self.external_friction()));
        }
        self.running = Some(Running {
            built_from: self.settings.clone(),
            simulator,
            start_time,
            transitions_reported: 0,
        });
        Ok(())
    }

    fn external_friction(&self) -> ExternalFriction {
        ExternalFriction {
            kinetic_force: self.settings.inputs.kinetic_force,
            static_limit: self.settings.inputs.static_limit,
        }
    }

    /// Passes the current inputs to a running simulation.
    fn apply_inputs(&mut self) {
        let external = (self.settings.friction_model == FrictionModel::External)
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
        }
    };
}

macro_rules! enum_parameter {
    ($vr:expr, $name:expr, $kind:expr, $description:expr, |$s:ident| $field:expr) => {
        Variable {
            name: $name,
            value_reference: $vr,
            causality: Causality::Parameter,
            variability: Variability::Fixed,
            description: $description,
            access: Access::Enumeration {
                kind: $kind,
                get: |m: &StickSlipBeam| {
                    let $s = &m.settings.scene;
                    $kind.value_of(&$field)
                },
                set: Some(|m: &mut StickSlipBeam, v: i32| {
                    let $s = &mut m.settings.scene;
                    $field = $kind.parse(v)?;
                    Ok(())
                }),
            },
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
        }
    };
}

macro_rules! input {
    ($vr:expr, $name:expr, $description:expr, $field:ident, $check:expr) => {
        Variable {
            name: $name,
            value_reference: $vr,
            causality: Causality::Input,
            variability: Variability::Continuous,
            description: $description,
            access: Access::Real {
                unit: Some(if $vr == BELT_SPEED { "m/s" } else { "N" }),
                get: |m: &StickSlipBeam| m.settings.inputs.$field,
                set: Some(|m: &mut StickSlipBeam, v: f64| {
                    let check: fn(f64) -> Result<(), String> = $check;
                    check(v)?;
                    m.settings.inputs.$field = v;
                    m.apply_inputs();
                    Ok(())
                }),
            },
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

pub static FRICTION_MODEL: EnumerationType = EnumerationType {
    name: "FrictionModel",
    description: "Where the kinetic friction force comes from",
    items: &[
        (
            "exponential",
            "mu(v) = mu_k + (mu_s - mu_k) exp(-alpha |v|) (paper, Eq. 6)",
        ),
        ("coulomb", "mu = mu_k"),
        ("neural", "the network in friction.weights"),
        (
            "external",
            "inputs external.kinetic_force and external.static_limit",
        ),
    ],
};

pub static HOLDING_FORCE: EnumerationType = EnumerationType {
    name: "HoldingForce",
    description: "How the stick holding force is obtained",
    items: &[
        ("reaction", "the constraint reaction of the discrete model"),
        ("euler-bernoulli", "paper-literal: 3 EI delta / L^3"),
    ],
};

pub static SLIDING_VELOCITY: EnumerationType = EnumerationType {
    name: "SlidingVelocity",
    description: "The velocity the friction law is evaluated at",
    items: &[
        ("relative", "v_rel = v_b - v_tip"),
        ("tip", "paper-literal: |v_tip| with the sign of v_rel"),
    ],
};

pub static INITIAL_STATE: EnumerationType = EnumerationType {
    name: "InitialState",
    description: "The state at t = 0",
    items: &[
        (
            "quasi-static",
            "tip moving with the belt, beam in its static shape",
        ),
        ("at-rest", "beam at rest"),
    ],
};

pub static FIDELITY_LEVEL: EnumerationType = EnumerationType {
    name: "FidelityLevel",
    description: "Structural model",
    items: &[
        ("modal", "reduced modal model"),
        ("beam", "Euler-Bernoulli beam elements"),
        (
            "plane-stress",
            "2D plane-stress mesh of 8-node quadrilaterals",
        ),
        (
            "auto",
            "the cheapest measured configuration that meets fidelity.tolerance on this scene",
        ),
    ],
};

pub static MODAL_BASIS: EnumerationType = EnumerationType {
    name: "ModalBasis",
    description: "The model whose modes the modal level keeps",
    items: &[
        ("beam", "beam elements"),
        ("plane-stress", "plane-stress mesh"),
    ],
};

pub static CLAMP: EnumerationType = EnumerationType {
    name: "Clamp",
    description: "Support of the plane-stress mesh at x = 0",
    items: &[
        (
            "neutral-axis",
            "transverse displacement fixed on the neutral axis only",
        ),
        ("full", "every node of the clamped face fixed"),
    ],
};

pub static SCHEME: EnumerationType = EnumerationType {
    name: "Scheme",
    description: "Time integrator",
    items: &[
        ("generalized-alpha", "Chung-Hulbert generalised-alpha"),
        ("moreau-jean", "Moreau-Jean theta time-stepping"),
    ],
};

const BELT_SPEED: u32 = 100;

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
    Variable {
        name: "friction.model",
        value_reference: 10,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        description: "Kinetic friction model",
        access: Access::Enumeration {
            kind: &FRICTION_MODEL,
            get: |m: &StickSlipBeam| FRICTION_MODEL.value_of(&m.settings.friction_model),
            set: Some(|m: &mut StickSlipBeam, v: i32| {
                m.settings.friction_model = FRICTION_MODEL.parse(v)?;
                Ok(())
            }),
        },
    },
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
            "Network weights for friction.model = neural: a file in resources/ or an absolute path",
        access: Access::String {
            get: |m: &StickSlipBeam| m.settings.weights.clone(),
            set: Some(|m: &mut StickSlipBeam, v: &str| {
                m.settings.weights = weights_name(v)?;
                Ok(())
            }),
        },
    },
    enum_parameter!(
        20,
        "contact.holding_force",
        &HOLDING_FORCE,
        "Stick holding force",
        |s| s.contact.holding_force
    ),
    enum_parameter!(
        21,
        "contact.sliding_velocity",
        &SLIDING_VELOCITY,
        "Velocity argument of the law",
        |s| s.contact.sliding_velocity
    ),
    enum_parameter!(
        22,
        "contact.initial_state",
        &INITIAL_STATE,
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
    Variable {
        name: "fidelity.level",
        value_reference: 50,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        description: "Structural model; auto also picks the time step and integrator",
        access: Access::Enumeration {
            kind: &FIDELITY_LEVEL,
            get: |m: &StickSlipBeam| {
                if m.settings.fidelity_auto {
                    FIDELITY_LEVEL.items.len() as i32
                } else {
                    FIDELITY_LEVEL.value_of(&m.settings.scene.fidelity.level)
                }
            },
            set: Some(|m: &mut StickSlipBeam, v: i32| {
                if FIDELITY_LEVEL.item(v)? == "auto" {
                    m.settings.fidelity_auto = true;
                } else {
                    m.settings.scene.fidelity.level = FIDELITY_LEVEL.parse(v)?;
                    m.settings.fidelity_auto = false;
                }
                Ok(())
            }),
        },
    },
    Variable {
        name: "fidelity.tolerance",
        value_reference: 57,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        description: "fidelity.level = auto: RMS tip-deflection error allowed over the run",
        access: Access::Real {
            unit: Some("m"),
            get: |m: &StickSlipBeam| m.settings.fidelity_tolerance,
            set: Some(|m: &mut StickSlipBeam, v: f64| {
                if !(v.is_finite() && v > 0.0) {
                    return Err(format!("{v} must be finite and > 0"));
                }
                m.settings.fidelity_tolerance = v;
                Ok(())
            }),
        },
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
        10_000,
        "Number of modes of the modal level",
        modes
    ),
    enum_parameter!(
        54,
        "fidelity.modal_basis",
        &MODAL_BASIS,
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
    },
    enum_parameter!(
        56,
        "fidelity.clamp",
        &CLAMP,
        "Support of the plane-stress mesh",
        |s| s.fidelity.clamp
    ),
    enum_parameter!(60, "integrator.scheme", &SCHEME, "Time integrator", |s| s
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
    input!(
        BELT_SPEED,
        "belt_speed",
        "Belt speed v_b",
        belt_speed,
        |v| {
            let _ = v;
            Ok(())
        }
    ),
    input!(
        101,
        "normal_force",
        "Normal force F_n",
        normal_force,
        non_negative
    ),
    input!(
        102,
        "external.kinetic_force",
        "Kinetic friction force magnitude (friction.model = external)",
        kinetic_force,
        non_negative
    ),
    input!(
        103,
        "external.static_limit",
        "Static limit, the largest holding force (friction.model = external)",
        static_limit,
        non_negative
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

    fn do_step(&mut self, _from: f64, to: f64, events: &mut Vec<String>) -> Result<(), String> {
        let Some(running) = &mut self.running else {
            return Err("the simulation was not initialised".into());
        };
        let result = running.simulator.advance_to(to - running.start_time);
        let transitions = running.simulator.transitions();
        for t in &transitions[running.transitions_reported.min(transitions.len())..] {
            let to_state = match t.to {
                ContactState::Stick => "stick",
                ContactState::Slip => "slip",
            };
            events.push(format!(
                "t = {:.6} s: {to_state}",
                t.time + running.start_time
            ));
        }
        running.transitions_reported = transitions.len();
        result.map_err(|e| e.to_string())
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
                transitions: r.simulator.transitions().to_vec(),
            }),
        };
        serde_json::to_value(saved).unwrap_or(serde_json::Value::Null)
    }

    fn restore(&mut self, saved: serde_json::Value, time: f64) -> Result<(), String> {
        let saved: Saved = serde_json::from_value(saved)
            .map_err(|e| format!("saved StickSlipBeam state is malformed: {e}"))?;
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
                && r.built_from.friction_model == run.built_from.friction_model
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
                .restore(run.state, run.transitions)
                .map_err(|e| e.to_string())?;
            running.start_time = run.start_time;
            running.transitions_reported = running.simulator.transitions().len();
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
