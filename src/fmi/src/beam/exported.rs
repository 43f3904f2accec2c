//! StickSlipBeam starting at a user's scene: the model behind an exported FMU
//! (`crate::export`).

use super::{BeamInputs, Settings, StickSlipBeam};
use crate::model::Model;
use stickslip::scene::Scene;

impl StickSlipBeam {
    /// The model with `scene`'s values as start values (and `reset`'s), the network of
    /// `weights` (a file in `resources/`) for the neural law. A scene without a
    /// fidelity tolerance gets the default one, as StickSlipBeam's defaults and the
    /// command line do; the inputs start at the scene's loading, and the external law's
    /// at its coefficients times the normal force, as StickSlipBeam's defaults do.
    pub fn with_scene(mut scene: Scene, weights: &str) -> Self {
        scene
            .fidelity
            .tolerance
            .get_or_insert(super::DEFAULT_FIDELITY_TOLERANCE);
        let defaults = Settings::default();
        let f = &scene.friction;
        let inputs = BeamInputs {
            belt_speed: scene.loading.belt_speed,
            normal_force: scene.loading.normal_force,
            kinetic_force: f.kinetic_coefficient * scene.loading.normal_force,
            static_limit: f.static_coefficient * scene.loading.normal_force,
            ..defaults.inputs
        };
        let start = Settings {
            scene,
            weights: weights.to_owned(),
            inputs,
            ..defaults
        };
        let mut model = Self::with_defaults();
        model.settings = start.clone();
        model.start = start;
        model
    }
}
