//! The Pareto front: the runs no other run of the same law beats in both wall time and
//! RMS error, and the points of it that `auto` reads.

use super::configuration::Configuration;
use super::errors::Errors;
use super::law::Law;
use super::measure::Measured;
use serde::{Deserialize, Serialize};

/// One row of the study.
#[derive(Clone, Debug)]
pub struct Row {
    /// The law of the run, and of the reference its errors are against.
    pub law: Law,
    pub measured: Measured,
    pub errors: Errors,
    pub on_front: bool,
}

/// Marks the rows that no other row of the same law beats in both wall time and RMS
/// error: each law's errors are against its own reference, so a front across laws
/// would compare unlike things.
pub fn mark_pareto_front(rows: &mut [Row]) {
    let points: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.measured.seconds, r.errors.rms))
        .collect();
    let laws: Vec<Law> = rows.iter().map(|r| r.law.clone()).collect();
    for (k, row) in rows.iter_mut().enumerate() {
        let (t, e) = points[k];
        row.on_front = e.is_finite()
            && !points.iter().enumerate().any(|(j, &(tj, ej))| {
                j != k && laws[j] == laws[k] && tj <= t && ej <= e && (tj < t || ej < e)
            });
    }
}

/// The front, cheapest first (so error decreases along it): of the one law of `rows`,
/// or each law's front interleaved by wall time when `rows` has several (see
/// [`front_of`]).
pub fn front(rows: &[Row]) -> Vec<&Row> {
    let mut front: Vec<&Row> = rows.iter().filter(|r| r.on_front).collect();
    front.sort_by(|a, b| a.measured.seconds.total_cmp(&b.measured.seconds));
    front
}

/// A point of the measured front as the `auto` fidelity reads it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FrontPoint {
    pub configuration: Configuration,
    /// Wall time measured in the study (s).
    pub seconds: f64,
    /// RMS tip-deflection error against the study's reference (m).
    pub rms_error: f64,
}

/// The front of `law` alone, cheapest first.
pub fn front_of<'a>(rows: &'a [Row], law: &Law) -> Vec<&'a Row> {
    front(rows).into_iter().filter(|r| r.law == *law).collect()
}

/// The points of `front` (rows on a front, cheapest first: [`front`], [`front_of`]) as
/// `auto` reads them.
pub fn front_points(front: &[&Row]) -> Vec<FrontPoint> {
    front
        .iter()
        .map(|r| FrontPoint {
            configuration: r.measured.configuration,
            seconds: r.measured.seconds,
            rms_error: r.errors.rms,
        })
        .collect()
}
