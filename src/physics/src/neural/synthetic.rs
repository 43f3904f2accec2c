//! The settings of the paper's synthetic friction data (Vater, Stender, Hoffmann, PAMM
//! 2023, Sec. 3.1), which every model trained on it records in its weights file.
//!
//! The defaults are the distribution of the data set the authors published with the
//! paper (repository TUHH-DYN/NeuralNetworkFrictionModel_FEA, in
//! `data/paper-authors/exponential_friction_model_samples_full.csv`): F_n ~ U[98, 102] N,
//! v_s ~ N(0, 0.1 m/s) with no limit but the draws with |v_s| <= 1e-4 m/s removed, and a
//! relative noise of 2 %. The generation itself is `stickslip_train::data::Synthetic`.
//!
//! Before this reading the generator followed a guess from the paper's text (F_n in
//! [90, 110] N, v_s redrawn outside [-0.4, 0.4] m/s, additive noise N(0, 0.02 N), no
//! cut). Weights files written then have no `velocity_cut` nor `relative_noise_std`
//! field; their serde defaults (0: nothing removed, no relative noise) keep such a file
//! describing the data it was trained on.

use serde::{Deserialize, Serialize};

crate::choice! {
    /// Which synthetic data set `stickslip train` generates (`--generator`).
    #[choice(name = "SyntheticData", description = "Distribution of the synthetic friction data")]
    #[derive(Default)]
    pub enum SyntheticPreset {
        /// `SyntheticSpec::default()`: the authors' published data set's distribution.
        #[default]
        Authors = "authors": "the distribution of the paper authors' published data: F_n 98 to 102 N, 2 % relative noise, draws with |v_s| <= 1e-4 m/s removed",
        /// `SyntheticSpec::former()`: the data the shipped networks were trained on.
        Former = "former": "the generator before the authors' data were read, the shipped networks' data: F_n 90 to 110 N, 0.02 N additive noise, |v_s| <= 0.4 m/s",
    }
}

/// The paper's synthetic friction data, every distribution a parameter.
///
/// Each of the `samples` draws takes, in this order from one random stream:
/// - F_n ~ U[`normal_force_min`, `normal_force_max`) (N);
/// - v_s ~ N(0, `velocity_std`) (m/s), drawn again while |v_s| > `velocity_limit` (when
///   there is a limit);
/// - z ~ N(0, 1), and F_f = F + z sqrt(`noise_std`^2 + (`relative_noise_std` F)^2) (N)
///   with F = sign(v_s) [mu_k + (mu_s - mu_k) exp(-alpha |v_s|)] F_n, the paper's Eq. 6
///   made odd in v_s (the force acts in the direction of the sliding velocity, as in
///   `crate::friction::exponential::ExponentialLaw`): the sum of an additive noise N(0, `noise_std`)
///   and a relative one F N(0, `relative_noise_std`), in one draw. With only the
///   relative part this is the authors' F_f = F (1 + 0.02 N(0, 1)) (z is symmetric).
///
/// A draw with |v_s| <= `velocity_cut` is then removed (its numbers are still drawn, so
/// the cut does not shift the other samples), so the data set holds the draws that
/// remain: 4,994 of 5,000 in the authors' file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SyntheticSpec {
    /// Number of draws (5000); the data set holds those the velocity cut leaves.
    pub samples: usize,
    /// Lower bound of the normal force (98 N).
    pub normal_force_min: f64,
    /// Upper bound of the normal force (102 N).
    pub normal_force_max: f64,
    /// Standard deviation of the sliding velocity (0.1 m/s).
    pub velocity_std: f64,
    /// Velocities are redrawn outside [-limit, limit] (m/s); `null`: no limit (the
    /// default, as in the authors' data). Absent in a file: 0.4, the old generator's.
    #[serde(default = "SyntheticSpec::former_velocity_limit")]
    pub velocity_limit: Option<f64>,
    /// Draws with |v_s| <= this are removed (1e-4 m/s); 0 removes none (absent in a
    /// file: 0, the old generator's).
    #[serde(default)]
    pub velocity_cut: f64,
    /// mu_s (0.5).
    pub static_coefficient: f64,
    /// mu_k (0.2).
    pub kinetic_coefficient: f64,
    /// alpha (5 s/m).
    pub decay: f64,
    /// Standard deviation of the additive force noise (0 N; the old generator's 0.02 N).
    pub noise_std: f64,
    /// Standard deviation of the noise relative to the noise-free force (0.02, i.e. 2 %;
    /// absent in a file: 0, the old generator's).
    #[serde(default)]
    pub relative_noise_std: f64,
    /// Share of the samples held out for testing (0.3).
    pub test_fraction: f64,
}

impl Default for SyntheticSpec {
    fn default() -> Self {
        SyntheticSpec {
            samples: 5000,
            normal_force_min: 98.0,
            normal_force_max: 102.0,
            velocity_std: 0.1,
            velocity_limit: None,
            velocity_cut: 1e-4,
            static_coefficient: 0.5,
            kinetic_coefficient: 0.2,
            decay: 5.0,
            noise_std: 0.0,
            relative_noise_std: 0.02,
            test_fraction: 0.3,
        }
    }
}

impl SyntheticSpec {
    /// The settings of `preset`.
    pub fn preset(preset: SyntheticPreset) -> Self {
        match preset {
            SyntheticPreset::Authors => SyntheticSpec::default(),
            SyntheticPreset::Former => SyntheticSpec::former(),
        }
    }

