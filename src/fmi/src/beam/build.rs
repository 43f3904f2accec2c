//! Building the simulation from the parameters: the checked scene (with `fidelity =
//! auto` resolved), its friction law (`LawSource`, the loaded network shared) and the
//! simulator.

use super::{Running, Settings, StickSlipBeam};
use crate::networks::NetworkError;
use stickslip::auto::{AutoError, Horizon};
use stickslip::friction::FrictionLawKind;
use stickslip::law_source::{LawSource, NetworkOrigin};
use stickslip::neural::SceneLawError;
use stickslip::scene::{CheckedScene, FidelityLevel, Scene, SceneError};
use stickslip::simulation::{SimulationError, Simulator};
use stickslip::study::Configuration;

/// Why the simulation could not be built from the parameters (the `Model` methods log
/// the message).
#[derive(Debug, thiserror::Error)]
pub(super) enum BuildError {
    #[error(transparent)]
    Scene(#[from] SceneError),
    #[error(transparent)]
    Auto(#[from] AutoError),
    #[error(transparent)]
    Network(#[from] NetworkError),
    /// The weights are not a friction law of the beam (wrong features), worded
    /// "friction.weights: weights file {name}: {reason}".
    #[error(transparent)]
    NotAFrictionLaw(#[from] SceneLawError),
    #[error(transparent)]
    Simulation(#[from] SimulationError),
}

/// The scene `settings` run over the experiment from `start_time` to `stop_time`: the
/// inputs that are scene fields in place, and the end at the stop time.
fn scene_of(settings: &Settings, start_time: f64, stop_time: Option<f64>) -> Scene {
    let mut scene = settings.scene.clone();
    scene.loading.belt_speed = settings.inputs.belt_speed;
    scene.loading.normal_force = settings.inputs.normal_force;
    if let Some(stop) = stop_time {
        scene.time.end = (stop - start_time).max(scene.time.step);
    }
    scene
}

impl StickSlipBeam {
    /// The scene of the current settings, checked, and the law it runs. The scene is
    /// checked before the law is resolved, so that a bad parameter is reported as such
    /// before a weights file is read (as the command line does); with `fidelity = auto`
    /// the law (the network read once) then serves the calibration runs.
    fn checked_scene(
        &mut self,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<(CheckedScene, LawSource), BuildError> {
        let scene = scene_of(&self.settings, start_time, stop_time);
        let weights = self.settings.weights.clone();
        if scene.fidelity.level == FidelityLevel::Auto {
            scene.clone().check()?;
            let law = self.law_source(&scene, &weights)?;
            // The bound holds over the experiment: to its stop time when one is defined,
            // else the horizon is open (the scene's time.end is no end the user set).
            let horizon = match stop_time {
                Some(_) => Horizon::Until(scene.time.end),
                None => Horizon::Open,
            };
            let scene = self
                .auto_choice(&scene, &law, horizon)?
                .apply(&scene)
                .check()?;
            // The choice may name an evaluation of the network (the shipped front does
            // not): the law follows the scene that runs.
            let law = law.with_inference(scene.friction.inference);
            return Ok((scene, law));
        }
        let scene = scene.check()?;
        let law = self.law_source(&scene, &weights)?;
        Ok((scene, law))
    }

    /// The checks `checked_scene` makes of `settings` before any simulation runs: the
    /// scene's rules and the law (the network read, and fitting the scene), which it
    /// returns. `auto`'s choice is not made: its request passes the same scene check
    /// first.
    pub(super) fn check_buildable(
        &mut self,
        settings: &Settings,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<LawSource, BuildError> {
        let scene = scene_of(settings, start_time, stop_time);
        scene.clone().check()?;
        self.law_source(&scene, &settings.weights)
    }

    /// The law of `scene`'s friction settings, with the network of weights `name` (read
    /// once per name by `networks`, then shared) for the neural law.
    fn law_source(&mut self, scene: &Scene, name: &str) -> Result<LawSource, BuildError> {
        let networks = &mut self.networks;
        // A learned law with state (`stickslip::friction::learned_state`), told by its file.
        if scene.friction.law == FrictionLawKind::Neural {
            if let Some(law) = networks.state_law(name)? {
                if let Some(reason) = stickslip::law_source::learned_state::refusal(scene) {
                    return Err(BuildError::NotAFrictionLaw(SceneLawError::Weights {
                        path: name.to_owned(),
                        source: stickslip::neural::NeuralError::NotAFrictionLaw(reason),
                    }));
                }
                return Ok(LawSource::LearnedState(law));
            }
        }
        let law = LawSource::with_network(&scene.friction, scene.loading.normal_force, || {
            let network = networks.get(name)?.clone();
            Ok::<_, NetworkError>((network, NetworkOrigin::Weights(name.to_owned())))
        })?;
        Ok(law)
    }

    /// The `auto` choice for `scene` at its tolerance over `horizon`, under `law`. The choice is kept by
    /// `stickslip::auto` for the process, keyed by scene and law: the calibration runs
    /// the scene several times, and another instance (or this one after a reset) of the
    /// same scene and network gets the same choice without them.
    fn auto_choice(
        &mut self,
        scene: &Scene,
        law: &LawSource,
        horizon: Horizon,
    ) -> Result<Configuration, BuildError> {
        // The calibration runs stand alone, without this FMU's inputs: with the external
        // model they run the exponential law of the scene's coefficients instead. With
        // the neural law they run the network of friction.weights, the one this FMU
        // will run (not the scene's default, the shipped plain network).
        let mut calibrated = scene.clone();
        if calibrated.friction.law == FrictionLawKind::External {
            calibrated.friction.law = FrictionLawKind::Exponential;
        }
        let law = law.stand_alone();
        // The front measured with that law (a law with state has its own).
        let front = stickslip::auto::front_for(&calibrated, &law)?;
        let mut progress = Vec::new();
        let choice =
            stickslip::auto::choose_cached(&calibrated, &law, horizon, &front, &mut |line| {
                progress.push(line.to_string())
            });
        // The progress lines are logged whether or not a choice came of them.
        self.auto_log.append(&mut progress);
        let choice = choice?;
        let tolerance = stickslip::auto::tolerance_of(&calibrated);
        self.auto_log
            .push(stickslip::auto::describe(&choice, tolerance));
        Ok(choice.configuration)
    }

    /// Builds the simulation unless it is already built from the current settings.
    pub(super) fn ensure_running(
        &mut self,
        start_time: f64,
        stop_time: Option<f64>,
    ) -> Result<(), BuildError> {
        if let Some(running) = &self.running {
            if running.built_from == self.settings {
                return Ok(());
            }
        }
        let (scene, law) = self.checked_scene(start_time, stop_time)?;
        // The inputs replace the law while the external model is on; the simulator
        // still holds a law, the exponential one of the scene's coefficients.
        let mut simulator = Simulator::new(scene, law.law()?)?;
        if law.is_external() {
            simulator.set_external_friction(Some(self.external_friction()));
        }
        let at_start = simulator.sample().relative_velocity;
        self.running = Some(Running {
            built_from: self.settings.clone(),
            simulator,
            start_time,
            mean_relative_velocity: at_start,
        });
        Ok(())
    }
}
