//! StickSlipBeam's variable table: the scene's fields under the scene file's names as
//! parameters, the belt, the normal force and the external friction model as inputs,
//! the tip and the contact as outputs. The value references are part of saved FMU
//! states and SSP files: never renumber one.

use super::StickSlipBeam;
use crate::declare::{
    choice_parameter, count_parameter, law_parameters, non_negative, real_input, real_output,
    real_parameter, weights_parameter,
};
use crate::law_state::law_state_outputs;
use crate::variables::{
    Access, Causality, Dependencies, InitialDependencies, Variability, Variable,
};
use std::sync::LazyLock;
use stickslip::friction::tabulated::TABLE_VELOCITIES;
use stickslip::friction::FrictionLawKind;
use stickslip::neural::inference::Inference;
use stickslip::scene::{
    Clamp, DampingPhase, FidelityLevel, FirstSlipStep, HoldingForce, InitialState, ModalBasis,
    Scheme, SlidingVelocity, SlipForce, TipVelocity,
};
use stickslip::short::Short;
use stickslip::simulation::ExternalCoupling;

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

pub(super) static VARIABLES: LazyLock<Vec<Variable<StickSlipBeam>>> = LazyLock::new(|| {
    let head = [
    real_parameter!(
        1,
        "geometry.length",
        Some("m"),
        "Beam length L",
        |m: StickSlipBeam| m.settings.scene.geometry.length
    ),
    real_parameter!(
        2,
        "geometry.height",
        Some("m"),
        "Beam height h",
        |m: StickSlipBeam| m.settings.scene.geometry.height
    ),
    real_parameter!(
        3,
        "geometry.width",
        Some("m"),
        "Out-of-plane width b",
        |m: StickSlipBeam| m.settings.scene.geometry.width
    ),
    real_parameter!(
        4,
        "material.density",
        Some("kg/m3"),
        "Density rho",
        |m: StickSlipBeam| m.settings.scene.material.density
    ),
    real_parameter!(
        5,
        "material.youngs_modulus",
        Some("Pa"),
        "Young's modulus E",
        |m: StickSlipBeam| m.settings.scene.material.youngs_modulus
    ),
    real_parameter!(
        6,
        "material.poisson_ratio",
        None,
        "Poisson's ratio nu",
        |m: StickSlipBeam| m.settings.scene.material.poisson_ratio
    ),
    choice_parameter!(
        10,
        "friction.law",
        FrictionLawKind,
        "Kinetic friction law",
        |m: StickSlipBeam| m.settings.scene.friction.law
    ),
    real_parameter!(
        11,
        "friction.static_coefficient",
        None,
        "Static coefficient mu_s",
        |m: StickSlipBeam| m.settings.scene.friction.static_coefficient
    ),
    real_parameter!(
        12,
        "friction.kinetic_coefficient",
        None,
        "Kinetic coefficient mu_k",
        |m: StickSlipBeam| m.settings.scene.friction.kinetic_coefficient
    ),
    real_parameter!(
        13,
        "friction.decay",
        Some("s/m"),
        "Decay alpha of the exponential law",
        |m: StickSlipBeam| m.settings.scene.friction.decay
    ),
    real_parameter!(
        14,
        "friction.stick_threshold",
        Some("m/s"),
        "Stick threshold eps on |v_rel|",
        |m: StickSlipBeam| m.settings.scene.friction.stick_threshold
    ),
    weights_parameter!(
        15,
        "friction.weights",
        "Network weights for friction.law = neural: a file in resources/ or an absolute path",
        |m: StickSlipBeam| m.settings.weights
    ),
    choice_parameter!(
        16,
        "external.coupling",
        ExternalCoupling,
        "friction.law = external: how the kinetic force is read from the inputs",
        |m: StickSlipBeam| m.settings.coupling
    ),
    choice_parameter!(
        17,
        "friction.inference",
        Inference,
        "Evaluation of the network for friction.law = neural",
        |m: StickSlipBeam| m.settings.scene.friction.inference
    ),
    choice_parameter!(
        20,
        "contact.holding_force",
        HoldingForce,
        "Stick holding force",
        |m: StickSlipBeam| m.settings.scene.contact.holding_force
    ),
    choice_parameter!(
        21,
        "contact.sliding_velocity",
        SlidingVelocity,
        "Velocity argument of the law",
        |m: StickSlipBeam| m.settings.scene.contact.sliding_velocity
    ),
    choice_parameter!(
        22,
        "contact.initial_state",
        InitialState,
        "State at t = 0",
        |m: StickSlipBeam| m.settings.scene.contact.initial_state
    ),
    real_parameter!(
        23,
        "contact.preload",
        None,
        "Tip preload at t = 0 as a fraction of mu_s F_n, in [0, 1): start in the static shape under it",
        |m: StickSlipBeam| m.settings.scene.contact.preload
    ),
    choice_parameter!(
        24,
        "contact.tip_velocity",
        TipVelocity,
        "Tip velocity the contact evaluates",
        |m: StickSlipBeam| m.settings.scene.contact.tip_velocity
    ),
    choice_parameter!(
        25,
        "contact.damping_phase",
        DampingPhase,
        "Contact phases in which the Rayleigh damping acts",
        |m: StickSlipBeam| m.settings.scene.contact.damping_phase
    ),
    choice_parameter!(
        26,
        "contact.first_slip_step",
        FirstSlipStep,
        "Tip force over the first step of each slip phase",
        |m: StickSlipBeam| m.settings.scene.contact.first_slip_step
    ),
    choice_parameter!(
        27,
        "contact.slip_force",
        SlipForce,
        "Sliding velocity the kinetic force of a slip step is evaluated at",
        |m: StickSlipBeam| m.settings.scene.contact.slip_force
    ),
    real_parameter!(
        30,
        "damping.mass_proportional",
        Some("1/s"),
        "Rayleigh damping a in C = a M + b K",
        |m: StickSlipBeam| m.settings.scene.damping.mass_proportional
    ),
    real_parameter!(
        31,
        "damping.stiffness_proportional",
        Some("s"),
        "Rayleigh damping b in C = a M + b K",
        |m: StickSlipBeam| m.settings.scene.damping.stiffness_proportional
    ),
    real_parameter!(
        40,
        "time.step",
        Some("s"),
        "Internal time step (the FMU sub-steps each communication step)",
        |m: StickSlipBeam| m.settings.scene.time.step
    ),
    choice_parameter!(
        50,
        "fidelity.level",
        FidelityLevel,
        "Structural model; auto also picks the time step and integrator",
        |m: StickSlipBeam| m.settings.scene.fidelity.level
    ),
    Variable {
        name: "fidelity.tolerance",
        value_reference: 57,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        description: "fidelity.level = auto: largest tip-deflection deviation allowed over the experiment (to its stop time; without one, or beyond 10 s, over the first three major slips)",
        access: Access::Real {
            unit: Some("m"),
            // Some from the start value on; NaN stands for a tolerance never given.
            get: Box::new(|m: &StickSlipBeam| m.settings.scene.fidelity.tolerance.unwrap_or(f64::NAN)),
            set: Some(Box::new(|m: &mut StickSlipBeam, v: f64| {
                if !(v.is_finite() && v > 0.0) {
                    return Err(format!("{} must be finite and > 0", Short(v)));
                }
                m.settings.scene.fidelity.tolerance = Some(v);
                Ok(())
            })),
        },
        depends_on: None,
    },
    count_parameter!(
        51,
        "fidelity.beam_elements",
        stickslip::scene::MAX_BEAM_ELEMENTS as i32,
        "Number of beam elements (beam level, and the modal level's beam basis)",
        |m: StickSlipBeam| m.settings.scene.fidelity.beam_elements
    ),
    real_parameter!(
        52,
        "fidelity.element_size",
        Some("m"),
        "Plane-stress element size",
        |m: StickSlipBeam| m.settings.scene.fidelity.element_size
    ),
    count_parameter!(
        53,
        "fidelity.modes",
        stickslip::scene::MAX_MODES as i32,
        "Number of modes of the modal level",
        |m: StickSlipBeam| m.settings.scene.fidelity.modes
    ),
    choice_parameter!(
        54,
        "fidelity.modal_basis",
        ModalBasis,
        "Model whose modes the modal level keeps",
        |m: StickSlipBeam| m.settings.scene.fidelity.modal_basis
    ),
    Variable {
        name: "fidelity.static_correction",
        value_reference: 55,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        description: "Add the static tip-load shape to the modal basis",
        access: Access::Boolean {
            get: Box::new(|m: &StickSlipBeam| m.settings.scene.fidelity.static_correction),
            set: Some(Box::new(|m: &mut StickSlipBeam, v: bool| {
                m.settings.scene.fidelity.static_correction = v;
                Ok(())
            })),
        },
        depends_on: None,
    },
    choice_parameter!(
        56,
        "fidelity.clamp",
        Clamp,
        "Support of the plane-stress mesh",
        |m: StickSlipBeam| m.settings.scene.fidelity.clamp
    ),
    choice_parameter!(
        60,
        "integrator.scheme",
        Scheme,
        "Time integrator",
        |m: StickSlipBeam| m.settings.scene.integrator.scheme
    ),
    real_parameter!(
        61,
        "integrator.rho_inf",
        None,
        "Generalised-alpha spectral radius at infinite frequency",
        |m: StickSlipBeam| m.settings.scene.integrator.rho_inf
    ),
    real_parameter!(
        62,
        "integrator.theta",
        None,
        "Moreau-Jean theta",
        |m: StickSlipBeam| m.settings.scene.integrator.theta
    ),
    ];
    let tail = [
    // Any finite belt speed (either direction) is a valid input.
    real_input!(
        100,
        "belt_speed",
        Some("m/s"),
        "Belt speed v_b",
        |m: StickSlipBeam| m.settings.inputs.belt_speed,
        then = m.apply_inputs()
    ),
    real_input!(
        NORMAL_FORCE,
        "normal_force",
        Some("N"),
        "Normal force F_n",
        |m: StickSlipBeam| m.settings.inputs.normal_force,
        check = non_negative,
        then = m.apply_inputs()
    ),
    real_input!(
        102,
        "external.kinetic_force",
        Some("N"),
        "Kinetic friction force magnitude (friction.law = external)",
        |m: StickSlipBeam| m.settings.inputs.kinetic_force,
        check = non_negative,
        then = m.apply_inputs()
    ),
    real_input!(
        103,
        "external.static_limit",
        Some("N"),
        "Static limit, the largest holding force (friction.law = external)",
        |m: StickSlipBeam| m.settings.inputs.static_limit,
        check = non_negative,
        then = m.apply_inputs()
    ),
    real_input!(
        104,
        "external.friction_force",
        Some("N"),
        "Signed kinetic friction force F(v) at external.sliding_velocity (external.coupling = signed)",
        |m: StickSlipBeam| m.settings.inputs.friction_force,
        then = m.apply_inputs()
    ),
    real_input!(
        105,
        "external.friction_slope",
        Some("N.s/m"),
        "dF/dv at external.sliding_velocity (external.coupling = signed)",
        |m: StickSlipBeam| m.settings.inputs.friction_slope,
        then = m.apply_inputs()
    ),
    real_input!(
        106,
        "external.sliding_velocity",
        Some("m/s"),
        "Sliding velocity the friction model was evaluated at (external.coupling = signed or step)",
        |m: StickSlipBeam| m.settings.inputs.sliding_velocity,
        then = m.apply_inputs()
    ),
    real_input!(
        107,
        "external.step_force",
        Some("N"),
        "Force after one communication step at external.sliding_velocity held, the law's state advanced (external.coupling = step)",
        |m: StickSlipBeam| m.settings.inputs.step_force,
        then = m.apply_inputs()
    ),
    real_input!(
        108,
        "external.step_slope",
        Some("N.s/m"),
        "Derivative of external.step_force with respect to the held velocity, the state's response included (external.coupling = step)",
        |m: StickSlipBeam| m.settings.inputs.step_slope,
        then = m.apply_inputs()
    ),
    real_output!(
        200,
        "tip_deflection",
        Some("m"),
        "Transverse tip deflection",
        BEAM_OUTPUT,
        |m: StickSlipBeam| m.output(|s| s.tip_deflection)
    ),
    real_output!(
        201,
        "tip_velocity",
        Some("m/s"),
        "Transverse tip velocity",
        BEAM_OUTPUT,
        |m: StickSlipBeam| m.output(|s| s.tip_velocity)
    ),
    real_output!(
        202,
        "relative_velocity",
        Some("m/s"),
        "Sliding velocity v_rel = v_b - v_tip",
        BEAM_OUTPUT,
        |m: StickSlipBeam| m.output(|s| s.relative_velocity)
    ),
    real_output!(
        203,
        "friction_force",
        Some("N"),
        "Force of the contact on the tip",
        BEAM_OUTPUT,
        |m: StickSlipBeam| m.output(|s| s.friction_force)
    ),
    real_output!(
        204,
        "holding_force",
        Some("N"),
        "Force that stick needs (compared with the static limit)",
        BEAM_OUTPUT,
        |m: StickSlipBeam| m.output(|s| s.holding_force)
    ),
    real_output!(
        207,
        "mean_relative_velocity",
        Some("m/s"),
        "Mean of relative_velocity over the last communication step: the distance slid over it / its length (relative_velocity before the first step); NeuralFriction's mean_sliding_velocity",
        BEAM_OUTPUT,
        |m: StickSlipBeam| m.running.as_ref().map_or(0.0, |r| r.mean_relative_velocity)
    ),
    Variable {
        name: "stick",
        value_reference: 205,
        causality: Causality::Output,
        variability: Variability::Discrete,
        description: "True while the tip sticks to the belt (with a law with state, lugre or rate-and-state: while |v_rel| < friction.stick_threshold)",
        access: Access::Boolean {
            get: Box::new(|m: &StickSlipBeam| m.sample().map(|s| s.stick).unwrap_or(true)),
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
            get: Box::new(|m: &StickSlipBeam| {
                m.running
                    .as_ref()
                    .map(|r| r.simulator.state().transition_count.min(i32::MAX as u64) as i32)
                    .unwrap_or(0)
            }),
            set: None,
        },
        depends_on: Some(BEAM_OUTPUT),
    },
    ];
    // The law's state outputs, value references 210, 211, ..., one per entry of
    // STATE_VARIABLES, in its order, at the end of the table.
    let law_state = law_state_outputs(
        210,
        |_| BEAM_OUTPUT,
        |m: &StickSlipBeam, k| m.sample().map_or(0.0, |s| s.law_state[k]),
    );
    let laws = law_parameters(
        "friction.law",
        |m: &StickSlipBeam| &m.settings.scene.friction.laws,
        |m: &mut StickSlipBeam| &mut m.settings.scene.friction.laws,
    );
    head.into_iter()
        .chain(laws)
        .chain(tail)
        .chain(law_state)
        .chain(table_inputs())
        .collect()
});

