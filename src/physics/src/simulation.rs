//! The transient stick-slip simulation: a structural model, an integrator, the contact
//! and a friction law, stepped at a fixed time step.
//!
//! A step reads: the integrator's trial solve without tip force, then the contact's
//! resolution of the tip force from it (stick reaction, slip solve and switch for either
//! scheme, see `contact`), then the integrator's finish with that force.

use crate::contact::{
    Contact, ContactState, Direction, Kinetic, Previous, Resolution, SlipSolve, SlipSolver,
    Transition,
};
use crate::friction::state::{StateVariable, STATE_VARIABLES};
use crate::friction::tabulated::StepCurves;
use crate::friction::FrictionLaw;
use crate::integrator::{Coefficients, Integrator, Kinematics, TrialStep};
use crate::modal_slip::{SlipBasis, SlipBasisError};
use crate::scene::{CheckedScene, DampingPhase, InitialState, TipVelocity};
use crate::short::Short;
use crate::structure::{observe, singular, ModelError, StructuralModel};
use serde::{Deserialize, Serialize};

/// Everything that evolves in time; plain data, so that it can be saved and restored.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SimulationState {
    /// Steps taken.
    pub step: u64,
    /// Time (s).
    pub time: f64,
    pub kinematics: Kinematics,
    pub contact: ContactState,
    /// v_rel = v_b - v_tip at `time` (m/s).
    pub relative_velocity: f64,
    /// Force of the contact on the tip (N): the holding force in stick, the kinetic
    /// friction force in slip.
    pub contact_force: f64,
    /// Force that stick needs (N), the quantity compared with mu_s F_n.
    pub holding_force: f64,
    /// Number of stick/slip transitions so far.
    pub transition_count: u64,
    /// Time (s) of the last step of irregular length (0 if none): full steps count from
    /// here, so that `time` stays anchor + n dt rather than accumulating rounding.
    #[serde(default)]
    pub anchor_time: f64,
    /// Full steps since `anchor_time`.
    #[serde(default)]
    pub steps_since_anchor: u64,
    /// The friction law's internal state (`memory::StatefulLaw::state`), empty for a
    /// memoryless law (and in states saved before laws had state).
    #[serde(default)]
    pub law_state: Vec<f64>,
}

/// One output sample (SI units).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Time (s).
    pub time: f64,
    /// Transverse tip deflection (m).
    pub tip_deflection: f64,
    /// Transverse tip velocity (m/s).
    pub tip_velocity: f64,
    /// Relative sliding velocity v_b - v_tip (m/s).
    pub relative_velocity: f64,
    /// Force of the contact on the tip (N).
    pub friction_force: f64,
    /// Force that stick needs (N).
    pub holding_force: f64,
    pub stick: bool,
    /// The friction law's committed state, one value per entry of
    /// [`STATE_VARIABLES`] in its order, in that entry's unit: 0 where the run's law has
    /// not that variable (every entry for a memoryless law; see
    /// [`Simulator::law_state_slots`] for the ones it has).
    pub law_state: LawStateValues,
}

/// A sensor's reading (`user_structure::Sensor`, `StructuralModel::sensors`): its DOF's
/// displacement (m, rad on a rotation) and velocity (m/s, rad/s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct SensorReading {
    pub displacement: f64,
    pub velocity: f64,
}

/// A value per entry of [`STATE_VARIABLES`] (see [`Sample::law_state`]).
pub type LawStateValues = [f64; STATE_VARIABLES.len()];

/// A simulation that cannot go on.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SimulationError {
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A scene option the run's law cannot honour (a slip-phase rule with a network
    /// that has state, known only once its weights are read).
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
    /// The modes of `contact.slip_modes_below` could not be found.
    #[error(transparent)]
    SlipBasis(#[from] SlipBasisError),
    /// The state became NaN or infinite.
    #[error("{quantity} became non-finite at t = {} s", Short(*.time))]
    NonFinite { time: f64, quantity: &'static str },
    /// A requested end time that is not finite or lies in the past.
    #[error("cannot advance to t = {} s from t = {} s: the target must be finite and not in the past", Short(*.target), Short(*.time))]
    InvalidTarget { time: f64, target: f64 },
}

/// Friction supplied from outside (a coupled friction model), held constant over a step.
/// It replaces the law and the static limit mu_s F_n of the scene.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExternalFriction {
    /// The kinetic friction force in slip.
    pub kinetic: ExternalKinetic,
    /// Largest holding force that stick sustains (N).
    pub static_limit: f64,
}

