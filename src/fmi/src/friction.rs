//! NeuralFriction: the friction law alone, as an FMU to couple with StickSlipBeam (or
//! anything else that needs a friction force).
//!
//! The outputs follow the inputs directly: they are evaluated when read. A law with
//! state (`law = lugre`, `rate-and-state`, or the learned law with memory: weights of
//! format `stickslip-state-friction`) also integrates its state over each
//! communication step (`memory`), the outputs are evaluated at the committed state, and
//! the state is an output (`state_outputs`). A
//! network's features are filled by role: the one with role sliding_velocity from
//! `sliding_velocity`, normal_force from `normal_force`, and any further features, in
//! the order the weights file lists them, from `extra_feature[1]` ... `extra_feature[4]`
//! (in FMI 3.0 the four elements of the array variable `extra_feature`).
//! Inputs are clamped to the network's training range (see `neural`).
//!
//! Besides the force, its slope dF/dv at the input (`friction_force_slope`, by
//! forward-mode differentiation of the network, or the exponential law's closed form)
//! and the velocity it was evaluated at (`evaluated_velocity`) are outputs: together
//! they are the law's tangent, which StickSlipBeam's `external.coupling = signed` solves
//! within its internal steps (see `stickslip::contact`).

use crate::declare::{
    choice_parameter, non_negative, real_input, real_output, real_parameter, weights_parameter,
    with_memory_law_parameters, LUGRE_PARAMETERS, RATE_STATE_PARAMETERS,
};
use crate::model::{Model, ModelInfo, PartialDerivatives};
use crate::networks::{NetworkError, Networks, DEFAULT_WEIGHTS, WEIGHTS_RESOURCES};
use crate::variables::{
    ArrayVariable, Dependencies, DependencyKind, InitialDependencies, Variable,
};
use serde::{Deserialize, Serialize};
use std::path::Path;
use stickslip::friction::{ExponentialLaw, FrictionLaw, LawChoice};
use stickslip::memory::parameters::{LuGreParameters, RateStateParameters};
use stickslip::memory::{MemoryLaw, STATE_VARIABLES};
use stickslip::neural::{FeatureRole, NeuralError, NeuralModel};
use stickslip::scene::{Scene, SceneError};

mod derivatives;
mod memory;
mod state_outputs;

use state_outputs::STATE_OUTPUT;

/// How many features beyond velocity and normal force a network may have.
pub const EXTRA_FEATURES: usize = 4;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct Settings {
    law: LawChoice,
    static_coefficient: f64,
    kinetic_coefficient: f64,
    decay: f64,
    weights: String,
    /// Absent from states saved before `law = lugre` existed: the defaults.
    #[serde(default)]
    lugre: LuGreParameters,
    /// As `lugre`.
    #[serde(default)]
    rate_and_state: RateStateParameters,
    sliding_velocity: f64,
    normal_force: f64,
    extra_features: [f64; EXTRA_FEATURES],
}

impl Settings {
    /// The value of input `vr` (one of the inputs' value references).
    fn input(&self, vr: u32) -> f64 {
        match vr {
            SLIDING_VELOCITY => self.sliding_velocity,
            NORMAL_FORCE => self.normal_force,
            _ => EXTRA_FEATURE
                .iter()
                .position(|&e| e == vr)
                .map_or(f64::NAN, |j| self.extra_features[j]),
        }
    }
}

/// The input (value reference) that feeds each of the network's features, in feature
/// order: by role, and the further features from `extra_feature[1]` on.
fn feature_inputs(model: &NeuralModel, weights: &str) -> Result<Vec<u32>, EvaluateError> {
    let velocity = model.feature_with_role(FeatureRole::SlidingVelocity);
    let normal = model.feature_with_role(FeatureRole::NormalForce);
    let mut extra = EXTRA_FEATURE.iter();
    (0..model.features.len())
        .map(|k| {
            if Some(k) == velocity {
                Ok(SLIDING_VELOCITY)
            } else if Some(k) == normal {
                Ok(NORMAL_FORCE)
            } else {
                extra
                    .next()
                    .copied()
                    .ok_or_else(|| EvaluateError::TooManyFeatures {
                        weights: weights.to_owned(),
                    })
            }
        })
        .collect()
}

