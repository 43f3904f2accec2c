//! The scene: every parameter of the stick-slip set-up, in SI units.
//!
//! A [`Scene`] is plain data (serde, loadable from TOML or JSON). It becomes usable only
//! through [`Scene::check`], which validates every field once and returns a
//! [`CheckedScene`]; everything downstream takes a `CheckedScene` and does not re-check.
//!
//! Every closed set of options is a [`Choice`](crate::choice::Choice) enum defined here
//! (friction law, holding force, sliding velocity, initial state, fidelity level, modal
//! basis, clamp, scheme): the scene file's words, the command line's values and the FMI
//! enumeration items with their descriptions are all read from these enums.
//!
//! Two values are requests that only some places can honour, so a checked scene may
//! hold them but a run refuses them: `fidelity.level = auto` (with `fidelity.tolerance`)
//! is resolved by [`crate::auto::resolve`] into a concrete scene before it runs, and
//! `friction.law = external` takes its force from the StickSlipBeam FMU's inputs.
//! `StructuralModel::build` refuses an unresolved auto and `run::run_scene` refuses
//! external, each with a message that says so.
//!
//! `Scene::default()` is the paper's scene (Vater, Stender, Hoffmann, PAMM 2023,
//! Fig. 1a and Sections 3-4): L = 2 m, h = 0.01 m, rho = 1000 kg/m3, E = 200 GPa,
//! v_b = 0.02 m/s, F_n = 100 N, mu_s = 0.5, mu_k = 0.2, alpha = 5 s/m, eps = 1e-3 m/s,
//! dt = 1e-4 s, t_end = 1.2 s. The paper does not give Poisson's ratio; 0.3 (steel) is used.

use crate::friction::parameters::ParameterProblem;
use crate::friction::registry::{Coefficients, LawTables};
use crate::friction::{exponential::ExponentialLaw, FrictionLawKind};
use crate::neural::inference::Inference;
use crate::user_structure::StructureSection;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Beam geometry (m). Plane stress with out-of-plane width `width`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Geometry {
    /// Beam length L (m).
    pub length: f64,
    /// Beam height h (m), in the direction of the tip deflection.
    pub height: f64,
    /// Out-of-plane width b (m); the paper's plane-stress model uses unit width.
    pub width: f64,
}

impl Default for Geometry {
    fn default() -> Self {
        Self {
            length: 2.0,
            height: 0.01,
            width: 1.0,
        }
    }
}

/// Linear elastic, isotropic material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Material {
    /// Mass density rho (kg/m3).
    pub density: f64,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio nu (1); used by the plane-stress model only.
    pub poisson_ratio: f64,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            density: 1000.0,
            youngs_modulus: 200e9,
            poisson_ratio: 0.3,
        }
    }
}

/// The conveyor belt under the tip.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Loading {
    /// Belt speed v_b (m/s), in the tip's transverse direction.
    pub belt_speed: f64,
    /// Normal force F_n pressing the tip on the belt (N).
    pub normal_force: f64,
}

impl Default for Loading {
    fn default() -> Self {
        Self {
            belt_speed: 0.02,
            normal_force: 100.0,
        }
    }
}

/// Friction parameters (paper, Eq. 3 and Eq. 6) and the stick threshold.
///
/// Unknown keys are refused by [`LawTables`], which receives every key not named here
/// (serde's `deny_unknown_fields` does not combine with `flatten`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Friction {
    /// Kinetic law used during slip.
    pub law: FrictionLawKind,
    /// Static coefficient mu_s (1): stick holds while |F_hold| <= mu_s F_n.
    pub static_coefficient: f64,
    /// Kinetic coefficient mu_k (1): the high-speed limit of the exponential law.
    pub kinetic_coefficient: f64,
    /// Decay alpha of the exponential law (s/m).
    pub decay: f64,
    /// Stick threshold eps (m/s): slip -> stick is considered when |v_rel| < eps.
    pub stick_threshold: f64,
    /// Weights file of the neural law; `None` uses the weights shipped with the crate.
    pub weights: Option<String>,
    /// How the neural law's network is evaluated (speed for accuracy; the other laws
    /// ignore it).
    pub inference: Inference,
    /// Every law's own parameters, `[friction.<law>]` (`friction::registry`): each law
    /// reads its table, the others ignore it.
    #[serde(flatten)]
    pub laws: LawTables,
}

impl Default for Friction {
    fn default() -> Self {
        Self {
            law: FrictionLawKind::Exponential,
            static_coefficient: 0.5,
            kinetic_coefficient: 0.2,
            decay: 5.0,
            stick_threshold: 1e-3,
            weights: None,
            inference: Inference::Exact,
            laws: LawTables::default(),
        }
    }
}

