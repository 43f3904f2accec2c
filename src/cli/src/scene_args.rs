//! The scene flags that `simulate`, `static` and `estimates` share ([`SceneArgs`]): a
//! scene file (or the paper's scene) with command-line overrides, checked, and with
//! `fidelity = auto` resolved to a configuration.
//!
//! The values of `--fidelity`, `--friction` and `--integrator` are the scene's words
//! (`crate::choice`); `--friction analytical` stays accepted for `exponential`.

use crate::choice::{parser, ChoiceParser};
use crate::error::CliError;
use clap::Args;
use std::path::PathBuf;
use stickslip::choice::Choice;
use stickslip::friction::lugre;
use stickslip::friction::rate_and_state::{self, StateEvolution};
use stickslip::friction::registry::{self, LawParameter};
use stickslip::friction::FrictionLawKind;
use stickslip::law_source::LawSource;
use stickslip::neural::inference::Inference;
use stickslip::run::RunError;
use stickslip::scene::{
    CheckedScene, DampingPhase, FidelityLevel, FirstSlipStep, Scene, Scheme, SlipForce, TipVelocity,
};
use stickslip::scene_preset::ScenePreset;

/// `--friction`: the scene's laws, plus `analytical`, the command line's name for the
/// exponential law before the values were the scene's words (scripts use it). The
/// external law is refused: its force comes from the StickSlipBeam FMU's inputs.
pub fn friction_parser() -> ChoiceParser<FrictionLawKind> {
    parser::<FrictionLawKind>()
        .alias("analytical", FrictionLawKind::Exponential)
        .refuse(
            FrictionLawKind::External,
            "the external law takes its force from the inputs external.kinetic_force and external.static_limit of the StickSlipBeam FMU, and a command-line run has none",
        )
}

/// Options shared by commands that build a scene: a scene file plus overrides.
#[derive(Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Scene file (.toml or .json); missing fields take the paper's values.
    #[arg(long, conflicts_with = "preset")]
    pub scene: Option<PathBuf>,
    /// A named scene to start from instead of a scene file (default: paper).
    #[arg(long, value_parser = parser::<ScenePreset>())]
    pub preset: Option<ScenePreset>,
    /// Tip preload at t = 0 as a fraction of F_crit = mu_s F_n, in [0, 1).
    #[arg(long, allow_negative_numbers = true)]
    pub preload: Option<f64>,
    /// The contact phases in which the Rayleigh damping acts.
    #[arg(long, value_parser = parser::<DampingPhase>())]
    pub damping_phase: Option<DampingPhase>,
    /// The tip velocity the contact evaluates.
    #[arg(long, value_parser = parser::<TipVelocity>())]
    pub tip_velocity: Option<TipVelocity>,
    /// The tip force over the first step of each slip phase.
    #[arg(long, value_parser = parser::<FirstSlipStep>())]
    pub first_slip_step: Option<FirstSlipStep>,
    /// Which sliding velocity the kinetic force of a slip step is evaluated at.
    #[arg(long, value_parser = parser::<SlipForce>())]
    pub slip_force: Option<SlipForce>,
    /// Slip on the plane-stress mesh's modes below this cut-off (rad/s; the paper
    /// authors' 1e4); 0: on the full model. Plane-stress fidelity only.
    #[arg(long, allow_negative_numbers = true)]
    pub slip_modes_below: Option<f64>,
    /// Structural model; `auto` also picks the time step and integrator.
    #[arg(long, value_parser = parser::<FidelityLevel>())]
    pub fidelity: Option<FidelityLevel>,
    /// With fidelity auto (`--fidelity auto`, or a scene file's `fidelity.level =
    /// "auto"`): the largest tip-deflection deviation allowed over the run, to
    /// --t-end (m; beyond 10 s, over the first three major slips, with the phase drift
    /// reported); it replaces the scene file's `fidelity.tolerance`.
    /// Default (neither given): 1e-5 m, as in the FMU (`stickslip::auto::DEFAULT_TOLERANCE`).
    #[arg(long, allow_negative_numbers = true)]
    pub tolerance: Option<f64>,
    /// Number of beam elements (beam, and modal from a beam).
    #[arg(long)]
    pub elements: Option<usize>,
    /// Plane-stress element size (m).
    #[arg(long, allow_negative_numbers = true)]
    pub element_size: Option<f64>,
    /// Number of modes of the modal model.
    #[arg(long)]
    pub modes: Option<usize>,
    /// Time step (s).
    #[arg(long, allow_negative_numbers = true)]
    pub dt: Option<f64>,
    /// End time (s).
    #[arg(long, allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// Time integration scheme.
    #[arg(long, value_parser = parser::<Scheme>())]
    pub integrator: Option<Scheme>,
    /// Generalised-alpha spectral radius at infinity, in [0, 1].
    #[arg(long, allow_negative_numbers = true)]
    pub rho_inf: Option<f64>,
    /// Rayleigh damping ratio applied at the first and third bending frequencies of the
    /// Euler-Bernoulli cantilever.
    #[arg(long, allow_negative_numbers = true)]
    pub damping_ratio: Option<f64>,
    /// Friction law during slip (`analytical` is accepted for `exponential`).
    #[arg(long, value_parser = friction_parser())]
    pub friction: Option<FrictionLawKind>,
    /// Weights file of the neural law (default: the weights shipped with the crate).
    #[arg(long)]
    pub weights: Option<String>,
    /// How the neural law's network is evaluated: speed for accuracy.
    #[arg(long, value_parser = parser::<Inference>())]
    pub inference: Option<Inference>,
    /// LuGre's bristle stiffness sigma0 (N/m) for `--friction lugre`; the other LuGre
    /// parameters come from the scene file's `[friction.lugre]`.
    #[arg(long, allow_negative_numbers = true)]
    pub bristle_stiffness: Option<f64>,
    /// Rate-and-state's characteristic slip D_c (m) for `--friction rate-and-state`; the
    /// other parameters come from the scene file's `[friction.rate_and_state]`.
    #[arg(long, allow_negative_numbers = true)]
    pub characteristic_slip: Option<f64>,
    /// Rate-and-state's evolution law of the state theta.
    #[arg(long, value_parser = parser::<StateEvolution>())]
    pub state_evolution: Option<StateEvolution>,
    /// A friction law's parameter, NAME=VALUE (repeatable): NAME its table and key in the
    /// scene file (`lugre.bristle_damping`, `rate_and_state.state_evolution`), VALUE a
    /// number or, for a choice, its word. Every law's parameters, from the law registry
    /// (docs/variables.md lists them with units and ranges).
    #[arg(long = "law-parameter", value_name = "NAME=VALUE", value_parser = registry::parse_assignment)]
    pub law_parameters: Vec<(&'static LawParameter, f64)>,
}

