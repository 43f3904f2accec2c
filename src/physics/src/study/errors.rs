//! A run's errors against its reference: onsets, period, corridor and the RMS of the
//! tip-deflection difference.

use super::measure::Measured;
use crate::metrics::Summary;
use serde::{Deserialize, Serialize};

/// Errors of a run against the reference; `None` where either run lacks the metric
/// (no breakaway, fewer than two major slips ...).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Errors {
    /// |breakaway - reference| (s).
    pub breakaway: Option<f64>,
    /// |first major-slip duration - reference| (s).
    pub first_slip_duration: Option<f64>,
    /// |stick-slip period - reference| (s).
    pub period: Option<f64>,
    /// max(|min - min_ref|, |max - max_ref|) of the corridor after breakaway (m).
    pub corridor: Option<f64>,
    /// RMS of the tip-deflection difference over the run (m).
    pub rms: f64,
}

fn difference(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    Some((a? - b?).abs())
}

/// RMS of the difference of two tip series on the same grid (m).
pub fn rms_difference(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    if n == 0 {
        return f64::NAN;
    }
    let sum: f64 = a[..n]
        .iter()
        .zip(&b[..n])
        .map(|(x, y)| (x - y).powi(2))
        .sum();
    (sum / n as f64).sqrt()
}

impl Errors {
    pub fn between(run: &Measured, reference: &Measured) -> Self {
        let (s, r) = (&run.summary, &reference.summary);
        let first_duration = |s: &Summary| s.major_slips.first().and_then(|m| m.duration);
        let corridor = match (s.corridor, r.corridor) {
            (Some((lo, hi)), Some((rlo, rhi))) => Some((lo - rlo).abs().max((hi - rhi).abs())),
            _ => None,
        };
        Self {
            breakaway: difference(s.breakaway, r.breakaway),
            first_slip_duration: difference(first_duration(s), first_duration(r)),
            period: difference(s.period, r.period),
            corridor,
            rms: rms_difference(&run.tip, &reference.tip),
        }
    }
}