crate::choice! {
    /// How the holding (static friction) force is obtained during stick.
    #[choice(name = "HoldingForce", description = "How the stick holding force is obtained")]
    pub enum HoldingForce {
        /// The exact constraint reaction of the discrete equations (default).
        Reaction = "reaction": "the constraint reaction of the discrete model",
        /// The paper's literal rule: P = E h^3 delta / (4 L^3) = 3 EI delta / L^3 (unit
        /// width) from the tip deflection.
        EulerBernoulli = "euler-bernoulli": "paper-literal: 3 EI delta / L^3",
    }
}

crate::choice! {
    /// Which velocity feeds the kinetic friction law.
    #[choice(name = "SlidingVelocity", description = "The velocity the friction law is evaluated at")]
    pub enum SlidingVelocity {
        /// v_rel = v_b - v_tip (default, physically right).
        Relative = "relative": "v_rel = v_b - v_tip",
        /// The paper's literal v_s = v_tip (its magnitude, with the sign of v_rel).
        Tip = "tip": "paper-literal: |v_tip| with the sign of v_rel",
    }
}

crate::choice! {
    /// How the beam starts at t = 0.
    #[choice(name = "InitialState", description = "The state at t = 0")]
    pub enum InitialState {
        /// Undeformed, with the velocity field v_b times the static tip-load shape (tip at
        /// belt speed, consistent with the stick constraint).
        QuasiStatic = "quasi-static": "tip moving with the belt, beam in its static shape",
        /// Undeformed and at rest; the stick constraint then jerks the tip to belt speed.
        AtRest = "at-rest": "beam at rest",
    }
}

crate::choice! {
    /// In which contact phases the Rayleigh damping C = a M + b K acts.
    #[choice(name = "DampingPhase", description = "The contact phases in which the Rayleigh damping acts")]
    #[derive(Default)]
    pub enum DampingPhase {
        /// In stick and in slip (default).
        #[default]
        Always = "always": "in stick and in slip",
        /// Only while slipping: C = 0 in stick, switched at every transition (the paper
        /// authors' published script, `V_beam_transient_fea.m`).
        Slip = "slip": "only while slipping (C = 0 in stick)",
    }
}

crate::choice! {
    /// Which tip velocity the contact sees (the sliding velocity, the switch).
    #[choice(name = "TipVelocity", description = "The tip velocity the contact evaluates")]
    #[derive(Default)]
    pub enum TipVelocity {
        /// The integrator's velocity at t_{n+1} (default).
        #[default]
        Integrator = "integrator": "the integrator's tip velocity",
        /// The backward difference (u_tip,n+1 - u_tip,n) / dt, as the paper authors'
        /// script computes it; O(dt) from the integrator's. Generalised-alpha only.
        FiniteDifference = "finite-difference": "(u_tip,n+1 - u_tip,n) / dt",
    }
}

crate::choice! {
    /// The tip force over the first step of each slip phase (the step in which the
    /// holding force passes mu_s F_n).
    #[choice(name = "FirstSlipStep", description = "The tip force over the first step of each slip phase")]
    #[derive(Default)]
    pub enum FirstSlipStep {
        /// The kinetic force, as in every slip step (default).
        #[default]
        Law = "law": "the kinetic friction force, as every slip step",
        /// No friction force: the tip moves as the unloaded beam over that step (the
        /// paper authors' script, `V_beam_transient_fea.m`).
        Free = "free": "no friction force (the beam unloaded over that step)",
    }
}

crate::choice! {
    /// Which sliding velocity the kinetic force of a slip step is evaluated at.
    #[choice(name = "SlipForce", description = "When the kinetic force of a slip step is evaluated")]
    #[derive(Default)]
    pub enum SlipForce {
        /// F = F_law(x(F)) at the step's own sliding velocity (at generalised-alpha's
        /// level t_n+1-alpha_f), solved with the step (default).
        #[default]
        Implicit = "implicit": "the law at the step's own sliding velocity, solved with the step",
        /// F_n+1 = F_law(v_rel,n): the law at the relative velocity the previous step
        /// ended with (as `tip_velocity` gives it), held over the step, on every step
        /// that starts in slip (the step that leaves stick follows `first_slip_step`,
        /// implicit if loaded). Explicit, one step behind; the paper authors' script.
        /// Its loop gain |dF/dv| dv_tip/dF (dv_tip/dF about dt over the tip's modal
        /// mass) stays below 0.80 with the paper's law at every dt
        /// (docs/paper-authors-scene.md).
        Lagged = "lagged": "the law at the sliding velocity the previous step ended with, held over the step (explicit)",
    }
}

