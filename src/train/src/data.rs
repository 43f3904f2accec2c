//! Friction data: the paper's synthetic set (Vater, Stender, Hoffmann, PAMM 2023, Sec. 3.1)
//! and the common in-memory form of measured data read from CSV.

use std::fmt::Write as _;
use std::path::Path;

use nalgebra::DMatrix;
use rand::seq::SliceRandom;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal, StandardNormal, Uniform};
use serde::{Deserialize, Serialize};

use crate::error::TrainError;
use stickslip::elementary::signum_or_zero;
use stickslip::neural::{FeatureRole, SyntheticSpec};

/// Random streams drawn from one seed: ChaCha8 streams are independent, so changing how
/// many numbers one consumer draws never shifts another consumer's numbers.
pub(crate) const DATA_STREAM: u64 = 0;
pub(crate) const INIT_STREAM: u64 = 1;
pub(crate) const FOLD_STREAM: u64 = 2;

/// A seeded ChaCha8 generator on the given stream. ChaCha8 (rand_chacha 0.3) has a fixed,
/// documented output, unlike `StdRng`, whose algorithm may change between rand versions.
pub(crate) fn seeded_rng(seed: u64, stream: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    rng
}

/// A named physical quantity (a CSV column).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Quantity {
    pub name: String,
    /// Unit as written in the CSV header `name[unit]`; empty when none was given.
    pub unit: String,
}

impl Quantity {
    pub fn new(name: &str, unit: &str) -> Self {
        Quantity {
            name: name.to_string(),
            unit: unit.to_string(),
        }
    }

    /// The CSV header form: `name[unit]`, or `name` when the unit is empty.
    pub fn header(&self) -> String {
        if self.unit.is_empty() {
            self.name.clone()
        } else {
            format!("{}[{}]", self.name, self.unit)
        }
    }
}

/// Samples of features and one target.
#[derive(Clone, Debug, PartialEq)]
pub struct Dataset {
    pub features: Vec<Quantity>,
    /// One role per feature.
    pub roles: Vec<FeatureRole>,
    pub target: Quantity,
    /// Features, one column per sample (features x samples): the layout the network's
    /// batch products use, each sample contiguous in memory.
    pub inputs: DMatrix<f64>,
    /// Target, one value per sample.
    pub targets: Vec<f64>,
}

impl Dataset {
    pub fn len(&self) -> usize {
        self.targets.len()
    }

    pub fn is_empty(&self) -> bool {
        self.targets.is_empty()
    }

    /// The samples at `indices`, in that order.
    pub fn subset(&self, indices: &[usize]) -> Dataset {
        let inputs = DMatrix::from_fn(self.inputs.nrows(), indices.len(), |row, col| {
            self.inputs[(row, indices[col])]
        });
        Dataset {
            features: self.features.clone(),
            roles: self.roles.clone(),
            target: self.target.clone(),
            inputs,
            targets: indices.iter().map(|&i| self.targets[i]).collect(),
        }
    }

    /// Index of the feature with `role`, if exactly one has it.
    pub fn feature_with_role(&self, role: FeatureRole) -> Option<usize> {
        self.roles.iter().position(|&r| r == role)
    }

    /// Shuffles with `seed` and splits off `test_fraction` of the samples (rounded to the
    /// nearest integer) as the test set; the rest is the training set.
    pub fn split(&self, test_fraction: f64, seed: u64) -> Result<Split, TrainError> {
        if !(test_fraction > 0.0 && test_fraction < 1.0) {
            return Err(TrainError::InvalidInput(format!(
                "the test fraction must lie strictly between 0 and 1, got {test_fraction}"
            )));
        }
        let n = self.len();
        let n_test = (n as f64 * test_fraction).round() as usize;
        if n_test == 0 || n_test >= n {
            return Err(TrainError::InvalidInput(format!(
                "{n} samples cannot be split {:.0}/{:.0} into non-empty training and test sets",
                100.0 * (1.0 - test_fraction),
                100.0 * test_fraction
            )));
        }
        let mut order: Vec<usize> = (0..n).collect();
        // The split draws from its own stream so that it does not depend on how many
        // numbers the generator consumed.
        order.shuffle(&mut seeded_rng(seed, FOLD_STREAM + 1));
        let n_train = n - n_test;
        Ok(Split {
            train: self.subset(&order[..n_train]),
            test: self.subset(&order[n_train..]),
        })
    }

