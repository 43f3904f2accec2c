//! Synthetic tribometer records: a rate-and-state law driven through the velocity
//! histories a tribometer runs (velocity steps up and down, ramps, a reversal through
//! v = 0, slide-hold-slide) at several normal forces, sampled at a fixed rate, with
//! Gaussian force noise.
//!
//! The force is the generating law's, `stickslip::friction::rate_and_state::RateStateLaw`
//! (aging or slip evolution), stepped through its `StatefulLaw` interface as the time loop
//! steps it: each record starts at the steady state of its first velocity, and the
//! velocity is held over each sample interval, for which the law's step is exact (for
//! the aging law the closed form theta(t) = D_c/V + (theta_0 - D_c/V) exp(-V t / D_c)),
//! so the records have no time-step error before the noise is added. That law is
//! implemented apart from the learned one (`stickslip::friction::learned_state`), so a fit that
//! reproduces it checks both.

use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

use super::series::ForceSeries;
use crate::data::{seeded_rng, DATA_STREAM};
use crate::error::TrainError;
use stickslip::friction::learned_state::{LearnedStateLaw, StateLawParameters};
use stickslip::friction::rate_and_state::RateStateLaw;
use stickslip::friction::rate_and_state::RateStateParameters;
use stickslip::friction::state::{LawStep, StatefulLaw};
use stickslip::friction::FrictionLaw;

/// The records' settings (defaults in [`TribometerSpec::default`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TribometerSpec {
    /// The generating rate-and-state law.
    pub law: RateStateParameters,
    /// One set of records per normal force (N).
    pub normal_forces: Vec<f64>,
    /// The slowest and fastest sliding speed (m/s); the middle one is their geometric
    /// mean.
    pub speed_min: f64,
    pub speed_max: f64,
    /// Slip held at each velocity of the steps (m): long against D_c, so that each
    /// step's decay is complete.
    pub hold_slip: f64,
    /// Time at rest of the slide-hold-slide record (s).
    pub hold_time: f64,
    /// Sampling interval (s).
    pub sample_interval: f64,
    /// Standard deviation of the additive force noise (N).
    pub noise_std: f64,
}

impl Default for TribometerSpec {
    /// The generating law is the scene's default rate-and-state law (aging, a = 0.01,
    /// b = 0.015, D_c = 10 um, mu_0 = 0.5 at V_0 = 1 mm/s), so that the learned law can
    /// stand beside it in the paper scene; driven from 1 mm/s to 0.1 m/s, the speeds of
    /// the paper scene's tip (belt 0.02 m/s), holding each velocity for 20 D_c, sampled
    /// at 10 kHz (the slowest step's decay spans 20 samples); the noise (0.2 N, 0.4 % of
    /// the force) is a load cell's.
    fn default() -> Self {
        TribometerSpec {
            law: RateStateParameters::default(),
            normal_forces: vec![60.0, 100.0, 140.0],
            speed_min: 1e-3,
            speed_max: 0.1,
            hold_slip: 2e-4,
            hold_time: 0.2,
            sample_interval: 1e-4,
            noise_std: 0.2,
        }
    }
}

/// Builds one velocity history sample by sample.
struct History {
    dt: f64,
    velocity: Vec<f64>,
}

impl History {
    fn new(dt: f64, start: f64) -> Self {
        History {
            dt,
            velocity: vec![start],
        }
    }

    fn samples(&self, duration: f64) -> usize {
        ((duration / self.dt).ceil() as usize).max(5)
    }

    /// Holds `speed` for `slip` (m) of sliding.
    fn hold(&mut self, speed: f64, slip: f64) -> &mut Self {
        let n = self.samples(slip / speed.abs());
        self.velocity.extend(std::iter::repeat_n(speed, n));
        self
    }

    /// At rest for `time` s.
    fn rest(&mut self, time: f64) -> &mut Self {
        let n = self.samples(time);
        self.velocity.extend(std::iter::repeat_n(0.0, n));
        self
    }

    /// Linearly to `speed` over `time` s.
    fn ramp(&mut self, speed: f64, time: f64) -> &mut Self {
        let from = *self.velocity.last().unwrap_or(&0.0);
        let n = self.samples(time);
        self.velocity
            .extend((1..=n).map(|k| from + (speed - from) * k as f64 / n as f64));
        self
    }
}