/// Contact options, including the ones that reproduce the paper literally.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Contact {
    pub holding_force: HoldingForce,
    pub sliding_velocity: SlidingVelocity,
    pub initial_state: InitialState,
    /// Tip preload at t = 0 as a fraction of F_crit = mu_s F_n (1), in [0, 1): the beam
    /// starts in the static shape under the tip load P = preload mu_s F_n, so that the
    /// tip deflection is u_0 = P / k (k the model's static tip stiffness, 3 EI / L^3 for
    /// Euler-Bernoulli) and stick reaches F_crit at t_b = (mu_s F_n / k - u_0) / v_b.
    /// `initial_state` still sets the velocity field. 0 (default): undeformed. The paper
    /// authors' script starts at rest under 1 %.
    pub preload: f64,
    /// Which tip velocity the contact evaluates.
    pub tip_velocity: TipVelocity,
    /// In which phases the damping of `damping` acts.
    pub damping_phase: DampingPhase,
    /// The model slip runs on (rad/s): 0 (default) the full model; a cut-off
    /// omega_cut > 0, the plane-stress mesh's modes below it (the paper authors'
    /// algorithm, 1e4 rad/s), with the state projected onto them at stick -> slip and
    /// expanded back at slip -> stick (`modal_slip`). Plane-stress fidelity only.
    pub slip_modes_below: f64,
    /// The tip force over the first step of each slip phase.
    pub first_slip_step: FirstSlipStep,
    /// Which sliding velocity the kinetic force of a slip step is evaluated at.
    pub slip_force: SlipForce,
}

impl Contact {
    /// The first of the paper authors' slip-phase rules (`first_slip_step`,
    /// `slip_force`) this contact sets away from its default, as (field, value).
    pub fn phase_rule(&self) -> Option<(&'static str, &'static str)> {
        use crate::choice::Choice;
        if self.first_slip_step != FirstSlipStep::Law {
            Some(("contact.first_slip_step", self.first_slip_step.name()))
        } else if self.slip_force != SlipForce::Implicit {
            Some(("contact.slip_force", self.slip_force.name()))
        } else {
            None
        }
    }

    /// Why this contact cannot run a law with state named `law` (a `friction.law`, or
    /// the network of `friction.weights` when it has state), if it cannot: the
    /// slip-phase rules need a set-valued stick and a memoryless force. A law with
    /// state has neither: every step is one slip solve whose force and state update
    /// come from the same velocity (`contact::state_law`), so it has no slip phase to
    /// begin, and a force one step behind would leave its state a step ahead.
    pub fn refusal_with_memory(&self, law: &str) -> Option<SceneError> {
        let (field, value) = self.phase_rule()?;
        let requirement = match field {
            "contact.first_slip_step" => format!(
                "law with friction.law = {law}: a law with state has no set-valued stick, so there is no first step of a slip phase to leave free (its stick is |v_rel| < eps inside the one slip solve of every step)"
            ),
            _ => format!(
                "implicit with friction.law = {law}: a law with state advances its state with the force it gives at the same velocity; a force lagged one step would leave its state a step ahead"
            ),
        };
        Some(SceneError::Invalid {
            field,
            value: value.into(),
            requirement,
        })
    }
}

impl Default for Contact {
    fn default() -> Self {
        Self {
            holding_force: HoldingForce::Reaction,
            sliding_velocity: SlidingVelocity::Relative,
            initial_state: InitialState::QuasiStatic,
            preload: 0.0,
            tip_velocity: TipVelocity::Integrator,
            damping_phase: DampingPhase::Always,
            slip_modes_below: 0.0,
            first_slip_step: FirstSlipStep::Law,
            slip_force: SlipForce::Implicit,
        }
    }
}

/// Rayleigh damping C = a M + b K.
///
/// The paper gives no damping. Its MATLAB transient solver (a stiff, variable-step
/// integrator) damps high frequencies numerically. Undamped, the beam's higher modes make
/// every slip break into bursts of re-stick/slip whose timing depends on the time step
/// (the stick-slip period then moves by ~15 % when dt is halved). The default is
/// therefore light stiffness-proportional damping, b = 5e-5 s. Its ratio
/// zeta_n = b omega_n / 2 is 0.09 % at mode 1, 1.6 % at mode 3, and grows with
/// frequency. It shifts breakaway by only c v_b / k = b = half a step at the paper's dt.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Damping {
    /// Mass-proportional coefficient a (1/s).
    pub mass_proportional: f64,
    /// Stiffness-proportional coefficient b (s).
    pub stiffness_proportional: f64,
}

impl Default for Damping {
    fn default() -> Self {
        Self {
            mass_proportional: 0.0,
            stiffness_proportional: 5e-5,
        }
    }
}

impl Damping {
    /// No damping at all.
    pub fn none() -> Self {
        Self {
            mass_proportional: 0.0,
            stiffness_proportional: 0.0,
        }
    }

    /// Rayleigh coefficients that give the damping ratio `ratio` at the two frequencies
    /// `f1_hz` and `f2_hz`: zeta(w) = a / (2 w) + b w / 2 (Chopra, Dynamics of Structures,
    /// Sec. 11.4).
    pub fn from_ratio(ratio: f64, f1_hz: f64, f2_hz: f64) -> Self {
        let (w1, w2) = (
            2.0 * std::f64::consts::PI * f1_hz,
            2.0 * std::f64::consts::PI * f2_hz,
        );
        Self {
            mass_proportional: 2.0 * ratio * w1 * w2 / (w1 + w2),
            stiffness_proportional: 2.0 * ratio / (w1 + w2),
        }
    }
}

