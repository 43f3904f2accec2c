//! StickSlipBeam starting at a user's scene: the model behind an exported FMU
//! (`crate::export`).

use super::{BeamInputs, Settings, StickSlipBeam};
use crate::model::Model;
use crate::variables::DynamicOutput;
use stickslip::scene::Scene;
use stickslip::user_structure::Sensor;

/// The table outputs a sensor's displacement and velocity are computed like: the tip's
/// (`tip_deflection`, `tip_velocity`), read off the same kinematics.
const LIKE_DISPLACEMENT: u32 = 200;
const LIKE_VELOCITY: u32 = 201;

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
        let sensors = start
            .scene
            .structure
            .as_ref()
            .map(|s| sensor_outputs(&s.sensors))
            .unwrap_or_default();
        let mut model = Self::with_defaults();
        model.settings = start.clone();
        model.start = start;
        model.sensors = sensors;
        model
    }

    /// Dynamic output `index` ([`sensor_outputs`]' order): sensor index / 2's
    /// displacement (even) or velocity (odd); 0 before the simulation exists, as the
    /// table's outputs.
    pub(super) fn sensor_value(&self, index: usize) -> f64 {
        let Some(running) = &self.running else {
            return 0.0;
        };
        running
            .simulator
            .sensor_readings()
            .get(index / 2)
            .map_or(f64::NAN, |r| {
                if index.is_multiple_of(2) {
                    r.displacement
                } else {
                    r.velocity
                }
            })
    }
}

/// The first value reference after StickSlipBeam's table (its rows and arrays), where
/// an export's sensors start.
pub fn first_sensor_value_reference() -> u32 {
    let rows = StickSlipBeam::variables().iter().map(|v| v.value_reference);
    let arrays = StickSlipBeam::arrays().iter().map(|a| a.value_reference);
    rows.chain(arrays).max().map_or(0, |vr| vr + 1)
}

/// Each sensor's two outputs: its name (the displacement, m) and its velocity name
/// (m/s), value references from [`first_sensor_value_reference`] on, two per sensor
/// in the section's order. (The unit is m and m/s whatever the direction: a sensor on
/// a rotation reads rad and rad/s, which FMI's units would call another quantity; the
/// description says which DOF it is.)
pub fn sensor_outputs(sensors: &[Sensor]) -> Vec<DynamicOutput> {
    let base = first_sensor_value_reference();
    sensors
        .iter()
        .enumerate()
        .flat_map(|(k, s)| {
            let at = format!("{} (structure.sensors)", s.dof());
            let vr = base + 2 * k as u32;
            [
                DynamicOutput {
                    name: s.name.clone(),
                    value_reference: vr,
                    unit: "m",
                    description: format!("Displacement of sensor {}: {at}", s.name),
                    like: LIKE_DISPLACEMENT,
                },
                DynamicOutput {
                    name: s.velocity_name(),
                    value_reference: vr + 1,
                    unit: "m/s",
                    description: format!("Velocity of sensor {}: {at}", s.name),
                    like: LIKE_VELOCITY,
                },
            ]
        })
        .collect()
}