    /// The generator as it was before the authors' data were read (see the module
    /// documentation): what a weights file without the new fields was trained on.
    pub fn former() -> Self {
        SyntheticSpec {
            normal_force_min: 90.0,
            normal_force_max: 110.0,
            velocity_limit: Some(0.4),
            velocity_cut: 0.0,
            noise_std: 0.02,
            relative_noise_std: 0.0,
            ..SyntheticSpec::default()
        }
    }

    fn former_velocity_limit() -> Option<f64> {
        SyntheticSpec::former().velocity_limit
    }

    /// Checks the settings before any sample is drawn; the message names the setting.
    pub fn check(&self) -> Result<(), String> {
        let bad = |what: &str| Err(format!("synthetic data: {what}"));
        let all_finite = [
            self.normal_force_min,
            self.normal_force_max,
            self.velocity_std,
            self.velocity_limit.unwrap_or(0.0),
            self.velocity_cut,
            self.static_coefficient,
            self.kinetic_coefficient,
            self.decay,
            self.noise_std,
            self.relative_noise_std,
            self.test_fraction,
        ]
        .iter()
        .all(|v| v.is_finite());
        if !all_finite {
            return bad("every parameter must be a finite number");
        }
        if self.samples < 10 {
            return bad("at least 10 samples are needed");
        }
        if self.normal_force_min >= self.normal_force_max {
            return bad("normal_force_min must be below normal_force_max");
        }
        if self.velocity_std <= 0.0 {
            return bad("velocity_std must be positive");
        }
        if let Some(limit) = self.velocity_limit {
            // Below 0.05 sigma the rejection loop would need thousands of draws per sample.
            if limit < 0.05 * self.velocity_std {
                return bad("velocity_limit must be at least 0.05 velocity_std");
            }
            if self.velocity_cut >= limit {
                return bad(&format!(
                    "velocity_cut ({}) must be below velocity_limit ({limit}): every draw \
                     would be removed",
                    self.velocity_cut
                ));
            }
        }
        if self.velocity_cut < 0.0 {
            return bad("velocity_cut must not be negative");
        }
        // A cut of one sigma already removes 68 % of the draws; beyond it the "data near
        // v = 0" the paper is about would be gone.
        if self.velocity_cut >= self.velocity_std {
            return bad("velocity_cut must be below velocity_std");
        }
        if self.noise_std < 0.0 {
            return bad("noise_std must not be negative");
        }
        if self.relative_noise_std < 0.0 {
            return bad("relative_noise_std must not be negative");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `training.synthetic` object as the old generator wrote it (before the authors'
    /// data were read): no `velocity_cut`, no `relative_noise_std`.
    const FORMER_JSON: &str = r#"{
        "samples": 5000, "normal_force_min": 90.0, "normal_force_max": 110.0,
        "velocity_std": 0.1, "velocity_limit": 0.4, "static_coefficient": 0.5,
        "kinetic_coefficient": 0.2, "decay": 5.0, "noise_std": 0.02, "test_fraction": 0.3
    }"#;

    #[test]
    fn an_old_description_reads_as_the_former_generator() {
        let spec: SyntheticSpec = serde_json::from_str(FORMER_JSON).unwrap();
        assert_eq!(spec, SyntheticSpec::former());
        assert!(spec.check().is_ok());
    }

    #[test]
    fn the_new_fields_and_no_limit_survive_a_round_trip() {
        let spec = SyntheticSpec::default();
        let text = serde_json::to_string(&spec).unwrap();
        assert!(text.contains("\"velocity_limit\":null"), "{text}");
        assert_eq!(serde_json::from_str::<SyntheticSpec>(&text).unwrap(), spec);
        assert!(spec.check().is_ok());
    }

    #[test]
    fn a_weights_file_with_bad_generator_settings_is_refused() {
        let text = crate::neural::PAPER_PLAIN_JSON.replace(
            "\"relative_noise_std\": 0.0",
            "\"relative_noise_std\": -0.02",
        );
        assert_ne!(text, crate::neural::PAPER_PLAIN_JSON);
        let message = crate::neural::NeuralModel::from_json(&text, "edited.json")
            .unwrap_err()
            .to_string();
        assert!(
            message.contains("edited.json") && message.contains("relative_noise_std"),
            "{message}"
        );
    }

    #[test]
    fn bad_settings_are_refused_with_their_name() {
        let refused = |change: fn(&mut SyntheticSpec), word: &str| {
            let mut spec = SyntheticSpec::default();
            change(&mut spec);
            let message = spec.check().unwrap_err();
            assert!(message.contains(word), "{message}");
        };
        refused(|s| s.relative_noise_std = -0.01, "relative_noise_std");
        refused(|s| s.noise_std = -1.0, "noise_std");
        refused(|s| s.velocity_cut = -1e-4, "velocity_cut");
        refused(
            |s| s.velocity_cut = 0.1,
            "velocity_cut must be below velocity_std",
        );
        refused(
            |s| {
                s.velocity_limit = Some(0.05);
                s.velocity_cut = 0.05;
            },
            "velocity_cut (0.05) must be below velocity_limit (0.05)",
        );
        refused(|s| s.velocity_limit = Some(1e-3), "velocity_limit");
        refused(|s| s.velocity_limit = Some(f64::NAN), "finite");
        refused(|s| s.relative_noise_std = f64::INFINITY, "finite");
        refused(|s| s.normal_force_max = 98.0, "normal_force_min");
        refused(|s| s.samples = 3, "samples");
    }
}