/// Time stepping (s).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Time {
    /// Time step dt (s).
    pub step: f64,
    /// End time (s).
    pub end: f64,
}

impl Default for Time {
    fn default() -> Self {
        Self {
            step: 1e-4,
            end: 1.2,
        }
    }
}

crate::choice! {
    /// Structural model level.
    #[choice(name = "FidelityLevel", description = "Structural model")]
    pub enum FidelityLevel {
        /// Reduced model: `modes` eigenmodes of `modal_basis` plus static correction.
        Modal = "modal": "reduced modal model",
        /// Euler-Bernoulli Hermite beam elements.
        Beam = "beam": "Euler-Bernoulli beam elements",
        /// The paper's 2D plane-stress continuum (quadratic Q8 elements).
        PlaneStress = "plane-stress": "2D plane-stress mesh of 8-node quadrilaterals",
        /// Not a model but a request: the `auto` module replaces the level, the time
        /// step and the integrator by the cheapest point of the measured front whose
        /// largest tip deviation on this scene over the run meets `fidelity.tolerance`
        /// (`auto::resolve`). A scene must be resolved before a model is built from it.
        Auto = "auto": "the cheapest measured configuration that meets fidelity.tolerance on this scene",
    }
}

crate::choice! {
    /// Full model that a modal model is reduced from.
    #[choice(name = "ModalBasis", description = "The model whose modes the modal level keeps")]
    pub enum ModalBasis {
        Beam = "beam": "beam elements",
        PlaneStress = "plane-stress": "plane-stress mesh",
    }
}

crate::choice! {
    /// Boundary condition of the plane-stress model at the clamped face x = 0.
    #[choice(name = "Clamp", description = "Support of the plane-stress mesh at x = 0")]
    pub enum Clamp {
        /// u_x = 0 on the face and u_y = 0 at mid-height only: the section cannot rotate
        /// but may contract (Poisson). This is the support of the elasticity solution that
        /// Euler-Bernoulli approximates (Timoshenko and Goodier, Theory of Elasticity,
        /// Sec. 21), so the mesh converges to delta_EB (1 + shear term), +0.002 % here.
        NeutralAxis = "neutral-axis": "transverse displacement fixed on the neutral axis only",
        /// Both components fixed on the whole face. It converges to the same deflection,
        /// but only at first order, because of the stress singularities at the two corners.
        Full = "full": "every node of the clamped face fixed",
    }
}

/// Fidelity level and its resolution.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Fidelity {
    pub level: FidelityLevel,
    /// With `level = auto`: the largest tip-deflection deviation (m) over the first
    /// stick-slip cycle that the chosen configuration must meet (`auto` module doc);
    /// absent, `auto::DEFAULT_TOLERANCE`. Ignored by the other levels.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    /// Number of beam elements (beam level, and the modal basis when it is a beam).
    pub beam_elements: usize,
    /// Target element edge length of the plane-stress mesh (m).
    pub element_size: f64,
    /// Number of eigenmodes kept by the modal level.
    pub modes: usize,
    /// Full model the modal level is reduced from.
    pub modal_basis: ModalBasis,
    /// Add the static tip-load shape to the modal basis, so that the static tip
    /// stiffness is exact whatever `modes` is.
    pub static_correction: bool,
    /// Clamp of the plane-stress model.
    pub clamp: Clamp,
}

impl Default for Fidelity {
    fn default() -> Self {
        Self {
            level: FidelityLevel::PlaneStress,
            tolerance: None,
            beam_elements: 100,
            element_size: 0.02,
            modes: 10,
            modal_basis: ModalBasis::Beam,
            static_correction: true,
            clamp: Clamp::NeutralAxis,
        }
    }
}

crate::choice! {
    /// Time integration scheme.
    #[choice(name = "Scheme", description = "Time integrator")]
    pub enum Scheme {
        /// Chung-Hulbert generalised-alpha; rho_inf = 1 is Newmark average acceleration.
        GeneralizedAlpha = "generalized-alpha": "Chung-Hulbert generalised-alpha",
        /// Moreau-Jean nonsmooth theta scheme with impulse-level contact.
        MoreauJean = "moreau-jean": "Moreau-Jean theta time-stepping",
    }
}

/// Integrator and its parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Integrator {
    pub scheme: Scheme,
    /// Spectral radius at infinite frequency of generalised-alpha, in [0, 1].
    pub rho_inf: f64,
    /// Theta of Moreau-Jean, in [0.5, 1]; 0.5 is the trapezoidal rule.
    pub theta: f64,
}

impl Default for Integrator {
    fn default() -> Self {
        Self {
            scheme: Scheme::GeneralizedAlpha,
            rho_inf: 0.8,
            theta: 0.5,
        }
    }
}

/// Every parameter of the stick-slip set-up. `Scene::default()` is the paper's scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
#[serde(default, deny_unknown_fields)]
pub struct Scene {
    pub geometry: Geometry,
    pub material: Material,
    pub loading: Loading,
    pub friction: Friction,
    pub contact: Contact,
    pub damping: Damping,
    pub time: Time,
    pub fidelity: Fidelity,
    pub integrator: Integrator,
    /// A user's structure from files in place of the built-in beam (absent: the beam);
    /// `user_structure` gives the section's fields.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub structure: Option<StructureSection>,
}