impl SceneArgs {
    /// The scene file (or the paper's scene) with the overrides applied, checked.
    pub fn scene(&self) -> Result<CheckedScene, CliError> {
        Ok(self.build()?.0)
    }

    /// [`Self::scene`] and the friction law it runs, resolved once (the weights file
    /// read once): with `fidelity = auto` before the calibration, whose runs all use it.
    pub fn scene_and_law(&self) -> Result<(CheckedScene, LawSource), CliError> {
        let (scene, law) = self.build()?;
        let law = match law {
            Some(law) => law,
            None => law_of(&scene)?,
        };
        Ok((scene, law))
    }

    /// The checked scene, and its law if `fidelity = auto` needed it.
    fn build(&self) -> Result<(CheckedScene, Option<LawSource>), CliError> {
        let mut scene: Scene = match &self.scene {
            Some(path) => Scene::load(path)?.into_scene(),
            None => self.preset.unwrap_or_default().scene(),
        };
        self.override_contact(&mut scene);
        self.override_fidelity_and_time(&mut scene);
        self.override_friction(&mut scene);
        // Before the damping, which checks the scene: the tolerance must be in it.
        let auto_tolerance = self.auto_tolerance(&mut scene)?;
        if let Some(zeta) = self.damping_ratio {
            // At the first and third cantilever frequencies (the same numbers
            // `stickslip estimates` prints).
            let checked = scene.clone().check()?;
            if !(zeta.is_finite() && zeta >= 0.0) {
                return Err(CliError::DampingRatio(zeta));
            }
            scene.damping = stickslip::stability::rayleigh_at_modes_1_and_3(&checked, zeta);
        }
        let Some(tolerance) = auto_tolerance else {
            return Ok((scene.check()?, None));
        };
        let source = law_of(&scene.clone().check()?)?;
        // The front measured with the scene's law (a law with state has its own).
        let front = stickslip::auto::front_for(&scene, &source)?;
        let (resolved, choice) =
            stickslip::auto::resolve(scene, &source, &front, &mut |line| eprintln!("{line}"))?;
        if let Some(choice) = &choice {
            eprintln!("{}", stickslip::auto::describe(choice, tolerance));
        }
        Ok((resolved.check()?, Some(source)))
    }