crate::choice! {
    /// How a coupled friction model hands over its kinetic force (the StickSlipBeam
    /// FMU's `external.coupling`, with `friction.law = external`).
    #[choice(name = "ExternalCoupling", description = "How friction.law = external reads the coupled friction model")]
    #[derive(Default)]
    pub enum ExternalCoupling {
        /// [`ExternalKinetic::Magnitude`] from `external.kinetic_force`.
        #[default]
        Magnitude = "magnitude": "external.kinetic_force along v_rel: for laws sign(v) g(|v|) (exponential, Coulomb, the signed network)",
        /// [`ExternalKinetic::Signed`] from `external.friction_force`,
        /// `external.friction_slope` and `external.sliding_velocity`.
        Signed = "signed": "the tangent external.friction_force + external.friction_slope (v - external.sliding_velocity): for smooth signed laws (the plain network)",
        /// [`ExternalKinetic::Step`] from `external.step_force`,
        /// `external.step_slope` and `external.sliding_velocity`.
        Step = "step": "the signed tangent blended over the communication step into the step-consistent one, external.step_force + external.step_slope (v - external.sliding_velocity): for laws with state (LuGre, rate-and-state, the learned law with memory)",
        /// [`ExternalKinetic::Table`] from `external.table_force_i`,
        /// `external.table_step_force_i`, `external.friction_force`,
        /// `external.step_force` and `external.sliding_velocity`.
        Table = "table": "both force curves of a law with state, the instantaneous and the one-step one, tabulated at fixed velocities (external.table_force_i, external.table_step_force_i) and at external.sliding_velocity, blended over the communication step and interpolated piecewise linearly: for laws with state (issue 36)",
    }
}

/// How a coupled friction model gives the kinetic force.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum ExternalKinetic {
    /// A magnitude (N), applied in the direction of v_rel: for laws of the form
    /// F(v) = sign(v) g(|v|), whose sign the beam knows better than a force held from
    /// the start of the step (the exponential and Coulomb laws, the signed network).
    Magnitude(f64),
    /// A signed law F(v) by its value `force` (N) and slope `slope` = dF/dv (N s/m) at
    /// the sliding velocity `velocity` (m/s) the model was evaluated at. In slip the
    /// step takes the tangent F(v) ~ force + slope (v - velocity) at its own sliding
    /// velocity, solved implicitly as the embedded slip solve does with a law; where
    /// the tangent points against v_rel, its magnitude acts along v_rel (friction
    /// dissipates; see `contact::Kinetic::ExternalSigned`). For smooth signed laws such
    /// as the paper's plain network.
    Signed {
        force: f64,
        slope: f64,
        velocity: f64,
    },
    /// A law with state by two tangents at the sliding velocity `velocity` (m/s) the
    /// model was evaluated at, from its state at the start of the communication step:
    /// the instantaneous one (`force`, `slope`: N, N s/m) and the step-consistent one
    /// (`step_force`, `step_slope`: the force after the whole communication step at
    /// `velocity` held, the state advanced, and its derivative with respect to that
    /// held velocity, the state's response included; NeuralFriction's
    /// `step_friction_force` and `step_friction_slope`). An internal step ending at the
    /// fraction theta of the communication step (the steps of the `advance` call, j / n
    /// for the j-th of n) takes
    /// (1 - theta) of the first and theta of the second: the force of a state that moves
    /// over the step, to first order in the step, and the step-consistent tangent
    /// itself at its end. Solved as `Signed`, except that the force is turned along
    /// v_rel only where v_rel has crossed 0 since `velocity` (a law with state may push
    /// against v_rel: LuGre's bristles after a reversal; see `contact::tangent`). For a
    /// memoryless law both tangents are the same.
    Step {
        force: f64,
        slope: f64,
        step_force: f64,
        step_slope: f64,
        velocity: f64,
    },
    /// A law with state by both its curves over the communication step, tabulated
    /// ([`StepCurves`]): an internal step ending at the fraction theta of the
    /// communication step (as for `Step`) solves the piecewise linear interpolant of
    /// (1 - theta) F + theta F_h as the scene's law is solved
    /// ([`crate::friction::tabulated::BlendedCurve`]), against the static limit given.
    Table(StepCurves),
}

/// Where the step after `taken` of `planned` steps ends in its window, as a fraction
/// clamped to [0, 1]; 1 for an empty window.
fn window_fraction((taken, planned): (u64, u64)) -> f64 {
    if planned > 0 {
        ((taken + 1) as f64 / planned as f64).min(1.0)
    } else {
        1.0
    }
}

/// Why a saved state does not fit a simulator.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("saved state does not fit this model: {0}")]
pub struct StateMismatch(pub String);

/// Puts `law` in the saved state `law_state` if it fits: a law with state checks its
/// length and domain (`StatefulLaw::set_state`), a memoryless law takes only an empty one.
/// The law is unchanged on refusal. What [`Simulator::restore`] does with a state's
/// law state, for a caller that checks a saved state before building a simulation.
pub fn set_law_state(law: &mut dyn FrictionLaw, law_state: &[f64]) -> Result<(), StateMismatch> {
    if let Some(memory) = law.as_stateful_mut() {
        return memory
            .set_state(law_state)
            .map_err(|e| StateMismatch(e.to_string()));
    }
    if law_state.is_empty() {
        Ok(())
    } else {
        Err(StateMismatch(format!(
            "law_state has {} values, the law {} has no state",
            law_state.len(),
            law.name()
        )))
    }
}