/// A scene field outside its allowed range, or a file that does not parse.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SceneError {
    /// `field` holds `value`, which violates `requirement`.
    #[error("invalid scene: {field} = {value}; it must be {requirement}")]
    Invalid {
        field: &'static str,
        value: String,
        requirement: String,
    },
    /// The scene text could not be read or parsed. The message is kept rather than the
    /// I/O or parser error, so that the error stays `Clone` and `PartialEq` and the
    /// file's path can be put in front of a parser's message.
    #[error("scene file: {0}")]
    Parse(String),
    /// The scene file cannot be read (missing, a directory, a device, empty, not UTF-8).
    #[error(transparent)]
    File(#[from] crate::files::InputFileError),
}

impl SceneError {
    /// The offending field's dotted name, when the error is about one field.
    pub fn field(&self) -> Option<&'static str> {
        match self {
            SceneError::Invalid { field, .. } => Some(field),
            SceneError::Parse(_) | SceneError::File(_) => None,
        }
    }
}

/// Largest plane-stress mesh the scene accepts, in degrees of freedom; a guard against a
/// typo in `element_size` exhausting memory.
pub const MAX_DOFS: usize = 2_000_000;
/// Most beam elements a scene accepts.
pub const MAX_BEAM_ELEMENTS: usize = 100_000;

/// Most modes the modal level keeps.
pub const MAX_MODES: usize = 200;

/// Largest number of time steps a scene accepts.
pub const MAX_STEPS: f64 = 1e9;

fn invalid(field: &'static str, value: f64, requirement: &str) -> SceneError {
    SceneError::Invalid {
        field,
        value: crate::short::Short(value).to_string(),
        requirement: requirement.to_string(),
    }
}

/// `value` is finite and strictly positive.
fn positive(field: &'static str, value: f64, unit: &str) -> Result<(), SceneError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(invalid(field, value, &format!("finite and > 0 ({unit})")))
    }
}

/// `value` is finite and not negative.
fn non_negative(field: &'static str, value: f64, unit: &str) -> Result<(), SceneError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(invalid(field, value, &format!("finite and >= 0 ({unit})")))
    }
}

/// `value` lies in `[lo, hi]` (or `[lo, hi)` when `hi_open`).
fn within(
    field: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    hi_open: bool,
) -> Result<(), SceneError> {
    let above = if hi_open { value < hi } else { value <= hi };
    if value.is_finite() && value >= lo && above {
        Ok(())
    } else {
        let close = if hi_open { ")" } else { "]" };
        Err(invalid(field, value, &format!("in [{lo}, {hi}{close}")))
    }
}

/// Plane-stress mesh size for a scene: (elements along the length, elements through the
/// height). The element edge never exceeds `element_size`.
pub fn plane_stress_divisions(geometry: &Geometry, element_size: f64) -> (usize, usize) {
    let along = (geometry.length / element_size - 1e-9).ceil().max(1.0) as usize;
    let through = (geometry.height / element_size - 1e-9).ceil().max(1.0) as usize;
    (along, through)
}

// The checks of the scene's sections, in the order `Scene::check` runs them. A check
// that needs another section's value takes it as an argument, so that what each rule
// depends on shows in its signature.

impl Geometry {
    /// The beam's dimensions: finite, positive, and a beam (height below length).
    fn check(&self) -> Result<(), SceneError> {
        positive("geometry.length", self.length, "m")?;
        positive("geometry.height", self.height, "m")?;
        if self.height >= self.length {
            return Err(invalid(
                "geometry.height",
                self.height,
                &format!("smaller than geometry.length = {} m", self.length),
            ));
        }
        positive("geometry.width", self.width, "m")
    }
}

impl Material {
    /// Density and Young's modulus positive, Poisson's ratio where plane stress is defined.
    fn check(&self) -> Result<(), SceneError> {
        positive("material.density", self.density, "kg/m3")?;
        positive("material.youngs_modulus", self.youngs_modulus, "Pa")?;
        // Open at both ends: nu = -1 and nu = 0.5 make the plane-stress D singular.
        if !(self.poisson_ratio > -1.0 && self.poisson_ratio < 0.5) {
            return Err(invalid(
                "material.poisson_ratio",
                self.poisson_ratio,
                "in (-1, 0.5)",
            ));
        }
        Ok(())
    }
}

impl Loading {
    /// A finite belt speed (either sign) and a normal force not negative.
    pub fn check(&self) -> Result<(), SceneError> {
        if !self.belt_speed.is_finite() {
            return Err(invalid(
                "loading.belt_speed",
                self.belt_speed,
                "finite (m/s)",
            ));
        }
        non_negative("loading.normal_force", self.normal_force, "N")
    }
}