    /// Writes [`Dataset::to_csv`] to `path`, whole or not at all.
    pub fn write_csv(&self, path: &Path) -> Result<(), TrainError> {
        Ok(stickslip::files::write_atomically(path, self.to_csv())?)
    }

    /// The set as CSV: a header of `name[unit]` columns (features, then target) and one
    /// row per sample, every number in Rust's shortest round-trip form, so that another
    /// program parses back exactly the same f64 values.
    pub fn to_csv(&self) -> String {
        let mut text = String::new();
        let header: Vec<String> = self
            .features
            .iter()
            .chain(std::iter::once(&self.target))
            .map(Quantity::header)
            .collect();
        text.push_str(&header.join(","));
        text.push('\n');
        for (sample, target) in self.targets.iter().enumerate() {
            for value in self.inputs.column(sample).iter() {
                let _ = write!(text, "{value},");
            }
            let _ = writeln!(text, "{target}");
        }
        text
    }

    /// Minimum and maximum of feature `index` over the samples.
    pub fn feature_range(&self, index: usize) -> (f64, f64) {
        min_max(self.inputs.row(index).iter().copied())
    }

    /// Minimum and maximum of the target over the samples.
    pub fn target_range(&self) -> (f64, f64) {
        min_max(self.targets.iter().copied())
    }
}