impl Default for Settings {
    fn default() -> Self {
        let scene = Scene::default();
        Self {
            law: LawChoice::Neural,
            static_coefficient: scene.friction.static_coefficient,
            kinetic_coefficient: scene.friction.kinetic_coefficient,
            decay: scene.friction.decay,
            weights: DEFAULT_WEIGHTS.into(),
            lugre: scene.friction.lugre,
            rate_and_state: scene.friction.rate_and_state,
            sliding_velocity: 0.0,
            normal_force: scene.loading.normal_force,
            extra_features: [0.0; EXTRA_FEATURES],
        }
    }
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Outputs {
    force: f64,
    /// dF/dv (N s/m) at `velocity`.
    slope: f64,
    /// The sliding velocity (m/s) the outputs were evaluated at.
    velocity: f64,
    coefficient: f64,
    static_limit: f64,
    /// The law's state, one entry per `STATE_VARIABLES` (0 for those it has not).
    state: [f64; STATE_VARIABLES.len()],
}

/// Why the outputs could not be evaluated (the `Model` methods log the message).
#[derive(Debug, thiserror::Error)]
enum EvaluateError {
    #[error(transparent)]
    Network(#[from] NetworkError),
    /// A parameter or a restored law state that the law refuses.
    #[error("{0}")]
    Parameter(String),
    #[error("weights {weights} have more than {EXTRA_FEATURES} features besides sliding velocity and normal force")]
    TooManyFeatures { weights: String },
    #[error("weights {weights}: {source}")]
    Evaluation {
        weights: String,
        source: NeuralError,
    },
    /// A partial derivative (output, input by value reference) that is not finite.
    #[error("the partial derivative of value reference {output} with respect to value reference {input} is {value}")]
    NonFiniteDerivative { output: u32, input: u32, value: f64 },
    /// A law state that a step made non-finite.
    #[error("the friction law's state is not finite ({state}) after a step at sliding_velocity = {sliding_velocity} m/s")]
    NonFiniteState { sliding_velocity: f64, state: f64 },
    /// Inputs (m/s, N) at which the law gives a non-finite force.
    #[error("the outputs are not finite at sliding_velocity = {sliding_velocity} m/s, normal_force = {normal_force} N (force {force}, slope {slope}, coefficient {coefficient}, static limit {static_limit})")]
    NonFiniteOutputs {
        sliding_velocity: f64,
        normal_force: f64,
        force: f64,
        slope: f64,
        coefficient: f64,
        static_limit: f64,
    },
}

pub struct NeuralFriction {
    settings: Settings,
    networks: Networks,
    outputs: Outputs,
    scratch: Vec<f64>,
    /// The partial derivatives last computed and the settings and law state they hold
    /// for: an
    /// importer asks column by column, one input at a time, at the same inputs.
    derivatives_at: Option<(Settings, Vec<f64>, PartialDerivatives)>,
    /// The law with state last built (`memory`).
    built: Option<(Settings, Box<dyn MemoryLaw>)>,
    /// The committed state of a law with state (`memory`); empty otherwise.
    law_state: Vec<f64>,
    /// Where the model is (s): the start time, then the end of the last step.
    time: f64,
}

impl NeuralFriction {
    /// Checks the analytical parameters with the scene's rules and messages.
    fn check(&self) -> Result<(), SceneError> {
        let mut scene = Scene::default();
        let s = &self.settings;
        scene.friction.static_coefficient = s.static_coefficient;
        scene.friction.kinetic_coefficient = s.kinetic_coefficient;
        scene.friction.decay = s.decay;
        scene.friction.lugre = s.lugre.clone();
        scene.friction.rate_and_state = s.rate_and_state.clone();
        scene.loading.normal_force = s.normal_force;
        scene.check().map(|_| ())
    }