/// The `[structure]` section's fields (`user_structure`), then what the rest of the
/// scene must be with a user's structure: `fidelity.level` not `beam` (which names the
/// built-in beam; `plane-stress` means the structure's full model, `modal` its reduction,
/// `auto` the choice between them, `auto::structure`)
/// and `contact.holding_force = reaction` (the paper's rule uses the beam's EI).
fn check_structure(
    section: &StructureSection,
    level: FidelityLevel,
    holding: HoldingForce,
) -> Result<(), SceneError> {
    section.check_fields().map_err(|p| SceneError::Invalid {
        field: p.field,
        value: p.value,
        requirement: p.requirement,
    })?;
    // plane-stress reads as the structure's full model, modal as its reduction and auto
    // as the choice between them (docs/structures.md, "Fidelity"); beam theory needs the
    // built-in beam's geometry, which a user's structure does not have.
    if level == FidelityLevel::Beam {
        return Err(SceneError::Invalid {
            field: "fidelity.level",
            value: crate::choice::Choice::name(level).into(),
            requirement: "plane-stress (the structure's full model), modal (its reduction) or auto with a [structure]: beam is the built-in Euler-Bernoulli beam, which a user's structure is not".into(),
        });
    }
    if holding != HoldingForce::Reaction {
        return Err(SceneError::Invalid {
            field: "contact.holding_force",
            value: crate::choice::Choice::name(holding).into(),
            requirement: "reaction with a [structure]: the paper's rule 3 EI delta / L^3 is the built-in beam's".into(),
        });
    }
    Ok(())
}

impl Friction {
    /// The coefficients every law may be built from (`friction::registry`).
    pub fn coefficients(&self) -> Coefficients {
        Coefficients {
            static_coefficient: self.static_coefficient,
            kinetic_coefficient: self.kinetic_coefficient,
            decay: self.decay,
        }
    }

    /// The exponential law (paper, Eq. 6) of these coefficients, whatever law `law`
    /// names: the law itself, LuGre's g(v), and the stand-in of `law = external`.
    pub fn exponential_law(&self) -> ExponentialLaw {
        ExponentialLaw::from(self.coefficients())
    }

    /// The first parameter out of range of the law `law` names, among those it is built
    /// from besides the coefficients (its table `[friction.<law>]`).
    /// [`Friction::check`] asks it of every law's table; a caller that builds a law
    /// from parameters no check has seen (NeuralFriction's outputs read before
    /// initialisation) asks it of the one law it builds.
    pub fn law_problem(&self) -> Option<ParameterProblem> {
        self.laws.problem_of(self.law)
    }

    /// The coefficients (kinetic at most static), the exponential law's decay, the stick
    /// threshold, the weights path when given, then the laws with state's parameters:
    /// every parameter a law is built from ([`crate::law_source::LawSource`]), so that a
    /// law built from a checked section needs no check of its own.
    pub fn check(&self) -> Result<(), SceneError> {
        non_negative("friction.static_coefficient", self.static_coefficient, "1")?;
        non_negative(
            "friction.kinetic_coefficient",
            self.kinetic_coefficient,
            "1",
        )?;
        if self.kinetic_coefficient > self.static_coefficient {
            return Err(invalid(
                "friction.kinetic_coefficient",
                self.kinetic_coefficient,
                &format!(
                    "<= friction.static_coefficient = {}",
                    self.static_coefficient
                ),
            ));
        }
        non_negative("friction.decay", self.decay, "s/m")?;
        non_negative("friction.stick_threshold", self.stick_threshold, "m/s")?;
        if let Some(path) = &self.weights {
            if path.trim().is_empty() {
                return Err(SceneError::Invalid {
                    field: "friction.weights",
                    value: "\"\"".into(),
                    requirement: "a path to a weights file, or absent".into(),
                });
            }
        }
        if let Some(problem) = self.laws.problem() {
            return Err(invalid(problem.field, problem.value, &problem.requirement));
        }
        Ok(())
    }
}

impl Contact {
    /// The preload's range, then the rules that tie the contact to the friction law
    /// (`law`), to the integrator's scheme (`scheme`) and to the model (`level`).
    fn check(
        &self,
        law: FrictionLawKind,
        scheme: Scheme,
        level: FidelityLevel,
    ) -> Result<(), SceneError> {
        within("contact.preload", self.preload, 0.0, 1.0, true)?;
        if law.has_memory() {
            self.check_with_memory_law(law)?;
        }
        self.check_with_scheme(scheme)?;
        self.check_slip_modes(level)
    }