/// The stick-slip simulation of one scene.
pub struct Simulator {
    scene: CheckedScene,
    model: StructuralModel,
    integrator: Integrator,
    /// With `contact.damping_phase = slip`: the undamped integrator of the stick phase
    /// (`integrator` is then the slip phase's). None otherwise.
    stick_integrator: Option<Integrator>,
    /// With `contact.slip_modes_below` > 0: the modes slip runs on, the slip phase's
    /// integrator on their modal model, and the modal coordinates of a step (scratch).
    modal_slip: Option<ModalSlip>,
    contact: Contact,
    law: Box<dyn FrictionLaw>,
    belt_speed: f64,
    normal_force: f64,
    external: Option<ExternalFriction>,
    /// The current `advance` call, the coupling's communication step, in internal
    /// steps: (taken, planned). Where within it a step ends, (taken + 1) / planned,
    /// weights `ExternalKinetic::Step`'s two tangents. Counted in steps, not read off
    /// the clocks, so that masters whose communication points differ by rounding
    /// (libcosim's nanoseconds, Ecos) give the same bits.
    window: (u64, u64),
    /// Integrator for the shorter last step that lands on a requested time; rebuilt
    /// only when that length (`landing_length`) or the phase's damping changes.
    landing: Option<Integrator>,
    landing_length: f64,
    /// Whether `landing` was built on the modal slip model.
    landing_modal: bool,
    state: SimulationState,
    /// The most recent transitions, oldest first (see [`Simulator::transitions`]).
    transitions: Vec<Transition>,
    /// Keep every transition instead of the most recent ones.
    keep_all_transitions: bool,
    /// The slip solve of the last step, if it needed one.
    last_slip: Option<SlipSolve>,
    /// For each component of the law's state listed in [`STATE_VARIABLES`]: its
    /// position in `SimulationState::law_state` and its index in the list; empty for a
    /// memoryless law.
    law_state_slots: Vec<(usize, usize)>,
}

/// How many transitions a simulator keeps at least, unless asked to keep all of them
/// ([`Simulator::keep_all_transitions`]). It holds between this many and twice this many
/// of the most recent ones: when the list reaches twice the bound, the older half is
/// dropped at once, so that recording a transition stays O(1) amortised. The list
/// then never takes more than 2 x 1024 x 16 bytes = 32 KiB, however long the run; the
/// count of all transitions is `SimulationState::transition_count`.
pub const RECENT_TRANSITIONS: usize = 1024;

/// Two times closer than this fraction of the step are the same time (landing on a
/// communication point must not leave a step of 1e-20 s behind; 1e-6 dt = 1e-10 s at
/// the paper's step, far below anything the outputs resolve).
const SAME_TIME: f64 = 1e-6;

impl Simulator {
    /// Builds the model the scene asks for and sets up the simulation with `law`.
    pub fn new(scene: CheckedScene, law: Box<dyn FrictionLaw>) -> Result<Self, SimulationError> {
        let model = StructuralModel::build(&scene)?;
        Self::with_model(scene, model, law)
    }

    /// Sets up the simulation on a given model (the scene's fidelity is then ignored).
    pub fn with_model(
        scene: CheckedScene,
        model: StructuralModel,
        mut law: Box<dyn FrictionLaw>,
    ) -> Result<Self, SimulationError> {
        if law.as_stateful().is_some() {
            // The scene check refuses the laws it knows to have state; a network's
            // state shows only in its weights.
            let named = format!(
                "{} (its law {} has state)",
                crate::choice::Choice::name(scene.friction.law),
                law.name()
            );
            if let Some(error) = scene.contact.refusal_with_memory(&named) {
                return Err(error.into());
            }
        }
        let (a, b) = phase_damping(&scene, ContactState::Slip);
        let integrator = Integrator::new(
            &model,
            Coefficients::from_scene(&scene),
            scene.time.step,
            a,
            b,
        )?;
        let stick_integrator = match scene.contact.damping_phase {
            DampingPhase::Always => None,
            DampingPhase::Slip => Some(Integrator::undamped(
                &model,
                Coefficients::from_scene(&scene),
                scene.time.step,
            )?),
        };
        let contact = Contact::new(&scene, integrator.coefficients());
        let mut state = initial_state(&scene, &model)?;
        let mut law_state_slots = Vec::new();
        if let Some(memory) = law.as_stateful_mut() {
            if scene.contact.preload > 0.0 {
                memory.hold(state.holding_force, scene.loading.normal_force);
            }
            state.law_state = memory.state().to_vec();
            law_state_slots = slots_of(memory.state_variables());
        }
        let modal_slip = match scene.contact.slip_modes_below {
            cutoff if cutoff > 0.0 => Some(ModalSlip::new(&scene, &model, cutoff)?),
            _ => None,
        };
        Ok(Self {
            belt_speed: scene.loading.belt_speed,
            normal_force: scene.loading.normal_force,
            scene,
            model,
            integrator,
            stick_integrator,
            modal_slip,
            contact,
            law,
            external: None,
            window: (0, 1),
            landing: None,
            landing_length: 0.0,
            landing_modal: false,
            state,
            transitions: Vec::with_capacity(256),
            keep_all_transitions: false,
            last_slip: None,
            law_state_slots,
        })
    }

    pub fn scene(&self) -> &CheckedScene {
        &self.scene
    }