    fn evaluate(&mut self) -> Result<Outputs, EvaluateError> {
        let s = self.settings.clone();
        let mut state = [0.0; STATE_VARIABLES.len()];
        let (force, slope) = match s.law {
            LawChoice::Exponential => {
                let mut law = ExponentialLaw {
                    static_coefficient: s.static_coefficient,
                    kinetic_coefficient: s.kinetic_coefficient,
                    decay: s.decay,
                };
                (
                    law.sliding_force(s.sliding_velocity, s.normal_force),
                    law.slope(s.sliding_velocity, s.normal_force),
                )
            }
            LawChoice::Neural | LawChoice::Lugre | LawChoice::RateAndState => 'memory: {
                if let Some((jacobian, values)) = self.state_jacobian()? {
                    state = values;
                    break 'memory (jacobian.force, jacobian.slope);
                }
                let mut features = std::mem::take(&mut self.scratch);
                // Never shared (this model hands its networks to no one), so evaluated in
                // place, with the network's own scratch buffers.
                let network = std::sync::Arc::make_mut(self.networks.get(&s.weights)?);
                features.clear();
                for input in feature_inputs(network.model(), &s.weights)? {
                    features.push(s.input(input));
                }
                // A network without a velocity feature does not depend on it: slope 0.
                let evaluated = network.evaluate_with_velocity_slope(&features);
                self.scratch = features;
                evaluated.map_err(|source| EvaluateError::Evaluation {
                    weights: s.weights,
                    source,
                })?
            }
        };
        let outputs = Outputs {
            force,
            slope,
            velocity: s.sliding_velocity,
            coefficient: if s.normal_force > 0.0 {
                force.abs() / s.normal_force
            } else {
                0.0
            },
            static_limit: s.static_coefficient * s.normal_force,
            state,
        };
        if ![
            outputs.force,
            outputs.slope,
            outputs.velocity,
            outputs.coefficient,
            outputs.static_limit,
        ]
        .iter()
        .chain(&outputs.state)
        .all(|x| x.is_finite())
        {
            return Err(EvaluateError::NonFiniteOutputs {
                sliding_velocity: s.sliding_velocity,
                normal_force: s.normal_force,
                force: outputs.force,
                slope: outputs.slope,
                coefficient: outputs.coefficient,
                static_limit: outputs.static_limit,
            });
        }
        Ok(outputs)
    }
}

const LAW: u32 = 1;
const STATIC_COEFFICIENT: u32 = 2;
const KINETIC_COEFFICIENT: u32 = 3;
const DECAY: u32 = 4;
const WEIGHTS: u32 = 5;
const SLIDING_VELOCITY: u32 = 10;
const NORMAL_FORCE: u32 = 11;
/// extra_feature[1] ... extra_feature[4].
const EXTRA_FEATURE: [u32; EXTRA_FEATURES] = [12, 13, 14, 15];
const FRICTION_FORCE: u32 = 20;
const FRICTION_FORCE_MAGNITUDE: u32 = 21;
const FRICTION_COEFFICIENT: u32 = 22;
const STATIC_LIMIT_OUTPUT: u32 = 23;
const FRICTION_FORCE_SLOPE: u32 = 24;
const EVALUATED_VELOCITY_OUTPUT: u32 = 25;
/// The FMI 3.0 array `extra_feature` of those four: a value reference of its own (16,
/// free in both descriptions), so that 12 means `extra_feature[1]` in FMI 2.0 and
/// nothing in FMI 3.0, never the whole array.
pub const EXTRA_FEATURE_ARRAY: u32 = 16;

/// NeuralFriction's FMI 3.0 arrays: the extra features.
static ARRAYS: &[ArrayVariable] = &[ArrayVariable {
    name: "extra_feature",
    value_reference: EXTRA_FEATURE_ARRAY,
    description: "Network features besides velocity and normal force, in the order the weights file lists them, if any",
    elements: &EXTRA_FEATURE,
}];

/// What the force, its magnitude and the coefficient depend on: the law is evaluated
/// from the inputs when an output is read, so every input it may read reaches them
/// directly, with no particular structure (the law is nonlinear in each). The network
/// reads the extra features it has (none for the shipped ones, up to four), the
/// exponential law none: the dependencies are those of any law the parameters can
/// choose. In Initialization Mode also the parameters of the laws.
const LAW_OUTPUT: Dependencies = Dependencies {
    inputs: &[
        (SLIDING_VELOCITY, DependencyKind::Dependent),
        (NORMAL_FORCE, DependencyKind::Dependent),
        (EXTRA_FEATURE[0], DependencyKind::Dependent),
        (EXTRA_FEATURE[1], DependencyKind::Dependent),
        (EXTRA_FEATURE[2], DependencyKind::Dependent),
        (EXTRA_FEATURE[3], DependencyKind::Dependent),
    ],
    initial: InitialDependencies::InputsAnd(&[
        LAW,
        STATIC_COEFFICIENT,
        KINETIC_COEFFICIENT,
        DECAY,
        WEIGHTS,
        // sigma1, sigma2; a, V_0, mu_0: the laws with state at their initial state.
        // sigma0 acts through z only (z = 0 at the start), and b, D_c and the
        // evolution law through theta, where b ln(V_0 theta / D_c) = 0 at the initial
        // theta = D_c / V_0 (to rounding): they reach the outputs in the steps.
        LUGRE_PARAMETERS[1],
        LUGRE_PARAMETERS[2],
        RATE_STATE_PARAMETERS[0],
        RATE_STATE_PARAMETERS[3],
        RATE_STATE_PARAMETERS[4],
    ]),
};

/// The velocity the outputs were evaluated at: the input itself.
const EVALUATED_VELOCITY: Dependencies = Dependencies {
    inputs: &[(SLIDING_VELOCITY, DependencyKind::Constant)],
    initial: InitialDependencies::InputsAnd(&[]),
};

/// The static limit mu_s F_n: the normal force times a fixed parameter.
const STATIC_LIMIT: Dependencies = Dependencies {
    inputs: &[(NORMAL_FORCE, DependencyKind::Fixed)],
    initial: InitialDependencies::InputsAnd(&[STATIC_COEFFICIENT]),
};

/// What the state outputs depend on. The state moves only in a step, so no input
/// reaches them directly. In Initialization Mode they hold the initial state: z = 0
/// and psi = 0 whatever the parameters, theta = D_c / V_0 with `law = rate-and-state`
/// (and 0 with any other law).
const STATE_OUTPUT_DEPENDS_ON: [Dependencies; STATE_VARIABLES.len()] = [
    Dependencies {
        inputs: &[],
        initial: InitialDependencies::InputsAnd(&[]),
    },
    Dependencies {
        inputs: &[],
        initial: InitialDependencies::InputsAnd(&[
            LAW,
            // D_c and V_0.
            RATE_STATE_PARAMETERS[2],
            RATE_STATE_PARAMETERS[3],
        ]),
    },
    Dependencies {
        inputs: &[],
        initial: InitialDependencies::InputsAnd(&[]),
    },
];

static VARIABLES: &[Variable<NeuralFriction>] = &with_memory_law_parameters!(
    "law",
    |m: NeuralFriction| m.settings.lugre, m.settings.rate_and_state;
    [
    choice_parameter!(
        LAW,
        "law",
        LawChoice,
        "Friction law: the network, the analytical law for comparison, or a law with state",
        |m: NeuralFriction| m.settings.law
    ),
    real_parameter!(
        STATIC_COEFFICIENT,
        "static_coefficient",
        None,
        "Static coefficient mu_s (static limit; exponential law)",
        |m: NeuralFriction| m.settings.static_coefficient
    ),
    real_parameter!(
        KINETIC_COEFFICIENT,
        "kinetic_coefficient",
        None,
        "Kinetic coefficient mu_k (exponential law)",
        |m: NeuralFriction| m.settings.kinetic_coefficient
    ),
    real_parameter!(
        DECAY,
        "decay",
        Some("s/m"),
        "Decay alpha (exponential law)",
        |m: NeuralFriction| m.settings.decay
    ),
    weights_parameter!(
        WEIGHTS,
        "weights",
        "Network weights: a file in resources/ or an absolute path",
        |m: NeuralFriction| m.settings.weights
    ),
    ]
    [
    real_input!(
        SLIDING_VELOCITY,
        "sliding_velocity",
        Some("m/s"),
        "Sliding velocity v_rel = v_b - v_tip",
        |m: NeuralFriction| m.settings.sliding_velocity
    ),
    real_input!(
        NORMAL_FORCE,
        "normal_force",
        Some("N"),
        "Normal force F_n",
        |m: NeuralFriction| m.settings.normal_force,
        check = non_negative
    ),
    real_input!(
        EXTRA_FEATURE[0],
        "extra_feature[1]",
        None,
        "First network feature besides velocity and normal force, if any",
        |m: NeuralFriction| m.settings.extra_features[0]
    ),
    real_input!(
        EXTRA_FEATURE[1],
        "extra_feature[2]",
        None,
        "Second further network feature, if any",
        |m: NeuralFriction| m.settings.extra_features[1]
    ),
    real_input!(
        EXTRA_FEATURE[2],
        "extra_feature[3]",
        None,
        "Third further network feature, if any",
        |m: NeuralFriction| m.settings.extra_features[2]
    ),
    real_input!(
        EXTRA_FEATURE[3],
        "extra_feature[4]",
        None,
        "Fourth further network feature, if any",
        |m: NeuralFriction| m.settings.extra_features[3]
    ),
    real_output!(
        FRICTION_FORCE,
        "friction_force",
        Some("N"),
        "Kinetic friction force, signed: positive for positive sliding velocity",
        LAW_OUTPUT,
        |m: NeuralFriction| m.outputs.force
    ),
    real_output!(
        FRICTION_FORCE_MAGNITUDE,
        "friction_force_magnitude",
        Some("N"),
        "Magnitude of the kinetic friction force",
        LAW_OUTPUT,
        |m: NeuralFriction| m.outputs.force.abs()
    ),
    real_output!(
        FRICTION_COEFFICIENT,
        "friction_coefficient",
        None,
        "|friction_force| / normal_force (0 when normal_force = 0)",
        LAW_OUTPUT,
        |m: NeuralFriction| m.outputs.coefficient
    ),
    real_output!(
        STATIC_LIMIT_OUTPUT,
        "static_limit",
        Some("N"),
        "Static limit mu_s F_n",
        STATIC_LIMIT,
        |m: NeuralFriction| m.outputs.static_limit
    ),
    real_output!(
        FRICTION_FORCE_SLOPE,
        "friction_force_slope",
        Some("N.s/m"),
        "dF/dv of friction_force at sliding_velocity (the exponential law: beside its jump at 0)",
        LAW_OUTPUT,
        |m: NeuralFriction| m.outputs.slope
    ),
    real_output!(
        EVALUATED_VELOCITY_OUTPUT,
        "evaluated_velocity",
        Some("m/s"),
        "The sliding_velocity the outputs were evaluated at: where friction_force and its slope hold",
        EVALUATED_VELOCITY,
        |m: NeuralFriction| m.outputs.velocity
    ),
    real_output!(
        STATE_OUTPUT[0],
        STATE_VARIABLES[0].name,
        state_outputs::unit(&STATE_VARIABLES[0]),
        state_outputs::DESCRIPTION[0],
        STATE_OUTPUT_DEPENDS_ON[0],
        |m: NeuralFriction| m.outputs.state[0]
    ),
    real_output!(
        STATE_OUTPUT[1],
        STATE_VARIABLES[1].name,
        state_outputs::unit(&STATE_VARIABLES[1]),
        state_outputs::DESCRIPTION[1],
        STATE_OUTPUT_DEPENDS_ON[1],
        |m: NeuralFriction| m.outputs.state[1]
    ),
    real_output!(
        STATE_OUTPUT[2],
        STATE_VARIABLES[2].name,
        state_outputs::unit(&STATE_VARIABLES[2]),
        state_outputs::DESCRIPTION[2],
        STATE_OUTPUT_DEPENDS_ON[2],
        |m: NeuralFriction| m.outputs.state[2]
    ),
    ]
);

impl Model for NeuralFriction {
    const INFO: ModelInfo = ModelInfo {
        model_identifier: "NeuralFriction",
        description: "Kinetic friction force from a trained neural network (or an analytical law, with or without state), for coupling with StickSlipBeam",
        start_time: 0.0,
        stop_time: 1.2,
        step_size: 1e-3,
        resources: WEIGHTS_RESOURCES,
        returns_early_at_events: false,
        provides_directional_derivatives: true,
    };

