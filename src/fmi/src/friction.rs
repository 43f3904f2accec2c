//! NeuralFriction: the friction law alone, as an FMU to couple with StickSlipBeam (or
//! anything else that needs a friction force).
//!
//! The outputs follow the inputs directly: they are evaluated when read. A law with
//! state (`law = lugre`, `rate-and-state`, or the learned law with memory: weights of
//! format `stickslip-state-friction`) also integrates its state over each
//! communication step (`state_laws`), the outputs are evaluated at the committed state, and
//! the state is an output (`crate::law_state`). A
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
//! within its internal steps (see `stickslip::contact`). For a law with state the
//! step-consistent pair is output too (`step_friction_force`, `step_friction_slope`,
//! see `state_laws`), which StickSlipBeam's `external.coupling = step` solves.

use crate::model::PartialDerivatives;
use crate::networks::{NetworkError, Networks, DEFAULT_WEIGHTS};
use serde::{Deserialize, Serialize};
use stickslip::friction::registry::LawTables;
use stickslip::friction::state::STATE_VARIABLES;
use stickslip::friction::tabulated::TABLE_VELOCITIES;
use stickslip::friction::FrictionLaw;
use stickslip::neural::{FeatureRole, NeuralError, NeuralModel};
use stickslip::scene::{Friction, Loading, Scene, SceneError};
use stickslip::short::Short;

mod derivatives;
mod laws;
mod model;
mod state_laws;
mod state_velocity;
mod variables;

pub use laws::NeuralFrictionLaw;
pub use state_velocity::StateVelocity;

/// How many features beyond velocity and normal force a network may have.
pub const EXTRA_FEATURES: usize = 4;

/// Saved in FMU states. Unknown keys are refused by [`LawTables`], which receives every
/// key not named here (serde's `deny_unknown_fields` does not combine with `flatten`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
struct Settings {
    law: NeuralFrictionLaw,
    static_coefficient: f64,
    kinetic_coefficient: f64,
    decay: f64,
    weights: String,
    /// Every law's parameters (`stickslip::friction::registry`), saved as one map per
    /// law beside the other settings (`"lugre": {...}`); a law's table absent from a
    /// state saved before the law existed reads as its defaults.
    #[serde(flatten)]
    laws: LawTables,
    sliding_velocity: f64,
    normal_force: f64,
    extra_features: [f64; EXTRA_FEATURES],
    /// Which velocity commits a law's state (`state_velocity`); absent from states
    /// saved before it existed, which committed at `sliding_velocity`: read as `end`.
    #[serde(default = "end_velocity")]
    state_velocity: StateVelocity,
    /// The input `mean_sliding_velocity` (m/s): the beam's mean v_rel over the step.
    #[serde(default)]
    mean_sliding_velocity: f64,
}

fn end_velocity() -> StateVelocity {
    StateVelocity::End
}

impl Settings {
    /// These settings as the scene's friction section (`friction.law` the law chosen,
    /// no weights: NeuralFriction reads its networks itself), the one form every law is
    /// built and checked from (`LawSource`, `Friction::check`).
    fn friction(&self) -> Friction {
        Friction {
            law: self.law.kind(),
            static_coefficient: self.static_coefficient,
            kinetic_coefficient: self.kinetic_coefficient,
            decay: self.decay,
            laws: self.laws.clone(),
            ..Friction::default()
        }
    }

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
            law: NeuralFrictionLaw::NEURAL,
            static_coefficient: scene.friction.static_coefficient,
            kinetic_coefficient: scene.friction.kinetic_coefficient,
            decay: scene.friction.decay,
            weights: DEFAULT_WEIGHTS.into(),
            laws: scene.friction.laws,
            sliding_velocity: 0.0,
            normal_force: scene.loading.normal_force,
            extra_features: [0.0; EXTRA_FEATURES],
            state_velocity: StateVelocity::default(),
            mean_sliding_velocity: 0.0,
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
    /// The step-consistent pair (N, N s/m) of a law with state: the force after one
    /// step of the last communication step's size at `velocity` held, and its
    /// derivative with respect to that velocity (`state_laws::step_pair`); `force`
    /// and `slope` for a memoryless law and before the first step.
    step_force: f64,
    step_slope: f64,
    /// Both force curves at `TABLE_VELOCITIES` (N): F(s_k, v_i) and F_h(s_k, v_i)
    /// (`NeuralFriction::table`).
    table_force: [f64; TABLE_LEN],
    table_step_force: [f64; TABLE_LEN],
}