    pub fn model(&self) -> &StructuralModel {
        &self.model
    }

    pub fn law_name(&self) -> &str {
        self.law.name()
    }

    /// The indices in [`STATE_VARIABLES`] (and in [`Sample::law_state`]) of the run's
    /// law's state variables, in the law's order; none for a memoryless law.
    pub fn law_state_slots(&self) -> Vec<usize> {
        self.law_state_slots.iter().map(|&(_, slot)| slot).collect()
    }

    pub fn state(&self) -> &SimulationState {
        &self.state
    }

    /// Replaces the evolving state (for FMU get/set state). Refuses a state whose size
    /// does not match the model or that holds non-finite numbers; the simulator is
    /// unchanged then. The list of transitions starts empty again: the restored state
    /// carries their count, not the transitions themselves.
    pub fn restore(&mut self, state: SimulationState) -> Result<(), StateMismatch> {
        let n = self.model.dofs();
        let k = &state.kinematics;
        for (name, v) in [
            ("displacement", &k.displacement),
            ("velocity", &k.velocity),
            ("acceleration", &k.acceleration),
        ] {
            if v.len() != n {
                return Err(StateMismatch(format!(
                    "{name} has {} entries, the model has {n} degrees of freedom",
                    v.len()
                )));
            }
            if v.iter().any(|x| !x.is_finite()) {
                return Err(StateMismatch(format!("{name} holds a non-finite value")));
            }
        }
        let scalars = [
            ("time", state.time),
            ("relative_velocity", state.relative_velocity),
            ("contact_force", state.contact_force),
            ("holding_force", state.holding_force),
            ("anchor_time", state.anchor_time),
        ];
        if let Some((name, _)) = scalars.iter().find(|(_, v)| !v.is_finite()) {
            return Err(StateMismatch(format!("{name} is not finite")));
        }
        // No run reaches 2^53 steps (centuries); larger counts would overflow when
        // stepped on (tests/fmu/fuzz_regressions.rs).
        for (name, count) in [
            ("step", state.step),
            ("steps_since_anchor", state.steps_since_anchor),
        ] {
            if count > 1 << 53 {
                return Err(StateMismatch(format!("{name} = {count} is above 2^53")));
            }
        }
        set_law_state(self.law.as_mut(), &state.law_state)?;
        self.state = state;
        self.transitions.clear();
        Ok(())
    }

    /// Friction from a coupled model instead of the law and mu_s F_n; `None` returns to
    /// the scene's law.
    pub fn set_external_friction(&mut self, external: Option<ExternalFriction>) {
        self.external = external;
    }

    /// The most recent stick/slip transitions, oldest first: every one since the start
    /// (or the last [`Self::restore`]) after [`Self::keep_all_transitions`], otherwise
    /// at least the last [`RECENT_TRANSITIONS`] of them (all of them while there are
    /// fewer). `state().transition_count` counts them all.
    pub fn transitions(&self) -> &[Transition] {
        &self.transitions
    }

    /// Keeps every transition from now on, for a consumer that needs the whole list
    /// (the run summary, `metrics::Summary`). Its memory then grows with the run.
    pub fn keep_all_transitions(&mut self) {
        self.keep_all_transitions = true;
    }

    /// Solves the slip force with `solver` from now on: Newton by default, the
    /// fixed-point iteration of earlier versions as the reference to compare with.
    pub fn set_slip_solver(&mut self, solver: SlipSolver) {
        self.contact.set_slip_solver(solver);
    }

    /// How the last step's slip solve went (law evaluations, solved or not); None if
    /// the step needed none.
    pub fn last_slip_solve(&self) -> Option<SlipSolve> {
        self.last_slip
    }

    /// Belt speed input v_b (m/s).
    pub fn set_belt_speed(&mut self, v: f64) {
        self.belt_speed = v;
    }

    /// Normal force input F_n (N).
    pub fn set_normal_force(&mut self, f: f64) {
        self.normal_force = f;
    }

    /// Current output sample.
    pub fn sample(&self) -> Sample {
        let k = &self.state.kinematics;
        Sample {
            time: self.state.time,
            tip_deflection: self.model.tip_value(&k.displacement),
            tip_velocity: self.model.tip_value(&k.velocity),
            relative_velocity: self.state.relative_velocity,
            friction_force: self.state.contact_force,
            holding_force: self.state.holding_force,
            stick: self.state.contact == ContactState::Stick,
            law_state: self.law_state_values(),
        }
    }

    /// Each sensor's reading now, in the model's sensor order (empty without sensors).
    pub fn sensor_readings(&self) -> Vec<SensorReading> {
        let k = &self.state.kinematics;
        self.model
            .sensors
            .iter()
            .map(|s| SensorReading {
                displacement: observe(s, &k.displacement),
                velocity: observe(s, &k.velocity),
            })
            .collect()
    }

    /// The committed law state of `state` spread over [`STATE_VARIABLES`]: read off the
    /// simulation state, so that after [`Self::restore`] it is the restored one.
    fn law_state_values(&self) -> LawStateValues {
        let mut values = [0.0; STATE_VARIABLES.len()];
        for &(k, slot) in &self.law_state_slots {
            values[slot] = self.state.law_state[k];
        }
        values
    }

