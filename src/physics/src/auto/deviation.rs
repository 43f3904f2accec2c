//! The first-cycle deviation between two runs.

use crate::study::{Measured, COMPARISON_INTERVAL};

/// The largest |tip - reference tip| (m) over the first stick-slip cycle of
/// `reference`: samples on the [`COMPARISON_INTERVAL`] grid before the onset of its
/// second major slip (the first with an onset later than the first's), or every sample
/// when it has no such slip.
pub fn first_cycle_deviation(tip: &[f64], reference: &Measured) -> f64 {
    let n = tip.len().min(reference.tip.len());
    // The second slip is the first with a later onset than the first: the detection
    // can report one slip twice (two downward crossings of the mid-level before a new
    // stick -> slip transition, as the neural law gave at dt <= 5e-6 s), and a window
    // ending at the first onset would skip the very slip it must cover.
    let slips = &reference.summary.major_slips;
    let second = slips
        .first()
        .and_then(|first| slips.iter().find(|s| s.onset > first.onset));
    let window = match second {
        Some(second) => ((second.onset / COMPARISON_INTERVAL).floor() as usize + 1).min(n),
        None => n,
    };
    if window == 0 {
        return f64::NAN;
    }
    tip[..window]
        .iter()
        .zip(&reference.tip[..window])
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}