    /// The flags of the scene's `[contact]` section.
    fn override_contact(&self, scene: &mut Scene) {
        if let Some(p) = self.preload {
            scene.contact.preload = p;
        }
        if let Some(p) = self.damping_phase {
            scene.contact.damping_phase = p;
        }
        if let Some(v) = self.tip_velocity {
            scene.contact.tip_velocity = v;
        }
        if let Some(f) = self.first_slip_step {
            scene.contact.first_slip_step = f;
        }
        if let Some(f) = self.slip_force {
            scene.contact.slip_force = f;
        }
        if let Some(cutoff) = self.slip_modes_below {
            scene.contact.slip_modes_below = cutoff;
        }
    }

    /// The flags of the `[fidelity]`, `[time]` and `[integrator]` sections.
    fn override_fidelity_and_time(&self, scene: &mut Scene) {
        if let Some(level) = self.fidelity {
            scene.fidelity.level = level;
        }
        if let Some(n) = self.elements {
            scene.fidelity.beam_elements = n;
        }
        if let Some(s) = self.element_size {
            scene.fidelity.element_size = s;
        }
        if let Some(m) = self.modes {
            scene.fidelity.modes = m;
        }
        if let Some(dt) = self.dt {
            scene.time.step = dt;
        }
        if let Some(t) = self.t_end {
            scene.time.end = t;
        }
        if let Some(s) = self.integrator {
            scene.integrator.scheme = s;
        }
        if let Some(r) = self.rho_inf {
            scene.integrator.rho_inf = r;
        }
    }

    /// The flags of the `[friction]` section and its laws' tables (the named flags
    /// first, then each `--law-parameter` in the order given).
    fn override_friction(&self, scene: &mut Scene) {
        if let Some(f) = self.friction {
            scene.friction.law = f;
        }
        if let Some(w) = &self.weights {
            scene.friction.weights = Some(w.clone());
        }
        if let Some(i) = self.inference {
            scene.friction.inference = i;
        }
        if let Some(k) = self.bristle_stiffness {
            scene.friction.laws.set(&lugre::BRISTLE_STIFFNESS, k);
        }
        if let Some(d) = self.characteristic_slip {
            scene
                .friction
                .laws
                .set(&rate_and_state::CHARACTERISTIC_SLIP, d);
        }
        if let Some(e) = self.state_evolution {
            scene
                .friction
                .laws
                .set(&rate_and_state::STATE_EVOLUTION, f64::from(e.code()));
        }
        for (parameter, value) in &self.law_parameters {
            scene.friction.laws.set(parameter, *value);
        }
    }

    /// With fidelity auto (from `--fidelity auto` or the scene file): puts `--tolerance`
    /// into the scene, refuses the flags whose values auto chooses, and returns the
    /// tolerance (m). Without auto: None, and `--tolerance` is refused.
    fn auto_tolerance(&self, scene: &mut Scene) -> Result<Option<f64>, CliError> {
        if scene.fidelity.level != FidelityLevel::Auto {
            if self.tolerance.is_some() {
                return Err(CliError::ToleranceWithoutAuto);
            }
            return Ok(None);
        }
        let by = if self.fidelity == Some(FidelityLevel::Auto) {
            "--fidelity auto"
        } else {
            "the scene's fidelity.level = auto"
        };
        if let Some(tolerance) = self.tolerance {
            scene.fidelity.tolerance = Some(tolerance);
        }
        // Absent from flag and file: the default that the FMU's start value also is.
        let tolerance = stickslip::auto::tolerance_of(scene);
        let chosen_by_auto = [
            ("--elements", self.elements.is_some()),
            ("--element-size", self.element_size.is_some()),
            ("--modes", self.modes.is_some()),
            ("--dt", self.dt.is_some()),
            ("--integrator", self.integrator.is_some()),
        ];
        if let Some(&(flag, _)) = chosen_by_auto.iter().find(|(_, given)| *given) {
            return Err(CliError::ChosenByAuto { flag, by });
        }
        Ok(Some(tolerance))
    }
}

/// The friction law of a checked scene, resolved once ([`LawSource::resolve`]).
pub fn law_of(scene: &CheckedScene) -> Result<LawSource, CliError> {
    LawSource::resolve(scene).map_err(|e| CliError::Run(RunError::Law(e)))
}