/// How many fixed velocities the curves are tabulated at.
const TABLE_LEN: usize = TABLE_VELOCITIES.len();

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
    #[error("the partial derivative of value reference {output} with respect to value reference {input} is {}", Short(*.value))]
    NonFiniteDerivative { output: u32, input: u32, value: f64 },
    /// A law state that a step made non-finite.
    #[error("the friction law's state is not finite ({}) after a step at sliding_velocity = {} m/s", Short(*.state), Short(*.sliding_velocity))]
    NonFiniteState { sliding_velocity: f64, state: f64 },
    /// Inputs (m/s, N) at which the law gives a non-finite force.
    #[error("the outputs are not finite at sliding_velocity = {} m/s, normal_force = {} N (force {}, slope {}, coefficient {}, static limit {})", Short(*.sliding_velocity), Short(*.normal_force), Short(*.force), Short(*.slope), Short(*.coefficient), Short(*.static_limit))]
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
    /// The law last built from the settings, any but the plain network (`state_laws`).
    built: Option<(Settings, Box<dyn FrictionLaw>)>,
    /// The committed state of a law with state (`state_laws`); empty otherwise.
    law_state: Vec<f64>,
    /// Where the model is (s): the start time, then the end of the last step.
    time: f64,
    /// The size (s) of the last communication step of nonzero size, the master's h:
    /// the step the step-consistent pair looks ahead over; 0 before the first step.
    step_size: f64,
    /// `mean_sliding_velocity` has been set: a master links it (one that does not never
    /// sets it, and its steps commit at `sliding_velocity`, as before the input
    /// existed). Not "set since the last step": Ecos sets an input only when its value
    /// changes (tested: in stick the mean repeats). Not a setting, since no variable
    /// sets it back to false (`check_as_set`); reset by fmi2Reset.
    mean_linked: bool,
}

/// Why initialisation refuses the parameters (fmi2ExitInitializationMode), and a saved
/// initialised state with them.
#[derive(Debug, thiserror::Error)]
enum InitialiseError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Evaluate(#[from] EvaluateError),
}

impl NeuralFriction {
    /// What fmi2ExitInitializationMode checks, in the law state in place (the initial
    /// one at initialisation, a saved one when a state is restored): the parameters by
    /// the scene's rules, then the law evaluated (its weights read, the law state
    /// set), which gives the outputs.
    fn initialise_outputs(&mut self) -> Result<(), InitialiseError> {
        self.check()?;
        self.outputs = self.evaluate()?;
        Ok(())
    }

    /// Checks the analytical parameters with the scene's rules and messages, in the
    /// scene's order: the normal force (`loading`), then the friction section every law
    /// is built from ([`Settings::friction`]).
    fn check(&self) -> Result<(), SceneError> {
        let loading = Loading {
            normal_force: self.settings.normal_force,
            ..Loading::default()
        };
        loading.check()?;
        self.settings.friction().check()
    }