    /// Static limit (N): mu_s F_n, or the external one when set.
    pub fn static_limit(&self) -> f64 {
        match self.external {
            Some(e) => e.static_limit,
            None => self.scene.friction.static_coefficient * self.normal_force,
        }
    }

    /// Advances one time step. No allocation, except when a transition is recorded
    /// beyond the reserved capacity (which stops growing at 2 [`RECENT_TRANSITIONS`]
    /// unless all transitions are kept).
    pub fn step(&mut self) -> Result<(), SimulationError> {
        self.window = (0, 1);
        self.take_step(false).map(|_| ())
    }

    /// Advances to `target` (s) and ends exactly there. Full steps, then, when `target`
    /// is off the step grid, a landing step of the rest. A rest shorter than half a step
    /// is not taken alone: the last full step and the rest become two equal steps, so
    /// that no step is much shorter than dt. (A very short step turns any mismatch of
    /// the tip velocity into a huge stick force.) A target within 1e-6 steps of the grid
    /// is reached by full steps alone. Refuses more than `MAX_STEPS` steps at once.
    pub fn advance_to(&mut self, target: f64) -> Result<(), SimulationError> {
        self.advance(target, false).map(|_| ())
    }

    /// Advances towards `target` (s) as [`Self::advance_to`] does, but stops at the end
    /// of the first step in which the contact switched between stick and slip, and
    /// returns that time (s): the time of the transition just recorded
    /// (`transitions().last()`), which is also the new `state().time`. (For a switch in
    /// the step that lands on `target`, the simulation ends on `target` exactly, as
    /// `advance_to` does, and returns `Some(target)`; the record is `target` to
    /// rounding.) `None` when no
    /// switch happened: the simulation is then at `target`, with the same steps and the
    /// same numbers as `advance_to`.
    ///
    /// For a co-simulation master that wants to exchange values at the switch (FMI 3.0
    /// early return): the step grid up to the switch is `advance_to`'s, so the switch
    /// time is known to within one internal step; a stop inside a split landing (see
    /// `advance_to`) leaves the simulation off the dt grid, and the next advance counts
    /// its full steps from there.
    pub fn advance_until_switch(&mut self, target: f64) -> Result<Option<f64>, SimulationError> {
        self.advance(target, true)
    }

    fn advance(
        &mut self,
        target: f64,
        stop_at_switch: bool,
    ) -> Result<Option<f64>, SimulationError> {
        let dt = self.integrator.dt();
        let tolerance = SAME_TIME * dt;
        let invalid = SimulationError::InvalidTarget {
            time: self.state.time,
            target,
        };
        if !target.is_finite() || target < self.state.time - tolerance {
            return Err(invalid);
        }
        let steps = ((target - self.state.time + tolerance) / dt).floor();
        if steps > crate::scene::MAX_STEPS {
            return Err(invalid);
        }
        let mut full_steps = steps as u64;
        let rest = target - (self.state.time + full_steps as f64 * dt);
        let split = rest > tolerance && rest < 0.5 * dt && full_steps >= 1;
        if split {
            full_steps -= 1;
        }
        let landing_steps = if split { 2 } else { 1 };
        let landing = rest > tolerance || split;
        self.window = (0, full_steps + if landing { landing_steps } else { 0 });
        for _ in 0..full_steps {
            if self.take_step(false)? && stop_at_switch {
                if (target - self.state.time).abs() <= tolerance {
                    // The last step, with nothing left to land: end on `target`, as
                    // advance_to does.
                    self.land_on(target);
                    return Ok(Some(target));
                }
                return Ok(Some(self.state.time));
            }
        }
        let remaining = target - self.state.time;
        if remaining > tolerance {
            self.landing_length = remaining / landing_steps as f64;
            for k in 0..landing_steps {
                let switched = self.take_step(true)?;
                if switched && stop_at_switch && k + 1 < landing_steps {
                    return Ok(Some(self.state.time));
                }
                if switched && stop_at_switch {
                    self.land_on(target);
                    return Ok(Some(target));
                }
            }
        }
        self.land_on(target);
        Ok(None)
    }

    /// Ends an advance exactly on `target`: the landing steps reach it to rounding.
    fn land_on(&mut self, target: f64) {
        if self.state.time != target {
            self.state.time = target;
            self.state.anchor_time = target;
            self.state.steps_since_anchor = 0;
        }
    }

    /// Takes one step; true when the contact switched between stick and slip in it.
    /// The step's damping is that of the phase the contact is in at its start, so that
    /// with `damping_phase = slip` the damping switches at the transitions.
    fn take_step(&mut self, landing: bool) -> Result<bool, SimulationError> {
        let damping = phase_damping(&self.scene, self.state.contact);
        let static_limit = self.static_limit();
        // A step that starts in slip runs on the modal slip model, if there is one.
        let on_modes = self.modal_slip.is_some() && self.state.contact == ContactState::Slip;
        if landing {
            self.prepare_landing(on_modes, damping)?;
        }
        let dt = self.step_parts(landing).0.integrator.dt();
        let trial = self.trial(landing);
        let resolution = self.resolve(&trial, static_limit);
        self.window.0 += 1;
        self.finish(landing, resolution.force);
        self.record(landing, dt, &trial, resolution)
    }