impl TribometerSpec {
    /// Checks the settings, with the field at fault named.
    pub fn check(&self) -> Result<(), TrainError> {
        let bad = |m: String| Err(TrainError::InvalidInput(format!("tribometer data: {m}")));
        if let Some(problem) = self.law.problem() {
            return bad(problem.to_string());
        }
        for (name, v) in [
            ("speed_min", self.speed_min),
            ("hold_slip", self.hold_slip),
            ("hold_time", self.hold_time),
            ("sample_interval", self.sample_interval),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return bad(format!("{name} must be positive and finite, got {v}"));
            }
        }
        if !(self.speed_max > self.speed_min && self.speed_max.is_finite()) {
            return bad(format!(
                "speed_max {} must exceed speed_min {}",
                self.speed_max, self.speed_min
            ));
        }
        if !(self.noise_std >= 0.0 && self.noise_std.is_finite()) {
            return bad(format!("noise_std must be >= 0, got {}", self.noise_std));
        }
        if self.normal_forces.is_empty()
            || self
                .normal_forces
                .iter()
                .any(|f| !(*f > 0.0 && f.is_finite()))
        {
            return bad("normal forces must be given, each positive".into());
        }
        Ok(())
    }

    /// The generating law, at its initial state.
    pub fn generating_law(&self) -> RateStateLaw {
        RateStateLaw::new(self.law.clone())
    }

    /// The generating law in the learned law's form (no correction): the same
    /// equations, with either evolution law.
    pub fn as_learned(&self) -> LearnedStateLaw {
        let l = &self.law;
        LearnedStateLaw {
            parameters: StateLawParameters {
                reference_coefficient: l.reference_coefficient,
                reference_velocity: l.reference_velocity,
                direct_effect: l.direct_effect,
                evolution_effect: l.evolution_effect,
                characteristic_slip: l.characteristic_slip,
                state_evolution: l.state_evolution,
            },
            correction: None,
        }
    }

    /// The four velocity histories, named.
    fn histories(&self) -> Vec<(&'static str, Vec<f64>)> {
        let (lo, hi) = (self.speed_min, self.speed_max);
        let mid = (lo * hi).sqrt();
        let slip = self.hold_slip;
        let dt = self.sample_interval;
        let mut steps = History::new(dt, lo);
        steps
            .hold(lo, slip)
            .hold(hi, slip)
            .hold(lo, slip)
            .hold(mid, slip)
            .hold(hi, slip)
            .hold(mid, slip);
        let mut ramps = History::new(dt, lo);
        ramps
            .hold(lo, slip)
            .ramp(hi, slip / mid)
            .hold(hi, slip)
            .ramp(lo, slip / mid)
            .hold(lo, slip);
        let mut reversal = History::new(dt, mid);
        reversal
            .hold(mid, slip)
            .ramp(-mid, 2.0 * slip / mid)
            .hold(-mid, slip);
        let mut healing = History::new(dt, mid);
        healing.hold(mid, slip).rest(self.hold_time).hold(mid, slip);
        vec![
            ("velocity steps", steps.velocity),
            ("ramps", ramps.velocity),
            ("reversal", reversal.velocity),
            ("slide-hold-slide", healing.velocity),
        ]
    }

    /// The records: per normal force, the four histories, with noise drawn from `seed`.
    pub fn generate(&self, seed: u64) -> Result<Vec<ForceSeries>, TrainError> {
        self.check()?;
        let mut law = self.generating_law();
        let noise =
            Normal::new(0.0, self.noise_std).map_err(|source| TrainError::Distribution {
                quantity: "force noise",
                source,
            })?;
        let mut rng = seeded_rng(seed, DATA_STREAM);
        let mut records = Vec::new();
        for &normal_force in &self.normal_forces {
            for (name, velocity) in self.histories() {
                let n = velocity.len();
                let mut series = ForceSeries {
                    name: format!("{name} at {normal_force} N"),
                    time: (0..n).map(|k| k as f64 * self.sample_interval).collect(),
                    velocity,
                    normal_force: vec![normal_force; n],
                    force: vec![0.0; n],
                };
                let v0 = series.velocity[0];
                law.set_state(&[self.law.characteristic_slip / v0.abs()])
                    .map_err(|e| TrainError::InvalidInput(format!("tribometer data: {e}")))?;
                series.force[0] = law.sliding_force(v0, normal_force);
                for k in 1..n {
                    let step = LawStep {
                        dt: self.sample_interval,
                        sliding_velocity: series.velocity[k],
                        normal_force,
                    };
                    series.force[k] = law.step_force_and_slope(step).0;
                    law.commit(step);
                }
                for f in &mut series.force {
                    *f += noise.sample(&mut rng);
                }
                records.push(series);
            }
        }
        Ok(records)
    }

    /// Words for the weights file's `training.data`.
    pub fn describe(&self) -> String {
        let l = &self.law;
        format!(
            "synthetic tribometer records (velocity steps, ramps, reversal, slide-hold-slide; {} to {} m/s; F_n {:?} N; every {} s; noise {} N) of rate-and-state friction ({} law, asinh-regularised): mu_0 {}, V_0 {} m/s, a {}, b {}, D_c {} m",
            self.speed_min, self.speed_max, self.normal_forces, self.sample_interval, self.noise_std,
            stickslip::choice::Choice::name(l.state_evolution),
            l.reference_coefficient, l.reference_velocity, l.direct_effect, l.evolution_effect, l.characteristic_slip
        )
    }
}
