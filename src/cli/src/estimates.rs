//! `stickslip estimates`: the closed-form numbers of a scene's Euler-Bernoulli
//! cantilever (`stickslip::stability`), as JSON for scripts, so that no script
//! re-derives beam theory.

use crate::error::CliError;
use crate::scene_args::SceneArgs;
use clap::Args;
use serde::Serialize;
use stickslip::stability::{cantilever_omega, rayleigh_at_modes_1_and_3, sliding_stability_speed};

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

/// `stickslip estimates`: prints the scene's estimates as one JSON object.
pub fn estimates(args: &EstimatesArgs) -> Result<(), CliError> {
    let mut scene = args.scene.scene()?;
    if let Some(ratio) = args.rayleigh_ratio {
        if !(ratio.is_finite() && ratio >= 0.0) {
            return Err(CliError::RayleighRatio(ratio));
        }
        let damping = rayleigh_at_modes_1_and_3(&scene, ratio);
        let mut raw = scene.into_scene();
        raw.damping = damping;
        scene = raw.check()?;
    }
    let speed = sliding_stability_speed(&scene).map(|v| {
        if v.is_finite() {
            serde_json::json!(v)
        } else {
            serde_json::json!("inf")
        }
    });
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