/// The first of the `table` coupling's inputs: `external.table_force_i` at 401 + i and
/// `external.table_step_force_i` at 401 + TABLE_VELOCITIES.len() + i.
const FIRST_TABLE_INPUT: u32 = 401;

/// The `table` coupling's inputs (`external.coupling = table`): both force curves of a
/// law with state at each of `TABLE_VELOCITIES` (NeuralFriction's
/// `table_friction_force_i` and `table_step_friction_force_i`).
fn table_inputs() -> Vec<Variable<StickSlipBeam>> {
    let n = TABLE_VELOCITIES.len();
    (0..2 * n)
        .map(|k| {
            let (i, step) = (k % n, k >= n);
            let v = TABLE_VELOCITIES[i];
            // Once per row, when the table is first built.
            let (name, description) = if step {
                (
                    format!("external.table_step_force_{i}"),
                    format!("The one-step force curve at sliding velocity {v:e} m/s: the force after one communication step at that velocity held (external.coupling = table, node {i})"),
                )
            } else {
                (
                    format!("external.table_force_{i}"),
                    format!("The instantaneous force curve at sliding velocity {v:e} m/s, at the law's state at the step's start (external.coupling = table, node {i})"),
                )
            };
            Variable {
                name: Box::leak(name.into_boxed_str()),
                value_reference: FIRST_TABLE_INPUT + k as u32,
                causality: Causality::Input,
                variability: Variability::Continuous,
                description: Box::leak(description.into_boxed_str()),
                access: Access::Real {
                    unit: Some("N"),
                    get: Box::new(move |m: &StickSlipBeam| {
                        if step {
                            m.settings.inputs.table_step_force[i]
                        } else {
                            m.settings.inputs.table_force[i]
                        }
                    }),
                    set: Some(Box::new(move |m: &mut StickSlipBeam, x: f64| {
                        let curve = if step {
                            &mut m.settings.inputs.table_step_force
                        } else {
                            &mut m.settings.inputs.table_force
                        };
                        curve[i] = x;
                        m.apply_inputs();
                        Ok(())
                    })),
                },
                depends_on: None,
            }
        })
        .collect()
}