    /// Landing seam: makes `landing` the integrator of a landing step of
    /// `landing_length` with the Rayleigh coefficients `damping`, on the modal slip
    /// model when `on_modes`; the one built for an earlier landing is kept when it fits.
    fn prepare_landing(
        &mut self,
        on_modes: bool,
        damping: (f64, f64),
    ) -> Result<(), SimulationError> {
        let length = self.landing_length;
        let reusable = on_modes == self.landing_modal
            && matches!(&self.landing, Some(i) if i.dt() == length && i.damping() == damping);
        if !reusable {
            let model = match &self.modal_slip {
                Some(m) if on_modes => m.basis.model(),
                _ => &self.model,
            };
            self.landing_modal = on_modes;
            self.landing = Some(Integrator::new(
                model,
                Coefficients::from_scene(&self.scene),
                length,
                damping.0,
                damping.1,
            )?);
        }
        Ok(())
    }

    /// What a step runs on, chosen by its kind (`landing`) and the contact state at its
    /// start: the landing integrator, the modal slip model's, the stick phase's or the
    /// main one. Returned beside the simulation state so that a seam can change both.
    /// The choice is the same every time it is asked within a step, since neither the
    /// contact state nor the integrators change until the step is recorded.
    fn step_parts(&mut self, landing: bool) -> (StepParts<'_>, &mut SimulationState) {
        let modal = match &mut self.modal_slip {
            Some(m) if self.state.contact == ContactState::Slip => Some(m),
            _ => None,
        };
        let parts = match (
            landing,
            self.landing.as_mut(),
            self.stick_integrator.as_mut(),
            modal,
        ) {
            (true, Some(short), _, Some(m)) => StepParts {
                integrator: short,
                model: m.basis.model(),
                modal: Some((&m.basis, &mut m.state)),
            },
            (true, Some(short), _, None) => StepParts {
                integrator: short,
                model: &self.model,
                modal: None,
            },
            (false, _, _, Some(m)) => StepParts {
                integrator: &mut m.integrator,
                model: m.basis.model(),
                modal: Some((&m.basis, &mut m.state)),
            },
            (false, _, Some(stick), None) if self.state.contact == ContactState::Stick => {
                StepParts {
                    integrator: stick,
                    model: &self.model,
                    modal: None,
                }
            }
            _ => StepParts {
                integrator: &mut self.integrator,
                model: &self.model,
                modal: None,
            },
        };
        (parts, &mut self.state)
    }

    /// Trial seam: the step's solve without tip force, which the contact resolves the
    /// force from. With `contact.tip_velocity = finite-difference` its tip velocities
    /// are recast as differences of tip displacements.
    fn trial(&mut self, landing: bool) -> TrialStep {
        let finite_difference = self.scene.contact.tip_velocity == TipVelocity::FiniteDifference;
        let vb = self.belt_speed;
        let (mut parts, state) = self.step_parts(landing);
        let dt = parts.integrator.dt();
        // In slip on modes: q = Phi^T M x of the full state (a state already in their
        // span after the first slip step, so that this is exact; at stick -> slip it drops
        // the modes above the cut-off), expanded back after the step.
        if let Some((basis, q)) = &mut parts.modal {
            basis.project_kinematics(&state.kinematics, q);
        }
        let mut trial = match &parts.modal {
            Some((_, q)) => parts.integrator.trial(parts.model, q),
            None => parts.integrator.trial(parts.model, &state.kinematics),
        };
        if finite_difference {
            // v_tip,n+1 = (u_tip,n+1 - u_tip,n) / dt is affine in F as the integrator's
            // velocity is: the contact solves on it unchanged.
            trial.start_tip_velocity = vb - state.relative_velocity;
            trial.free_tip_velocity =
                (trial.free_tip_displacement - trial.start_tip_displacement) / dt;
            trial.velocity_per_force = trial.displacement_per_force / dt;
        }
        trial
    }

