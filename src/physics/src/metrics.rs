//! Summary metrics of a stick-slip run, robust to the short re-stick/slip bursts that
//! the beam's higher modes cause within one slip.
//!
//! - Breakaway: the first stick -> slip transition (s).
//! - Slip phases: every stick -> slip transition, bursts included.
//! - Major slips: the drops of the sawtooth. The tip deflection crosses the corridor's
//!   mid-level (min + max) / 2 downward, after having been above mid + 1/4 of the
//!   corridor width since the previous one (the hysteresis ignores ripple). The onset of
//!   a major slip is the last stick -> slip transition at or before the sawtooth's peak
//!   (the largest deflection since the previous crossing): bursts after the peak belong
//!   to the slip, not to its start. Its duration runs to the first transition to stick
//!   after the crossing.
//! - Stick-slip period: mean time between consecutive major-slip onsets (s).
//! - Corridor: min and max tip deflection after breakaway (m).

use crate::contact::{ContactState, Transition};
use crate::simulation::Sample;
use serde::{Deserialize, Serialize};

/// One major slip: onset time and duration (s).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MajorSlip {
    pub onset: f64,
    pub duration: Option<f64>,
}

/// Summary of a run.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// First stick -> slip transition (s); `None` when the tip never slips.
    pub breakaway: Option<f64>,
    /// Number of stick -> slip transitions.
    pub slip_phases: usize,
    /// The sawtooth's drops.
    pub major_slips: Vec<MajorSlip>,
    /// Mean time between major-slip onsets (s); needs two major slips.
    pub period: Option<f64>,
    /// Min and max tip deflection after breakaway (m).
    pub corridor: Option<(f64, f64)>,
}

impl Summary {
    pub fn new(samples: &[Sample], transitions: &[Transition]) -> Self {
        let breakaway = transitions
            .iter()
            .find(|t| t.to == ContactState::Slip)
            .map(|t| t.time);
        let slip_phases = transitions
            .iter()
            .filter(|t| t.to == ContactState::Slip)
            .count();
        let after: Vec<&Sample> = match breakaway {
            Some(t0) => samples.iter().filter(|s| s.time >= t0).collect(),
            None => Vec::new(),
        };
        let corridor = if after.is_empty() {
            None
        } else {
            Some(
                after
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| {
                        (lo.min(s.tip_deflection), hi.max(s.tip_deflection))
                    }),
            )
        };
        let mut major_slips = Vec::new();
        if let (Some((lo, hi)), Some(t0)) = (corridor, breakaway) {
            let mid = 0.5 * (lo + hi);
            let rearm = mid + 0.25 * (hi - lo);
            let mut armed = true;
            let mut peak = (f64::NEG_INFINITY, 0.0);
            for pair in samples.windows(2) {
                let (a, b) = (pair[0], pair[1]);
                if b.tip_deflection > rearm {
                    armed = true;
                }
                if b.tip_deflection > peak.0 {
                    peak = (b.tip_deflection, b.time);
                }
                if armed && a.tip_deflection >= mid && b.tip_deflection < mid {
                    armed = false;
                    let onset = transitions
                        .iter()
                        .rev()
                        .find(|t| t.to == ContactState::Slip && t.time <= peak.1)
                        .map(|t| t.time)
                        .unwrap_or(t0);
                    peak = (f64::NEG_INFINITY, 0.0);
                    let end = transitions
                        .iter()
                        .find(|t| t.to == ContactState::Stick && t.time > b.time)
                        .map(|t| t.time - onset);
                    major_slips.push(MajorSlip {
                        onset,
                        duration: end,
                    });
                }
            }
        }
        let period = if major_slips.len() >= 2 {
            let n = major_slips.len();
            Some((major_slips[n - 1].onset - major_slips[0].onset) / (n - 1) as f64)
        } else {
            None
        };
        Self {
            breakaway,
            slip_phases,
            major_slips,
            period,
            corridor,
        }
    }

    /// Human-readable summary.
    pub fn report(&self) -> String {
        let ms = |v: Option<f64>| match v {
            Some(v) => format!("{v:.4} s"),
            None => "none".into(),
        };
        let mut out = String::new();
        out += &format!("breakaway time          {}\n", ms(self.breakaway));
        out += &format!("slip phases             {}\n", self.slip_phases);
        out += &format!("major slips             {}", self.major_slips.len());
        if !self.major_slips.is_empty() {
            let onsets: Vec<String> = self
                .major_slips
                .iter()
                .map(|m| format!("{:.4}", m.onset))
                .collect();
            out += &format!(" (onsets {} s)", onsets.join(", "));
        }
        out += "\n";
        out += &format!("stick-slip period       {}\n", ms(self.period));
        match self.corridor {
            Some((lo, hi)) => {
                out += &format!(
                    "tip deflection after breakaway  min {:.3} mm, max {:.3} mm\n",
                    lo * 1e3,
                    hi * 1e3
                )
            }
            None => out += "tip deflection after breakaway  (no breakaway)\n",
        }
        out
    }
}