pub(crate) fn min_max(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

/// A training and a test set.
#[derive(Clone, Debug, PartialEq)]
pub struct Split {
    pub train: Dataset,
    pub test: Dataset,
}

impl Split {
    /// A split the user made (`--test-data`): the test set must hold the same columns,
    /// with the same units, as the training set, else its errors would compare
    /// different quantities. Both sets must be non-empty.
    pub fn given(train: Dataset, test: Dataset) -> Result<Split, TrainError> {
        let columns = |d: &Dataset| -> Vec<String> {
            d.features
                .iter()
                .chain(std::iter::once(&d.target))
                .map(Quantity::header)
                .collect()
        };
        let (expected, found) = (columns(&train), columns(&test));
        if let Some((e, f)) = expected.iter().zip(&found).find(|(e, f)| e != f) {
            return Err(TrainError::InvalidInput(format!(
                "the test data's column '{f}' does not match the training data's '{e}' \
                 (training columns: {}; test columns: {})",
                expected.join(", "),
                found.join(", ")
            )));
        }
        if train.is_empty() || test.is_empty() {
            return Err(TrainError::InvalidInput(format!(
                "{} training and {} test samples: both sets must be non-empty",
                train.len(),
                test.len()
            )));
        }
        Ok(Split { train, test })
    }
}

/// Name and unit of the synthetic set's columns; `NeuralLaw` finds the beam's inputs by
/// role, not by these names.
pub const SLIDING_VELOCITY: &str = "sliding_velocity";
pub const NORMAL_FORCE: &str = "normal_force";
pub const FRICTION_FORCE: &str = "friction_force";

/// Generation of the paper's synthetic data set from its settings (which live with the
/// weights file format in `stickslip::neural::weights`, since every trained model
/// records them).
pub trait Synthetic {
    /// mu(|v|) F_n with the sign of v: the noise-free force of Eq. 6 (N).
    fn exact_force(&self, sliding_velocity: f64, normal_force: f64) -> f64;
    /// All samples, features (sliding_velocity [m/s], normal_force [N]) and target
    /// friction_force [N], reproducible from `seed`.
    fn generate(&self, seed: u64) -> Result<Dataset, TrainError>;
    /// `generate`, split into training and test sets by `test_fraction`.
    fn generate_split(&self, seed: u64) -> Result<Split, TrainError>;
}

/// The settings' ranges (`SyntheticSpec::check`), checked before any sample is drawn.
fn check(spec: &SyntheticSpec) -> Result<(), TrainError> {
    spec.check().map_err(TrainError::InvalidInput)
}

impl Synthetic for SyntheticSpec {
    /// mu(|v|) F_n with the sign of v: the noise-free force of Eq. 6 (N).
    fn exact_force(&self, sliding_velocity: f64, normal_force: f64) -> f64 {
        let coefficient = self.kinetic_coefficient
            + (self.static_coefficient - self.kinetic_coefficient)
                * platform_exp(-self.decay * sliding_velocity.abs());
        signum_or_zero(sliding_velocity) * coefficient * normal_force
    }

    /// All samples, features (sliding_velocity [m/s], normal_force [N]) and target
    /// friction_force [N], reproducible from `seed`: the draws the velocity cut leaves.
    fn generate(&self, seed: u64) -> Result<Dataset, TrainError> {
        check(self)?;
        let mut rng = seeded_rng(seed, DATA_STREAM);
        let normal_force = Uniform::new(self.normal_force_min, self.normal_force_max);
        let velocity =
            Normal::new(0.0, self.velocity_std).map_err(|e| TrainError::Distribution {
                quantity: "velocity",
                source: e,
            })?;
        let mut columns = Vec::with_capacity(2 * self.samples);
        let mut targets = Vec::with_capacity(self.samples);
        for _ in 0..self.samples {
            let f_n: f64 = normal_force.sample(&mut rng);
            let v = loop {
                let candidate: f64 = velocity.sample(&mut rng);
                if self
                    .velocity_limit
                    .is_none_or(|limit| candidate.abs() <= limit)
                {
                    break candidate;
                }
            };
            // Drawn for every sample, whatever the noise level and the cut, so the
            // velocities and normal forces of the other samples do not depend on them.
            // For the additive noise alone, sigma z is the old generator's
            // Normal(0, sigma) draw, bit for bit (hypot(sigma, 0) = sigma exactly).
            let z: f64 = StandardNormal.sample(&mut rng);
            if self.velocity_cut > 0.0 && v.abs() <= self.velocity_cut {
                continue;
            }
            let force = self.exact_force(v, f_n);
            let sigma = platform_hypot(self.noise_std, self.relative_noise_std * force);
            columns.extend([v, f_n]);
            targets.push(force + sigma * z);
        }
        if targets.len() < 10 {
            return Err(TrainError::InvalidInput(format!(
                "synthetic data: only {} of {} draws lie outside the velocity cut \
                 {} m/s; at least 10 samples are needed",
                targets.len(),
                self.samples,
                self.velocity_cut
            )));
        }
        let inputs = DMatrix::from_vec(2, targets.len(), columns);
        Ok(Dataset {
            features: vec![
                Quantity::new(SLIDING_VELOCITY, "m/s"),
                Quantity::new(NORMAL_FORCE, "N"),
            ],
            roles: vec![FeatureRole::SlidingVelocity, FeatureRole::NormalForce],
            target: Quantity::new(FRICTION_FORCE, "N"),
            inputs,
            targets,
        })
    }

    /// The generated set split `1 - test_fraction` / `test_fraction` (70/30 by default).
    fn generate_split(&self, seed: u64) -> Result<Split, TrainError> {
        self.generate(seed)?.split(self.test_fraction, seed)
    }
}

/// The synthetic data keep the platform's `exp` and `hypot`, not
/// `stickslip::elementary`: the shipped weights were trained on data made with them, and
/// the ignored tests that retrain those weights bit for bit fail with libm's (measured,
/// issue 25). The trainer is CPU-dependent anyway (matrixmultiply's run-time FMA kernel).
#[allow(clippy::disallowed_methods)]
fn platform_exp(x: f64) -> f64 {
    x.exp()
}

/// See [`platform_exp`].
#[allow(clippy::disallowed_methods)]
fn platform_hypot(x: f64, y: f64) -> f64 {
    x.hypot(y)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Population mean and standard deviation.
    fn mean_std(values: &[f64]) -> (f64, f64) {
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let var = values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
        (mean, var.sqrt())
    }

    /// The residual of each target against Eq. 6: additive (F_f - F) or relative
    /// (F_f / F - 1).
    fn residuals(spec: &SyntheticSpec, data: &Dataset, relative: bool) -> Vec<f64> {
        (0..data.len())
            .map(|i| {
                let exact = spec.exact_force(data.inputs[(0, i)], data.inputs[(1, i)]);
                if relative {
                    data.targets[i] / exact - 1.0
                } else {
                    data.targets[i] - exact
                }
            })
            .collect()
    }

    // Tolerances below: about 3.5 standard errors of each statistic for these n (the
    // statistics against the authors' file are tests/neural/authors_data.rs).
    #[test]
    fn synthetic_data_follows_the_spec_and_is_reproducible() {
        let spec = SyntheticSpec::default();
        let a = spec.generate(7).unwrap();
        let b = spec.generate(7).unwrap();
        assert_eq!(a, b);
        assert_ne!(a, spec.generate(8).unwrap());
        // P(|v| <= 1e-4) = 8.0e-4 for N(0, 0.1): 4.0 +- 2.0 of 5000 draws removed.
        let removed = 5000 - a.len();
        assert!(removed <= 12, "{removed} removed");
        assert!(a.inputs.row(0).iter().all(|v| v.abs() > 1e-4));
        let (f_min, f_max) = a.feature_range(1);
        assert!(f_min >= 98.0 && f_max < 102.0);
        // Relative residual: mean 0 +- 0.0003, std 0.02 +- 0.0002.
        let (mean, std) = mean_std(&residuals(&spec, &a, true));
        assert!(mean.abs() < 0.001, "relative noise mean {mean}");
        assert!((std - 0.02).abs() < 0.0007, "relative noise std {std}");
    }

    #[test]
    fn the_former_generator_limits_velocities_and_adds_absolute_noise() {
        let spec = SyntheticSpec::former();
        let a = spec.generate(7).unwrap();
        assert_eq!(a.len(), 5000);
        let (v_min, v_max) = a.feature_range(0);
        assert!(v_min >= -0.4 && v_max <= 0.4);
        let (f_min, f_max) = a.feature_range(1);
        assert!(f_min >= 90.0 && f_max < 110.0);
        // Additive residual: mean 0 +- 0.0003 N, std 0.02 +- 0.0002 N.
        let (mean, std) = mean_std(&residuals(&spec, &a, false));
        assert!(mean.abs() < 0.001, "noise mean {mean}");
        assert!((std - 0.02).abs() < 0.0007, "noise std {std}");
        // Velocity std of N(0, 0.1) truncated at 4 sigma stays ~0.1 (+- 0.001).
        let v_std = (a.inputs.row(0).iter().map(|v| v * v).sum::<f64>() / 5000.0).sqrt();
        assert!((v_std - 0.1).abs() < 0.004, "velocity std {v_std}");
    }

    #[test]
    fn the_cut_removes_draws_without_shifting_the_others() {
        let uncut = SyntheticSpec {
            velocity_cut: 0.0,
            ..SyntheticSpec::default()
        };
        let wide_cut = SyntheticSpec {
            velocity_cut: 0.01,
            ..SyntheticSpec::default()
        };
        let (all, kept) = (uncut.generate(3).unwrap(), wide_cut.generate(3).unwrap());
        let survivors: Vec<usize> = (0..all.len())
            .filter(|&i| all.inputs[(0, i)].abs() > 0.01)
            .collect();
        // About 8 % of the draws lie within 0.01 m/s (one tenth of sigma).
        assert!(all.len() - survivors.len() > 250);
        assert_eq!(kept, all.subset(&survivors));
        let too_few = SyntheticSpec {
            samples: 10,
            velocity_cut: 0.09,
            ..SyntheticSpec::default()
        };
        let message = too_few.generate(1).unwrap_err().to_string();
        assert!(message.contains("at least 10 samples"), "{message}");
    }

    #[test]
    fn split_is_70_30_and_a_partition() {
        let spec = SyntheticSpec::default();
        let data = spec.generate(1).unwrap();
        let split = data.split(0.3, 1).unwrap();
        let n_test = (data.len() as f64 * 0.3).round() as usize;
        assert_eq!(split.test.len(), n_test);
        assert_eq!(split.train.len(), data.len() - n_test);
        let mut all: Vec<f64> = split
            .train
            .targets
            .iter()
            .chain(split.test.targets.iter())
            .copied()
            .collect();
        let mut original = data.targets.clone();
        all.sort_by(f64::total_cmp);
        original.sort_by(f64::total_cmp);
        assert_eq!(all, original);
        assert!(data.split(1.0, 1).is_err());
    }

    #[test]
    fn a_given_split_needs_the_same_columns_and_units() {
        let data = SyntheticSpec::default().generate(1).unwrap();
        let (train, test) = (data.subset(&[0, 1, 2]), data.subset(&[3, 4]));
        let split = Split::given(train.clone(), test.clone()).unwrap();
        assert_eq!((split.train.len(), split.test.len()), (3, 2));
        let mut other_unit = test.clone();
        other_unit.target.unit = "kN".into();
        let message = Split::given(train.clone(), other_unit)
            .unwrap_err()
            .to_string();
        assert!(message.contains("'friction_force[kN]'"), "{message}");
        assert!(Split::given(train, data.subset(&[])).is_err());
    }
}