    /// Resolve seam: the contact's tip force for the step from its `trial` (stick
    /// reaction, slip solve, switch), against `static_limit` and with the kinetic force
    /// of the external input or the law. A law with state advances its state here, and
    /// the simulation state keeps a copy.
    fn resolve(&mut self, trial: &TrialStep, static_limit: f64) -> Resolution {
        let vb = self.belt_speed;
        let state = &mut self.state;
        let previous = Previous {
            state: state.contact,
            relative_velocity: state.relative_velocity,
            force: state.contact_force,
        };
        match (self.external, self.law.as_stateful_mut()) {
            (None, Some(law)) => {
                let resolution =
                    self.contact
                        .resolve_with_memory(trial, previous, vb, law, self.normal_force);
                state.law_state.clear();
                state.law_state.extend_from_slice(law.state());
                resolution
            }
            (external, _) => {
                let mut table;
                let kinetic = match external {
                    Some(ExternalFriction {
                        kinetic: ExternalKinetic::Magnitude(force),
                        ..
                    }) => Kinetic::External { force },
                    Some(ExternalFriction {
                        kinetic:
                            ExternalKinetic::Signed {
                                force,
                                slope,
                                velocity,
                            },
                        ..
                    }) => Kinetic::ExternalSigned {
                        force,
                        slope,
                        velocity,
                        direction: Direction::AlongSlip,
                    },
                    Some(ExternalFriction {
                        kinetic:
                            ExternalKinetic::Step {
                                force,
                                slope,
                                step_force,
                                step_slope,
                                velocity,
                            },
                        ..
                    }) => {
                        let theta = window_fraction(self.window);
                        Kinetic::ExternalSigned {
                            force: (1.0 - theta) * force + theta * step_force,
                            slope: (1.0 - theta) * slope + theta * step_slope,
                            velocity,
                            direction: Direction::AcrossZero,
                        }
                    }
                    Some(ExternalFriction {
                        kinetic: ExternalKinetic::Table(curves),
                        ..
                    }) => {
                        table = curves.blended(window_fraction(self.window));
                        Kinetic::Law {
                            law: &mut table,
                            normal_force: self.normal_force,
                        }
                    }
                    None => Kinetic::Law {
                        law: self.law.as_mut(),
                        normal_force: self.normal_force,
                    },
                };
                self.contact
                    .resolve(trial, previous, vb, static_limit, kinetic)
            }
        }
    }

    /// Finish seam: the step's end kinematics under the resolved tip `force`, expanded
    /// back onto the full model when the step ran on the slip modes.
    fn finish(&mut self, landing: bool, force: f64) {
        let (parts, state) = self.step_parts(landing);
        match parts.modal {
            Some((basis, q)) => {
                parts.integrator.finish(q, force);
                basis.expand_kinematics(q, &mut state.kinematics);
            }
            None => parts.integrator.finish(&mut state.kinematics, force),
        }
    }

    /// Record seam: the step of length `dt` counted and timed, the tip's relative
    /// velocity and the `resolution`'s forces stored, and a switch of the contact state
    /// recorded as a transition. A non-finite tip state is refused. True when the
    /// contact switched.
    fn record(
        &mut self,
        landing: bool,
        dt: f64,
        trial: &TrialStep,
        resolution: Resolution,
    ) -> Result<bool, SimulationError> {
        let finite_difference = self.scene.contact.tip_velocity == TipVelocity::FiniteDifference;
        let vb = self.belt_speed;
        let state = &mut self.state;
        self.last_slip = resolution.slip;
        state.step += 1;
        if landing {
            state.time += dt;
            state.anchor_time = state.time;
            state.steps_since_anchor = 0;
        } else {
            state.steps_since_anchor += 1;
            state.time = state.anchor_time + state.steps_since_anchor as f64 * dt;
        }
        let new_tip_u = self.model.tip_value(&state.kinematics.displacement);
        let new_tip_v = if finite_difference {
            (new_tip_u - trial.start_tip_displacement) / dt
        } else {
            self.model.tip_value(&state.kinematics.velocity)
        };
        let relative = vb - new_tip_v;
        if ![
            new_tip_u,
            new_tip_v,
            resolution.force,
            resolution.holding_force,
            relative,
        ]
        .iter()
        .all(|x| x.is_finite())
        {
            return Err(SimulationError::NonFinite {
                time: state.time,
                quantity: "tip state",
            });
        }
        state.relative_velocity = relative;
        state.contact_force = resolution.force;
        state.holding_force = resolution.holding_force;
        if resolution.state != state.contact {
            state.transition_count += 1;
            if !self.keep_all_transitions && self.transitions.len() >= 2 * RECENT_TRANSITIONS {
                self.transitions
                    .drain(..self.transitions.len() - RECENT_TRANSITIONS);
            }
            self.transitions.push(Transition {
                time: state.time,
                to: resolution.state,
            });
        }
        let switched = resolution.state != state.contact;
        state.contact = resolution.state;
        Ok(switched)
    }

    /// Runs to the scene's end time, recording a sample every `every` steps (and the
    /// initial one).
    pub fn run(&mut self, every: usize) -> Result<Vec<Sample>, SimulationError> {
        Ok(self.run_observed(every)?.0)
    }

    /// [`Self::run`], with the sensors' readings at each sample (none without sensors).
    #[allow(clippy::type_complexity)]
    pub fn run_observed(
        &mut self,
        every: usize,
    ) -> Result<(Vec<Sample>, Vec<Vec<SensorReading>>), SimulationError> {
        let every = every.max(1) as u64;
        let steps = (self.scene.time.end / self.scene.time.step).round() as u64;
        let mut samples = Vec::with_capacity((steps / every + 2) as usize);
        let observing = !self.model.sensors.is_empty();
        let mut readings = Vec::new();
        let mut record = |sim: &Self| {
            samples.push(sim.sample());
            if observing {
                readings.push(sim.sensor_readings());
            }
        };
        record(self);
        while self.state.step < steps {
            self.step()?;
            if self.state.step.is_multiple_of(every) || self.state.step == steps {
                record(self);
            }
        }
        Ok((samples, readings))
    }
}