    /// What a law with state (`law`) needs of the contact: the relative sliding
    /// velocity, no modal slip and the default slip-phase rules. `fidelity = auto`
    /// chooses from the law's own measured front (`auto::front_for`).
    fn check_with_memory_law(&self, law: FrictionLawKind) -> Result<(), SceneError> {
        // A law with state is stepped with the relative slip velocity (its state
        // evolves with the slip), on the one model the whole run uses.
        if self.sliding_velocity != SlidingVelocity::Relative {
            return Err(SceneError::Invalid {
                field: "contact.sliding_velocity",
                value: crate::choice::Choice::name(self.sliding_velocity).into(),
                requirement: format!(
                    "relative with friction.law = {} (a law with state evolves with the relative slip velocity)",
                    crate::choice::Choice::name(law)
                ),
            });
        }
        if self.slip_modes_below > 0.0 {
            return Err(invalid(
                "contact.slip_modes_below",
                self.slip_modes_below,
                "0 with a law with state (it has no stick phase to keep on the full mesh)",
            ));
        }
        match self.refusal_with_memory(crate::choice::Choice::name(law)) {
            Some(error) => Err(error),
            None => Ok(()),
        }
    }

    /// What Moreau-Jean (`scheme`) refuses: the paper authors' slip-phase rules and the
    /// finite-difference tip velocity.
    fn check_with_scheme(&self, scheme: Scheme) -> Result<(), SceneError> {
        if let Some((field, value)) = self.phase_rule() {
            if scheme == Scheme::MoreauJean {
                return Err(SceneError::Invalid {
                    field,
                    value: value.into(),
                    requirement: "its default with integrator.scheme = moreau-jean (Moreau-Jean decides stick or slip afresh from each step's impulse; the rule belongs to the phases of generalised-alpha's switch)".into(),
                });
            }
        }
        if self.tip_velocity == TipVelocity::FiniteDifference && scheme == Scheme::MoreauJean {
            return Err(SceneError::Invalid {
                field: "contact.tip_velocity",
                value: crate::choice::Choice::name(TipVelocity::FiniteDifference).into(),
                requirement: "integrator (Moreau-Jean's stick holds the velocity itself, which a difference of displacements cannot)".into(),
            });
        }
        Ok(())
    }

    /// The modal slip's cut-off: not negative, and above 0 only on the plane-stress
    /// mesh (`level`).
    fn check_slip_modes(&self, level: FidelityLevel) -> Result<(), SceneError> {
        non_negative("contact.slip_modes_below", self.slip_modes_below, "rad/s")?;
        if self.slip_modes_below > 0.0 && level != FidelityLevel::PlaneStress {
            // The authors integrate slip on their continuum mesh's modes; on the beam
            // or a modal model the full model is already (close to) that basis, and
            // `auto` picks the model itself.
            return Err(invalid(
                "contact.slip_modes_below",
                self.slip_modes_below,
                "0 unless fidelity.level = plane-stress (slip on the modes of the plane-stress mesh below the cut-off)",
            ));
        }
        Ok(())
    }
}

impl Damping {
    /// Both Rayleigh coefficients finite and not negative.
    fn check(&self) -> Result<(), SceneError> {
        non_negative("damping.mass_proportional", self.mass_proportional, "1/s")?;
        non_negative(
            "damping.stiffness_proportional",
            self.stiffness_proportional,
            "s",
        )
    }
}

impl Time {
    /// Step and end positive, the step at most the end, and at most `MAX_STEPS` steps.
    fn check(&self) -> Result<(), SceneError> {
        positive("time.step", self.step, "s")?;
        positive("time.end", self.end, "s")?;
        if self.step > self.end {
            return Err(invalid(
                "time.step",
                self.step,
                &format!("<= time.end = {} s", self.end),
            ));
        }
        if self.end / self.step > MAX_STEPS {
            return Err(invalid(
                "time.step",
                self.step,
                &format!("large enough that time.end / time.step <= {MAX_STEPS:e}"),
            ));
        }
        Ok(())
    }
}

impl Fidelity {
    /// The tolerance when given, the beam's element count, the element size against the
    /// beam's length (`geometry`) and the plane-stress mesh's size, the mode count.
    fn check(&self, geometry: &Geometry) -> Result<(), SceneError> {
        // Absent, `auto` uses `auto::DEFAULT_TOLERANCE`, as the FMU's start value does.
        if let Some(tolerance) = self.tolerance {
            positive("fidelity.tolerance", tolerance, "m")?;
        }
        if self.beam_elements == 0 || self.beam_elements > MAX_BEAM_ELEMENTS {
            return Err(invalid(
                "fidelity.beam_elements",
                self.beam_elements as f64,
                &format!("in [1, {MAX_BEAM_ELEMENTS}]"),
            ));
        }
        positive("fidelity.element_size", self.element_size, "m")?;
        if self.element_size > geometry.length {
            return Err(invalid(
                "fidelity.element_size",
                self.element_size,
                &format!("<= geometry.length = {} m", geometry.length),
            ));
        }
        self.check_plane_stress_size(geometry)?;
        if self.modes == 0 || self.modes > MAX_MODES {
            return Err(invalid(
                "fidelity.modes",
                self.modes as f64,
                &format!("in [1, {MAX_MODES}]"),
            ));
        }
        Ok(())
    }

