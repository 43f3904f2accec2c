//! NeuralFriction's variable table: the parameters (the laws' own and, from one
//! declaration shared with StickSlipBeam, those of the laws with state), the inputs,
//! the law's outputs and the state outputs, with what each output depends on.

use super::*;
use crate::declare::{
    choice_parameter, law_parameters, non_negative, real_input, real_output, real_parameter,
    weights_parameter,
};
use crate::law_state::law_state_outputs;
use crate::variables::{
    ArrayVariable, Dependencies, DependencyKind, InitialDependencies, Variable,
};
use std::sync::LazyLock;
use stickslip::friction::registry;
use stickslip::friction::state::STATE_VARIABLES;

/// NeuralFriction's FMI 3.0 arrays: the extra features.
pub(super) static ARRAYS: &[ArrayVariable] = &[ArrayVariable {
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
fn law_output() -> Dependencies {
    Dependencies {
        inputs: &[
            (SLIDING_VELOCITY, DependencyKind::Dependent),
            (NORMAL_FORCE, DependencyKind::Dependent),
            (EXTRA_FEATURE[0], DependencyKind::Dependent),
            (EXTRA_FEATURE[1], DependencyKind::Dependent),
            (EXTRA_FEATURE[2], DependencyKind::Dependent),
            (EXTRA_FEATURE[3], DependencyKind::Dependent),
        ],
        initial: InitialDependencies::InputsAnd(&LAW_OUTPUT_INITIAL),
    }
}

/// The parameters the law's outputs depend on in Initialization Mode: the law, its
/// coefficients and network, and each law parameter that reaches the force at the
/// law's initial state (the registry's `initial_force`: LuGre's sigma1 and sigma2, not
/// sigma0, which acts through z = 0; rate-and-state's a, V_0 and mu_0, not b, D_c and
/// the evolution law, which act through theta).
static LAW_OUTPUT_INITIAL: LazyLock<Vec<u32>> = LazyLock::new(|| {
    [LAW, STATIC_COEFFICIENT, KINETIC_COEFFICIENT, DECAY, WEIGHTS]
        .into_iter()
        .chain(
            registry::parameters()
                .filter(|p| p.initial_force)
                .map(|p| p.value_reference),
        )
        .collect()
});

/// The velocity the outputs were evaluated at: the input itself.
const EVALUATED_VELOCITY: Dependencies = Dependencies {
    inputs: &[(SLIDING_VELOCITY, DependencyKind::Constant)],
    initial: InitialDependencies::InputsAnd(&[]),
};

/// The static limit mu F_n: the normal force times a fixed parameter, mu = mu_s but 0
/// with `law = lugre` (`Settings::static_limit_coefficient`, in `state_laws`).
const STATIC_LIMIT: Dependencies = Dependencies {
    inputs: &[(NORMAL_FORCE, DependencyKind::Fixed)],
    initial: InitialDependencies::InputsAnd(&[LAW, STATIC_COEFFICIENT]),
};

/// What the state outputs depend on. The state moves only in a step, so no input
/// reaches them directly. In Initialization Mode they hold the initial state: z = 0
/// and psi = 0 whatever the parameters, theta = D_c / V_0 with `law = rate-and-state`
/// (and 0 with any other law).
/// The first state output's value reference: 30, 31, ... in the order of
/// `STATE_VARIABLES` (room up to 39).
pub(super) const FIRST_STATE_OUTPUT: u32 = 30;

/// Per state output: the law and the parameters the initial state of the law that has
/// the state variable depends on (the registry's `initial_state`: rate-and-state's
/// theta = D_c / V_0; nothing for z = 0 and psi = 0).
static STATE_OUTPUT_INITIAL: LazyLock<Vec<Vec<u32>>> = LazyLock::new(|| {
    STATE_VARIABLES
        .iter()
        .map(|variable| {
            let parameters: Vec<u32> = registry::laws()
                .filter(|law| law.state_variables.contains(variable))
                .flat_map(|law| law.parameters)
                .filter(|p| p.initial_state)
                .map(|p| p.value_reference)
                .collect();
            if parameters.is_empty() {
                parameters
            } else {
                std::iter::once(LAW).chain(parameters).collect()
            }
        })
        .collect()
});

fn state_output(index: usize) -> Dependencies {
    Dependencies {
        inputs: &[],
        initial: InitialDependencies::InputsAnd(&STATE_OUTPUT_INITIAL[index]),
    }
}

pub(super) static VARIABLES: LazyLock<Vec<Variable<NeuralFriction>>> = LazyLock::new(|| {
    let head = [
        choice_parameter!(
            LAW,
            "law",
            NeuralFrictionLaw,
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
        choice_parameter!(
            STATE_VELOCITY,
            "state_velocity",
            StateVelocity,
            "The velocity a law with state is committed with over a step: auto, end (sliding_velocity) or mean (mean_sliding_velocity once a master sets it)",
            |m: NeuralFriction| m.settings.state_velocity
        ),
    ];
    let tail = [
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
    real_input!(
        MEAN_SLIDING_VELOCITY,
        "mean_sliding_velocity",
        Some("m/s"),
        "Mean sliding velocity over the coming step (StickSlipBeam's mean_relative_velocity, Gauss-Seidel): commits a law's state where state_velocity chooses it; unused until a master sets it",
        |m: NeuralFriction| m.settings.mean_sliding_velocity,
        then = m.mean_linked = true
    ),
    real_output!(
        FRICTION_FORCE,
        "friction_force",
        Some("N"),
        "Kinetic friction force, signed: positive for positive sliding velocity",
        law_output(),
        |m: NeuralFriction| m.outputs.force
    ),
    real_output!(
        FRICTION_FORCE_MAGNITUDE,
        "friction_force_magnitude",
        Some("N"),
        "Magnitude of the kinetic friction force",
        law_output(),
        |m: NeuralFriction| m.outputs.force.abs()
    ),
    real_output!(
        FRICTION_COEFFICIENT,
        "friction_coefficient",
        None,
        "|friction_force| / normal_force (0 when normal_force = 0)",
        law_output(),
        |m: NeuralFriction| m.outputs.coefficient
    ),
    real_output!(
        STATIC_LIMIT_OUTPUT,
        "static_limit",
        Some("N"),
        "Static limit mu_s F_n (0 with law = lugre: no set-valued stick, the bristles hold)",
        STATIC_LIMIT,
        |m: NeuralFriction| m.outputs.static_limit
    ),
    real_output!(
        FRICTION_FORCE_SLOPE,
        "friction_force_slope",
        Some("N.s/m"),
        "dF/dv of friction_force at sliding_velocity (the exponential law: beside its jump at 0)",
        law_output(),
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
        STEP_FRICTION_FORCE,
        "step_friction_force",
        Some("N"),
        "Force after one communication step (the last step's size) at sliding_velocity held, the law's state advanced; friction_force for a memoryless law and before the first step",
        law_output(),
        |m: NeuralFriction| m.outputs.step_force
    ),
    real_output!(
        STEP_FRICTION_SLOPE,
        "step_friction_slope",
        Some("N.s/m"),
        "Derivative of step_friction_force with respect to the held sliding_velocity, the state's response included; friction_force_slope for a memoryless law and before the first step",
        law_output(),
        |m: NeuralFriction| m.outputs.step_slope
    ),
    ];
    let law_state = law_state_outputs(FIRST_STATE_OUTPUT, state_output, |m: &NeuralFriction, k| {
        m.outputs.state[k]
    });
    let table = table_outputs();
    let laws = law_parameters(
        "law",
        |m: &NeuralFriction| &m.settings.laws,
        |m: &mut NeuralFriction| &mut m.settings.laws,
    );
    head.into_iter()
        .chain(laws)
        .chain(tail)
        .chain(law_state)
        .chain(table)
        .collect()
});

/// What the tabulated curves depend on: the law at fixed velocities, from the committed
/// state, so every input but the sliding velocity (the normal force, the features a
/// network reads); in Initialization Mode also the laws' parameters, as the force.
fn table_output() -> Dependencies {
    Dependencies {
        inputs: &[
            (NORMAL_FORCE, DependencyKind::Dependent),
            (EXTRA_FEATURE[0], DependencyKind::Dependent),
            (EXTRA_FEATURE[1], DependencyKind::Dependent),
            (EXTRA_FEATURE[2], DependencyKind::Dependent),
            (EXTRA_FEATURE[3], DependencyKind::Dependent),
        ],
        initial: InitialDependencies::InputsAnd(&LAW_OUTPUT_INITIAL),
    }
}

/// The `table` coupling's outputs (StickSlipBeam's `external.table_force_i` and
/// `external.table_step_force_i`): both force curves at each of `TABLE_VELOCITIES`,
/// value references from `FIRST_TABLE_OUTPUT` (the first curve's nodes, then the
/// second's).
fn table_outputs() -> Vec<Variable<NeuralFriction>> {
    (0..2 * TABLE_LEN)
        .map(|k| {
            let (i, step) = (k % TABLE_LEN, k >= TABLE_LEN);
            let v = TABLE_VELOCITIES[i];
            // Once per row, when the table is first built.
            let (name, description) = if step {
                (
                    format!("table_step_friction_force_{i}"),
                    format!("step_friction_force at sliding velocity {v:e} m/s held instead of sliding_velocity (the table coupling's one-step curve, node {i})"),
                )
            } else {
                (
                    format!("table_friction_force_{i}"),
                    format!("friction_force at sliding velocity {v:e} m/s instead of sliding_velocity, at the committed state (the table coupling's instantaneous curve, node {i})"),
                )
            };
            Variable {
                name: Box::leak(name.into_boxed_str()),
                value_reference: FIRST_TABLE_OUTPUT + k as u32,
                causality: crate::variables::Causality::Output,
                variability: crate::variables::Variability::Continuous,
                description: Box::leak(description.into_boxed_str()),
                access: crate::variables::Access::Real {
                    unit: Some("N"),
                    get: Box::new(move |m: &NeuralFriction| {
                        if step {
                            m.outputs.table_step_force[i]
                        } else {
                            m.outputs.table_force[i]
                        }
                    }),
                    set: None,
                },
                depends_on: Some(table_output()),
            }
        })
        .collect()
}