    fn variables() -> &'static [Variable<Self>] {
        VARIABLES
    }

    fn arrays() -> &'static [ArrayVariable] {
        ARRAYS
    }

    fn with_defaults() -> Self {
        Self {
            settings: Settings::default(),
            networks: Networks::default(),
            outputs: Outputs::default(),
            scratch: Vec::new(),
            derivatives_at: None,
            built: None,
            law_state: Vec::new(),
            time: 0.0,
        }
    }

    fn load_resources(&mut self, resources: &Path) -> Result<(), String> {
        self.networks
            .open_and_read_default(resources)
            .map_err(|e| e.to_string())
    }

    fn reset(&mut self) {
        self.settings = Settings::default();
        self.outputs = Outputs::default();
        self.law_state.clear();
        self.time = 0.0;
    }

    fn refresh_outputs(&mut self, _start_time: f64, _stop_time: Option<f64>) -> Result<(), String> {
        self.outputs = self.evaluate().map_err(|e| e.to_string())?;
        Ok(())
    }

    fn initialize(&mut self, start_time: f64, _stop_time: Option<f64>) -> Result<(), String> {
        self.check().map_err(|e| e.to_string())?;
        // A law with state starts at its initial state.
        self.time = start_time;
        self.law_state.clear();
        self.outputs = self.evaluate().map_err(|e| e.to_string())?;
        Ok(())
    }

    fn do_step(&mut self, to: f64, size: f64, _events: &mut Vec<String>) -> Result<(), String> {
        self.advance_state(to, size).map_err(|e| e.to_string())?;
        self.outputs = self.evaluate().map_err(|e| e.to_string())?;
        Ok(())
    }

    fn partial_derivatives(&mut self) -> Result<PartialDerivatives, String> {
        self.derivatives().map_err(|e| e.to_string())
    }

    /// State version 4: the settings and the law state (`memory`).
    fn save(&self) -> serde_json::Value {
        self.saved()
    }

    /// Versions 1 to 3 hold the settings alone, version 4 the law state besides.
    fn restore(&mut self, saved: serde_json::Value, version: u32, time: f64) -> Result<(), String> {
        self.restore_saved(saved, version, time)
    }
}
