//! What the tolerance is held over: the horizon the user asked for, and how the
//! deviation between two calibration runs is carried from the calibration window to it.

use super::drift::shift_within;
use crate::study::Measured;
use serde::Serialize;

/// A run up to this long (s of simulated time) is calibrated over its whole length, so
/// that the bound is measured over the run the user asked for. Longer runs, and open
/// horizons, are bounded over the calibration window of the first slips, with the phase
/// drift reported beside ([`Reach::Window`]). 10 s: the calibration's cost grows with
/// the run (the 10 um calibrations took 0.02-0.6 s for 1.2 s on the verification
/// scenes, so about 5 s for 10 s); and over a few seconds the slips of most
/// verification scenes lose their phase even between converged runs
/// (docs/speed-accuracy.md), so a longer tolerance is refused anyway.
pub const DIRECT_LIMIT: f64 = 10.0;

/// The simulated time over which the tolerance is to hold.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Horizon {
    /// The run ends at this time (s after its start): the scene's `time.end`, or in the
    /// FMU the experiment's stop time.
    Until(f64),
    /// No end is known (an FMU without a stop time, a digital twin).
    Open,
}

/// What the deviation between two calibration runs over the window [0, `window`]
/// bounds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reach {
    /// The window is the whole run: the largest deviation over the run.
    Whole,
    /// The horizon is open or longer than [`DIRECT_LIMIT`] (`asked`, if any): the
    /// tolerance bounds the window; the phase drift rate is reported beside, as a
    /// projection, not a bound (module doc of `auto`).
    Window { asked: Option<f64> },
}

impl Reach {
    /// The reach of a calibration over [0, `window`] s for `horizon`.
    pub fn of(horizon: Horizon, window: f64) -> Self {
        match horizon {
            Horizon::Until(end) if end <= window => Reach::Whole,
            Horizon::Until(end) => Reach::Window { asked: Some(end) },
            Horizon::Open => Reach::Window { asked: None },
        }
    }
}

/// The largest |a - b| (m) over the samples both runs have.
pub fn window_deviation(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(f64::NAN, |m, d| if m.is_nan() { d } else { m.max(d) })
}

/// Until when (s) a choice within the tolerance holds ([`super::Selection::holds_until`]):
/// with [`Reach::Window`] and a drift rate, the window plus the time the drift takes
/// to use up `room` (m, the tolerance left above the estimate) on the deepest
/// partner's tip (infinite without drift); else the horizon.
pub(super) fn holds_until(
    horizon: Horizon,
    reach: Reach,
    window: f64,
    drift_rate: Option<f64>,
    room: f64,
    deepest: &Measured,
) -> f64 {
    match (reach, drift_rate) {
        (Reach::Window { .. }, Some(rate)) => {
            let limit = 1e3 * window;
            let shift = shift_within(&deepest.tip, room, limit);
            if rate > 0.0 && shift < limit {
                window + shift / rate
            } else {
                f64::INFINITY
            }
        }
        (Reach::Window { .. }, None) => window,
        (_, _) => match horizon {
            Horizon::Until(end) => end,
            Horizon::Open => window,
        },
    }
}