    fn evaluate(&mut self) -> Result<Outputs, EvaluateError> {
        let s = self.settings.clone();
        let static_limit = s.static_limit_coefficient() * s.normal_force;
        let ((force, slope), state) = self.law_force()?;
        let (step_force, step_slope) = self.step_pair()?.unwrap_or((force, slope));
        let (table_force, table_step_force) = self.table()?;
        let outputs = Outputs {
            force,
            slope,
            step_force,
            step_slope,
            velocity: s.sliding_velocity,
            coefficient: if s.normal_force > 0.0 {
                force.abs() / s.normal_force
            } else {
                0.0
            },
            static_limit,
            state,
            table_force,
            table_step_force,
        };
        if ![
            outputs.force,
            outputs.slope,
            outputs.step_force,
            outputs.step_slope,
            outputs.velocity,
            outputs.coefficient,
            outputs.static_limit,
        ]
        .iter()
        .chain(&outputs.state)
        .chain(&outputs.table_force)
        .chain(&outputs.table_step_force)
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

    /// Both force curves at the fixed velocities `TABLE_VELOCITIES` (N), from the
    /// committed state at the current normal force (and features): the instantaneous
    /// F(s_k, v_i) and the one-step F_h(s_k, v_i) (`step_pair`; F itself for a
    /// memoryless law and before the first step). The `table` coupling's inputs
    /// (`stickslip::friction::tabulated`).
    #[allow(clippy::type_complexity)]
    fn table(&mut self) -> Result<([f64; TABLE_LEN], [f64; TABLE_LEN]), EvaluateError> {
        let v = self.settings.sliding_velocity;
        let mut force = [0.0; TABLE_LEN];
        let mut step_force = [0.0; TABLE_LEN];
        let mut fill = |m: &mut Self| -> Result<(), EvaluateError> {
            for (i, &at) in TABLE_VELOCITIES.iter().enumerate() {
                m.settings.sliding_velocity = at;
                let ((f, _), _) = m.law_force()?;
                force[i] = f;
                step_force[i] = m.step_pair()?.map_or(f, |p| p.0);
            }
            Ok(())
        };
        let filled = fill(self);
        self.settings.sliding_velocity = v;
        filled.map(|()| (force, step_force))
    }

    /// The law's force and slope at the current inputs (at the committed state for a
    /// law with state), and its state outputs.
    #[allow(clippy::type_complexity)]
    fn law_force(&mut self) -> Result<((f64, f64), [f64; STATE_VARIABLES.len()]), EvaluateError> {
        let s = self.settings.clone();
        let mut state = [0.0; STATE_VARIABLES.len()];
        let (force, slope) = 'law: {
            if let Some((jacobian, values)) = self.state_jacobian()? {
                state = values;
                break 'law (jacobian.force, jacobian.slope);
            }
            if let Some(jacobian) = self.memoryless_jacobian()? {
                break 'law (jacobian.force, jacobian.slope);
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
        };
        Ok(((force, slope), state))
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
const MEAN_SLIDING_VELOCITY: u32 = 17;
const STATE_VELOCITY: u32 = 6;
const FRICTION_FORCE: u32 = 20;
const FRICTION_FORCE_MAGNITUDE: u32 = 21;
const FRICTION_COEFFICIENT: u32 = 22;
const STATIC_LIMIT_OUTPUT: u32 = 23;
const FRICTION_FORCE_SLOPE: u32 = 24;
const EVALUATED_VELOCITY_OUTPUT: u32 = 25;
const STEP_FRICTION_FORCE: u32 = 26;
const STEP_FRICTION_SLOPE: u32 = 27;
/// The first of the `table` coupling's outputs: `table_friction_force_i` at
/// 101 + i and `table_step_friction_force_i` at 101 + TABLE_LEN + i, i = 0..TABLE_LEN
/// (`variables::table_outputs`).
const FIRST_TABLE_OUTPUT: u32 = 101;
/// The FMI 3.0 array `extra_feature` of those four: a value reference of its own (16,
/// free in both descriptions), so that 12 means `extra_feature[1]` in FMI 2.0 and
/// nothing in FMI 3.0, never the whole array.
pub const EXTRA_FEATURE_ARRAY: u32 = 16;