/// Where a law's state variables sit: (position in the law's state, index in
/// [`STATE_VARIABLES`]) for each one listed there. A law of a library user whose
/// variable the list lacks still runs; that variable only reaches no output (the list
/// holds every law of this crate, tested in `friction::state`).
fn slots_of(variables: &[StateVariable]) -> Vec<(usize, usize)> {
    variables
        .iter()
        .enumerate()
        .filter_map(|(k, v)| {
            STATE_VARIABLES
                .iter()
                .position(|listed| listed == v)
                .map(|slot| (k, slot))
        })
        .collect()
}

/// What one step runs on (see `Simulator::step_parts`).
struct StepParts<'a> {
    integrator: &'a mut Integrator,
    model: &'a StructuralModel,
    /// When the step runs on the slip modes: their basis and the step's modal
    /// coordinates.
    modal: Option<(&'a SlipBasis, &'a mut Kinematics)>,
}

/// The slip phase on modes below a cut-off (`contact.slip_modes_below`).
struct ModalSlip {
    basis: SlipBasis,
    /// The slip phase's integrator on the modal model.
    integrator: Integrator,
    /// Modal coordinates during a step.
    state: Kinematics,
}

impl ModalSlip {
    fn new(
        scene: &CheckedScene,
        model: &StructuralModel,
        cutoff: f64,
    ) -> Result<Self, SimulationError> {
        if model.damping.is_some() {
            return Err(ModelError::UserStructure(
                "contact.slip_modes_below with structure.damping: the slip phase's modal basis does not carry a damping matrix from a file yet; leave slip_modes_below at 0 or use the scene's Rayleigh damping".to_string(),
            )
            .into());
        }
        let basis = SlipBasis::below(model, cutoff)?;
        let (a, b) = phase_damping(scene, ContactState::Slip);
        let integrator = Integrator::new(
            basis.model(),
            Coefficients::from_scene(scene),
            scene.time.step,
            a,
            b,
        )?;
        let state = Kinematics::at_rest(basis.len());
        Ok(Self {
            basis,
            integrator,
            state,
        })
    }
}

/// The Rayleigh coefficients (a, b) of a step that starts in contact state `contact`.
fn phase_damping(scene: &CheckedScene, contact: ContactState) -> (f64, f64) {
    match (scene.contact.damping_phase, contact) {
        (DampingPhase::Slip, ContactState::Stick) => (0.0, 0.0),
        _ => (
            scene.damping.mass_proportional,
            scene.damping.stiffness_proportional,
        ),
    }
}

/// The state at t = 0: stuck to the belt, undeformed or in the static shape under the
/// preload.
fn initial_state(
    scene: &CheckedScene,
    model: &StructuralModel,
) -> Result<SimulationState, SimulationError> {
    let n = model.dofs();
    let mut kinematics = Kinematics::at_rest(n);
    let vb = scene.loading.belt_speed;
    let mut holding = 0.0;
    if scene.contact.preload > 0.0 {
        // u_0 = K^-1 c P: K u_0 = c P is balanced by a holding force P, so the
        // acceleration below is unchanged by the preload.
        let load =
            scene.contact.preload * scene.friction.static_coefficient * scene.loading.normal_force;
        kinematics.displacement = model.static_displacement(load)?;
        holding = load;
    }
    if scene.contact.initial_state == InitialState::QuasiStatic {
        // v_0 = v_b psi / (c . psi) with psi = K^-1 c: the tip at belt speed and the rest
        // of the beam moving in the static tip-load shape, so that the first step needs
        // no impulsive holding force.
        let psi = model.static_displacement(1.0)?;
        let tip_psi = model.tip_value(&psi);
        kinematics.velocity = psi.iter().map(|p| vb * p / tip_psi).collect();
        // Consistent acceleration with the tip held (c . a_0 = 0) under C = a M + b K:
        // M a_0 = -C v_0 + c lambda_0 gives a_0 = -a v_0 + (a v_b / (c . w)) w with
        // w = M^-1 c, and lambda_0 = a v_b / (c . w) + b v_b / (c . psi).
        let (a, b) = phase_damping(scene, ContactState::Stick);
        let mass_factor = model.mass.cholesky().map_err(singular("mass"))?;
        let mut w = model.tip_vector();
        mass_factor.solve_in_place(&mut w);
        let tip_w = model.tip_value(&w);
        for ((acc, vel), wi) in kinematics
            .acceleration
            .iter_mut()
            .zip(&kinematics.velocity)
            .zip(&w)
        {
            *acc = -a * vel + a * vb / tip_w * wi;
        }
        holding += a * vb / tip_w + b * vb / tip_psi;
    }
    Ok(SimulationState {
        step: 0,
        time: 0.0,
        kinematics,
        contact: ContactState::Stick,
        relative_velocity: 0.0,
        contact_force: holding,
        holding_force: holding,
        transition_count: 0,
        anchor_time: 0.0,
        steps_since_anchor: 0,
        law_state: Vec::new(),
    })
}