    /// When the plane-stress mesh is built (its level, or the modal level on its
    /// modes): at most `MAX_DOFS` degrees of freedom on `geometry`.
    fn check_plane_stress_size(&self, geometry: &Geometry) -> Result<(), SceneError> {
        let plane_stress_used = self.level == FidelityLevel::PlaneStress
            || (self.level == FidelityLevel::Modal && self.modal_basis == ModalBasis::PlaneStress);
        if plane_stress_used {
            let (nx, ny) = plane_stress_divisions(geometry, self.element_size);
            // Q8 nodes: (2 nx + 1)(ny + 1) corner-row nodes plus (nx + 1) ny mid-side ones.
            // In f64: with a tiny element on a long beam the count overflows usize.
            let (nx, ny) = (nx as f64, ny as f64);
            let nodes = (2.0 * nx + 1.0) * (ny + 1.0) + (nx + 1.0) * ny;
            if 2.0 * nodes > MAX_DOFS as f64 {
                return Err(invalid(
                    "fidelity.element_size",
                    self.element_size,
                    &format!("coarse enough for at most {MAX_DOFS} degrees of freedom"),
                ));
            }
        }
        Ok(())
    }
}

impl Integrator {
    /// Generalised-alpha's rho_inf in [0, 1], Moreau-Jean's theta in [0.5, 1].
    fn check(&self) -> Result<(), SceneError> {
        within("integrator.rho_inf", self.rho_inf, 0.0, 1.0, false)?;
        within("integrator.theta", self.theta, 0.5, 1.0, false)
    }
}

impl Scene {
    /// Validates every field and returns the checked scene: each section's check in
    /// turn, so that a scene with several faults reports the first in this order.
    pub fn check(self) -> Result<CheckedScene, SceneError> {
        self.geometry.check()?;
        self.material.check()?;
        self.loading.check()?;
        self.friction.check()?;
        self.contact.check(
            self.friction.law,
            self.integrator.scheme,
            self.fidelity.level,
        )?;
        self.damping.check()?;
        self.time.check()?;
        self.fidelity.check(&self.geometry)?;
        self.integrator.check()?;
        if let Some(section) = &self.structure {
            check_structure(section, self.fidelity.level, self.contact.holding_force)?;
        }
        Ok(CheckedScene(self))
    }

    /// Parses a scene from TOML text; missing fields take the paper's values.
    pub fn from_toml_str(text: &str) -> Result<Scene, SceneError> {
        toml::from_str(text).map_err(|e| SceneError::Parse(e.to_string()))
    }

    /// Parses a scene from JSON text; missing fields take the paper's values.
    pub fn from_json_str(text: &str) -> Result<Scene, SceneError> {
        serde_json::from_str(text).map_err(|e| SceneError::Parse(e.to_string()))
    }

    /// Reads a `.toml` or `.json` scene file and checks it.
    pub fn load(path: &Path) -> Result<CheckedScene, SceneError> {
        let text = crate::files::SCENE_FILE.read_text(path)?;
        let scene = match path.extension().and_then(|e| e.to_str()) {
            Some("json") => Scene::from_json_str(&text),
            Some("toml") => Scene::from_toml_str(&text),
            _ => {
                return Err(SceneError::Parse(format!(
                    "{}: unknown extension; use .toml or .json",
                    path.display()
                )))
            }
        }
        .map_err(|e| match e {
            SceneError::Parse(msg) => SceneError::Parse(format!("{}: {msg}", path.display())),
            other => other,
        });
        let mut scene = scene?;
        if let Some(section) = &mut scene.structure {
            // The structure's files are named relative to the scene file.
            section.resolve_paths(path.parent().unwrap_or(Path::new("")));
        }
        scene.check()
    }
}

/// A scene whose every field has been validated by [`Scene::check`].
#[derive(Clone, Debug, PartialEq)]
pub struct CheckedScene(Scene);

impl CheckedScene {
    /// The paper's scene, checked.
    pub fn paper() -> Self {
        Scene::default()
            .check()
            .expect("the paper's scene is valid")
    }

    /// The underlying scene data.
    pub fn scene(&self) -> &Scene {
        &self.0
    }

    /// Returns the data for editing; it must be checked again to be used.
    pub fn into_scene(self) -> Scene {
        self.0
    }

    /// Bending stiffness EI (N m2) of the Euler-Bernoulli beam.
    pub fn bending_stiffness(&self) -> f64 {
        let g = &self.0.geometry;
        self.0.material.youngs_modulus * g.width * g.height.powi(3) / 12.0
    }

    /// Mass per unit length rho A (kg/m).
    pub fn mass_per_length(&self) -> f64 {
        let g = &self.0.geometry;
        self.0.material.density * g.width * g.height
    }

    /// Static tip stiffness of the Euler-Bernoulli cantilever, k = 3 EI / L^3 (N/m).
    pub fn euler_bernoulli_tip_stiffness(&self) -> f64 {
        3.0 * self.bending_stiffness() / self.0.geometry.length.powi(3)
    }
}

impl std::ops::Deref for CheckedScene {
    type Target = Scene;
    fn deref(&self) -> &Scene {
        &self.0
    }
}
