//! The phase of the sawtooth: how far apart two runs' major slips drift, and what a
//! time shift costs in tip deflection.
//!
//! Two runs of one scene at different resolutions slip at slightly different times, and
//! the difference grows from slip to slip (stick-slip here is not strictly periodic: on
//! the paper scene the intervals between onsets vary by +-20 %, so the growth is not a
//! constant period error but what the window shows of it). A time shift s costs at
//! most the sawtooth's modulus of continuity, omega(s) = max_t |tip(t + s) - tip(t)|,
//! which rises like the steepest slope times s and saturates at the sawtooth's
//! peak-to-peak height when the phase is lost.

use crate::study::{Measured, COMPARISON_INTERVAL};

/// The onsets (s) of a run's major slips, each slip once: the detection can report one
/// slip twice with the same onset (see [`super::first_cycle_deviation`]).
pub fn distinct_onsets(run: &Measured) -> Vec<f64> {
    let mut onsets: Vec<f64> = Vec::new();
    for slip in &run.summary.major_slips {
        if onsets.last().is_none_or(|&last| slip.onset > last) {
            onsets.push(slip.onset);
        }
    }
    onsets
}

/// The phase drift rate of run `a` against run `b` (s of time shift per s of simulated
/// time, dimensionless): with s_i = onset_i(a) - onset_i(b) over the major slips both
/// runs show, the largest |s_i - s_1| / (onset_i(b) - onset_1(b)), i >= 2. The largest,
/// not a fit: the intervals between slips vary, and a fit would average a growing
/// shift away.
///
/// `Some(0)` when neither run has two slips (no sawtooth in the window: nothing to
/// drift); `None` when only one of them has (the phase is not comparable).
pub fn drift_rate(a: &Measured, b: &Measured) -> Option<f64> {
    let (oa, ob) = (distinct_onsets(a), distinct_onsets(b));
    let n = oa.len().min(ob.len());
    if n < 2 {
        return (oa.len().max(ob.len()) < 2).then_some(0.0);
    }
    let s1 = oa[0] - ob[0];
    Some(
        (1..n)
            .map(|i| ((oa[i] - ob[i]) - s1).abs() / (ob[i] - ob[0]))
            .fold(0.0, f64::max),
    )
}

/// The sawtooth's modulus of continuity: the largest |tip(t + h) - tip(t)| (m) over
/// the samples of `tip` (every [`COMPARISON_INTERVAL`], linear between them) and over
/// every shift |h| <= `shift`. For a shift beyond the samples, or an infinite one
/// (phase unknown), the peak-to-peak height. Nondecreasing and subadditive in the
/// shift, as a deviation must be for the chain's triangle inequality.
pub fn shift_deviation(tip: &[f64], shift: f64) -> f64 {
    let steps = shift.abs() / COMPARISON_INTERVAL;
    if !steps.is_finite() || steps >= (tip.len().saturating_sub(1)) as f64 {
        let max = tip.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let min = tip.iter().copied().fold(f64::INFINITY, f64::min);
        return (max - min).max(0.0);
    }
    // Linear between samples, |tip(t_i + h) - tip(t_i)| is convex in h between whole
    // steps: its largest value over |h| <= shift is at a whole step or at the shift.
    let at = |steps: f64| {
        let whole = steps.floor() as usize;
        let fraction = steps - whole as f64;
        (0..tip.len() - whole)
            .map(|i| {
                let j = i + whole;
                let shifted = match tip.get(j + 1) {
                    Some(next) => tip[j] + fraction * (next - tip[j]),
                    None => tip[j],
                };
                (shifted - tip[i]).abs()
            })
            .fold(0.0, f64::max)
    };
    (1..=steps.floor() as usize)
        .map(|k| at(k as f64))
        .fold(at(steps), f64::max)
}

/// The largest shift (s) whose [`shift_deviation`] stays within `allowance` (m), by
/// bisection to 1e-6 s, at most `limit` (s).
pub fn shift_within(tip: &[f64], allowance: f64, limit: f64) -> f64 {
    if allowance <= 0.0 {
        return 0.0;
    }
    if shift_deviation(tip, limit) <= allowance {
        return limit;
    }
    let (mut low, mut high) = (0.0, limit);
    while high - low > 1e-6 {
        let mid = 0.5 * (low + high);
        if shift_deviation(tip, mid) <= allowance {
            low = mid;
        } else {
            high = mid;
        }
    }
    low
}
