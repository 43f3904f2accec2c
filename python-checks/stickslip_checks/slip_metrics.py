"""Stick-slip metrics of a sampled run: the numbers a reviewer compares between two
friction laws (paper Sec. 4). Pure numpy; no FMU needed.

The definitions follow src/physics/src/metrics.rs (the command line's summary), applied
to the samples an FMU returns (every 1 ms) instead of the exact transition times:

- breakaway: the first sample with stick false (s);
- major slips: the sawtooth's drops. The tip deflection crosses the corridor's
  mid-level (min + max) / 2 downward, after having been above mid + 1/4 of the corridor
  width since the previous drop (hysteresis against ripple). The onset is the last
  stick -> slip sample at or before the sawtooth's peak; bursts of short re-stick/slip
  events that the beam's higher modes cause after the peak belong to the slip;
- slip duration: from the onset to the first slip -> stick sample after the crossing (s);
- cycle corridor: min and max tip deflection from one onset to the next (m); the last
  cycle runs to the end of the run and is marked incomplete;
- period: mean spacing of the major-slip onsets (s);
- phase shift at the end time: the lag tau (s) that best aligns the run's last reference
  period with the reference curve, i.e. minimises the RMS of u(t) - u_ref(t - tau) over
  t in [t_end - P_ref, t_end], searched over |tau| <= P_ref / 2 on the sample grid.
  Positive: the run lags behind the reference. In degrees: 360 tau / P_ref.

A sampled onset is at most one sample after the exact one, so these agree with
src/physics/src/metrics.rs to within one output interval.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Slip:
    """One major slip: onset and duration (s); the cycle it starts, min/max (m)."""

    onset: float
    duration: float | None
    cycle_min: float
    cycle_max: float
    cycle_complete: bool


def breakaway(time: np.ndarray, stick: np.ndarray) -> float | None:
    """Time of the first sample with stick false (s); None if the tip never slips."""
    slipping = np.flatnonzero(~np.asarray(stick, bool))
    return float(time[slipping[0]]) if slipping.size else None


def slip_onsets(time: np.ndarray, stick: np.ndarray) -> np.ndarray:
    """Sample times at which stick turns false (stick -> slip)."""
    stick = np.asarray(stick, bool)
    k = np.flatnonzero(stick[:-1] & ~stick[1:]) + 1
    return time[k]


def stick_onsets(time: np.ndarray, stick: np.ndarray) -> np.ndarray:
    """Sample times at which stick turns true (slip -> stick)."""
    stick = np.asarray(stick, bool)
    k = np.flatnonzero(~stick[:-1] & stick[1:]) + 1
    return time[k]


def major_slips(time: np.ndarray, u: np.ndarray, stick: np.ndarray) -> list[Slip]:
    """The sawtooth's drops with their durations and cycle corridors (module doc)."""
    t0 = breakaway(time, stick)
    if t0 is None:
        return []
    after = time >= t0
    lo, hi = float(u[after].min()), float(u[after].max())
    mid, rearm = 0.5 * (lo + hi), 0.5 * (lo + hi) + 0.25 * (hi - lo)
    slips_at, sticks_at = slip_onsets(time, stick), stick_onsets(time, stick)
    onsets: list[float] = []
    durations: list[float | None] = []
    armed = True
    peak_u, peak_t = -np.inf, 0.0
    for k in range(1, len(u)):
        if u[k] > rearm:
            armed = True
        if u[k] > peak_u:
            peak_u, peak_t = u[k], time[k]
        if armed and u[k - 1] >= mid and u[k] < mid:
            armed = False
            before = slips_at[slips_at <= peak_t + 1e-12]
            onset = float(before[-1]) if before.size else t0
            later = sticks_at[sticks_at > time[k]]
            onsets.append(onset)
            durations.append(float(later[0]) - onset if later.size else None)
            peak_u, peak_t = -np.inf, 0.0
    result = []
    for i, (onset, duration) in enumerate(zip(onsets, durations)):
        complete = i + 1 < len(onsets)
        end = onsets[i + 1] if complete else np.inf
        window = (time >= onset - 1e-12) & (time < end - 1e-12)
        result.append(
            Slip(onset, duration, float(u[window].min()), float(u[window].max()), complete)
        )
    return result


def period(slips: list[Slip]) -> float | None:
    """Mean spacing of the major-slip onsets (s); needs two slips."""
    if len(slips) < 2:
        return None
    return (slips[-1].onset - slips[0].onset) / (len(slips) - 1)


def phase_shift(
    time: np.ndarray, u: np.ndarray, reference_u: np.ndarray, reference_period: float
) -> float:
    """Lag tau (s) of `u` behind `reference_u` over the last reference period (module doc).

    Both curves must be sampled on the same uniform grid `time`.
    """
    dt = float(time[1] - time[0])
    window = int(round(reference_period / dt))
    max_lag = window // 2
    if window < 2 or len(time) < window + max_lag + 1:
        raise ValueError("the run is shorter than one and a half reference periods")
    end = len(time)
    target = u[end - window : end]
    best_lag, best_cost = 0, np.inf
    for lag in range(-max_lag, max_lag + 1):
        # u(t) against u_ref(t - tau): the reference window moves back by `lag` samples;
        # a negative lag would need samples after the end, so the window is cut there.
        start, stop = end - window - lag, end - lag
        if stop > end:
            shift = stop - end
            cost = np.mean((target[: window - shift] - reference_u[start:end]) ** 2)
        else:
            cost = np.mean((target - reference_u[start:stop]) ** 2)
        if cost < best_cost:
            best_lag, best_cost = lag, cost
    return best_lag * dt
