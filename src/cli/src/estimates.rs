//! `stickslip estimates`: the closed-form numbers of a scene's Euler-Bernoulli
//! cantilever (`stickslip::stability`), as JSON for scripts, so that no script
//! re-derives beam theory. With a `[structure]`, the structure's own numbers instead
//! (`stickslip::linear_structure::estimates`: its lowest modes and its static
//! compliance at the contact DOF), in [`StructureEstimatesJson`].

use crate::error::CliError;
use crate::scene_args::SceneArgs;
use clap::Args;
use serde::Serialize;
use stickslip::linear_structure::estimates::structure_estimates;
use stickslip::scene::{CheckedScene, Damping};
use stickslip::stability::{
    cantilever_omega, rayleigh_at_modes_1_and_3, sliding_stability_speed,
    sliding_stability_speed_in_mode,
};
use stickslip::user_structure::StructureSection;

/// Arguments of `stickslip estimates`.
#[derive(Args, Debug, Clone)]
pub struct EstimatesArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Replace the scene's damping by Rayleigh damping with this ratio at modes 1 and 3
    /// (and report its a and b).
    #[arg(long, allow_negative_numbers = true)]
    pub rayleigh_ratio: Option<f64>,
}

/// What `stickslip estimates` prints.
#[derive(Debug, Serialize)]
pub struct Estimates {
    /// Angular frequencies of bending modes 1 to 4 (rad/s).
    pub omega: Vec<f64>,
    /// Beam mass rho A L (kg).
    pub mass: f64,
    /// Static tip stiffness k = 3 EI / L^3 (N/m).
    pub tip_stiffness: f64,
    /// Rayleigh a (1/s) of the damping used below.
    pub mass_proportional: f64,
    /// Rayleigh b (s) of the damping used below.
    pub stiffness_proportional: f64,
    /// Belt speed above which steady sliding is linearly stable in mode 1 (m/s); null
    /// where the estimate does not apply, a string "inf" without damping.
    pub sliding_stability_speed: Option<serde_json::Value>,
}

/// What `stickslip estimates` prints for a scene with a `[structure]`: the structure's
/// own numbers (from its matrices; `geometry` and `material` are unused with it).
#[derive(Debug, Serialize)]
pub struct StructureEstimatesJson {
    /// What was solved: "structure, N DOFs (source), contact node X direction D".
    pub structure: String,
    /// Angular frequencies of the structure's lowest modes, up to 4 (rad/s).
    pub omega: Vec<f64>,
    /// The same in Hz.
    pub frequencies: Vec<f64>,
    /// Each mode's mass seen at the contact DOF, 1 / phi_j(contact)^2 of the
    /// M-normalised mode (kg; rho A L / 4 for every mode of the uniform cantilever's tip).
    pub contact_modal_mass: Vec<f64>,
    /// Static compliance at the contact DOF: its displacement under a unit force there
    /// (m/N).
    pub contact_compliance: f64,
    /// Static stiffness at the contact DOF, 1 / contact_compliance (N/m).
    pub tip_stiffness: f64,
    /// Rayleigh a (1/s) of the damping used below.
    pub mass_proportional: f64,
    /// Rayleigh b (s) of the damping used below.
    pub stiffness_proportional: f64,
    /// Belt speed above which steady sliding is linearly stable in the structure's mode
    /// 1 seen at the contact (m/s), as the beam's; null where the estimate does not
    /// apply, "inf" without damping.
    pub sliding_stability_speed: Option<serde_json::Value>,
}

/// A speed as JSON: a number, or "inf".
fn speed_json(speed: Option<f64>) -> Option<serde_json::Value> {
    speed.map(|v| {
        if v.is_finite() {
            serde_json::json!(v)
        } else {
            serde_json::json!("inf")
        }
    })
}

/// `scene` with Rayleigh damping of ratio `ratio` at angular frequencies 1 and 3 (rad/s)
/// given by `at`, or as it is without `ratio`.
fn with_rayleigh(
    scene: CheckedScene,
    ratio: Option<f64>,
    at: impl FnOnce(&CheckedScene, f64) -> Damping,
) -> Result<CheckedScene, CliError> {
    let Some(ratio) = ratio else {
        return Ok(scene);
    };
    if !(ratio.is_finite() && ratio >= 0.0) {
        return Err(CliError::RayleighRatio(ratio));
    }
    let damping = at(&scene, ratio);
    let mut raw = scene.into_scene();
    raw.damping = damping;
    Ok(raw.check()?)
}

/// `stickslip estimates` of a scene with a `[structure]`.
fn structure_estimates_json(
    scene: CheckedScene,
    section: &StructureSection,
    ratio: Option<f64>,
) -> Result<StructureEstimatesJson, CliError> {
    let found = structure_estimates(section, 4)?;
    let hz: Vec<f64> = found
        .omega
        .iter()
        .map(|w| w / (2.0 * std::f64::consts::PI))
        .collect();
    let scene = with_rayleigh(scene, ratio, |_, ratio| {
        // Modes 1 and 3 as for the beam (mode 1 twice for a structure of fewer DOFs).
        let third = hz.get(2).or(hz.last()).copied().unwrap_or(f64::NAN);
        Damping::from_ratio(ratio, hz[0], third)
    })?;
    Ok(StructureEstimatesJson {
        structure: found.label,
        frequencies: hz,
        contact_modal_mass: found
            .contact_participation
            .iter()
            .map(|p| 1.0 / p)
            .collect(),
        contact_compliance: found.contact_compliance,
        tip_stiffness: 1.0 / found.contact_compliance,
        mass_proportional: scene.damping.mass_proportional,
        stiffness_proportional: scene.damping.stiffness_proportional,
        sliding_stability_speed: speed_json(sliding_stability_speed_in_mode(
            &scene,
            found.omega[0],
            found.contact_participation[0],
        )),
        omega: found.omega,
    })
}

/// `stickslip estimates`: prints the scene's estimates as one JSON object.
pub fn estimates(args: &EstimatesArgs) -> Result<(), CliError> {
    let scene = args.scene.scene()?;
    if let Some(section) = scene.structure.clone() {
        let estimates = structure_estimates_json(scene, &section, args.rayleigh_ratio)?;
        // Plain numbers and strings: serialising them cannot fail.
        println!(
            "{}",
            serde_json::to_string_pretty(&estimates).unwrap_or_default()
        );
        return Ok(());
    }
    let scene = with_rayleigh(scene, args.rayleigh_ratio, rayleigh_at_modes_1_and_3)?;
    let speed = speed_json(sliding_stability_speed(&scene));
    let estimates = Estimates {
        omega: (1..=4)
            .filter_map(|n| cantilever_omega(&scene, n))
            .collect(),
        mass: scene.mass_per_length() * scene.geometry.length,
        tip_stiffness: scene.euler_bernoulli_tip_stiffness(),
        mass_proportional: scene.damping.mass_proportional,
        stiffness_proportional: scene.damping.stiffness_proportional,
        sliding_stability_speed: speed,
    };
    // Plain numbers and strings: serialising them cannot fail.
    let text = serde_json::to_string_pretty(&estimates).unwrap_or_default();
    println!("{text}");
    Ok(())
}
