"""What the two-algorithm table (paper_algorithms) relies on:

- under the paper authors' algorithm (`--preset paper-authors`) the breakaway of both
  laws is the analytical one under their preload, and the network's curve is the
  analytical law's up to it: in stick the tip moves with the belt and slips when the
  holding force reaches mu_s F_n, a condition no slip law enters (the network at
  v_rel = -v_b and F_n = 100 N plays no part before the first slip);
- the phase shift (onset shift and period difference) read from the major-slip onsets
  of two constructed sawtooth series with a known shift and known periods returns them,
  and so does the lag over the last period.

The command-line part needs the release binary (artifacts.find_binary) and converts the
authors' network (data/paper-authors/); runs in ~2 s.
"""

from __future__ import annotations

import numpy as np
import pytest

from stickslip_checks import paper_algorithms as pa
from stickslip_checks import paper_authors, slip_metrics
from stickslip_checks.artifacts import find_binary
from stickslip_checks.scene import BREAKAWAY_EXPECTED

# The authors' preload, a fraction of F_crit = mu_s F_n (docs/paper-authors-scene.md,
# stickslip::scene_preset). The holding force starts at PRELOAD F_crit and grows at
# k v_b, so t_b = (1 - PRELOAD) F_crit / (k v_b) = (1 - PRELOAD) 0.400 s = 0.396 s.
PRELOAD = 0.01
DT = 1e-4  # s, the scene's time step
# The switch is found at the end of the step in which the holding force reaches F_crit:
# at most one step after t_b; a second step covers the rounding of the force against
# F_crit at that step's boundary (t_b / dt = 3960 is a whole number of steps).
BREAKAWAY_TOLERANCE = 2 * DT


@pytest.fixture(scope="module")
def network(tmp_path_factory):
    return paper_authors.convert(tmp_path_factory.mktemp("onnx") / "authors.onnx")


@pytest.mark.parametrize("fidelity", ["modal", "beam"])
def test_breakaway_under_the_preload_is_analytical_and_law_independent(
        fidelity, network, tmp_path):
    binary = find_binary()
    analytical, neural = (pa.simulate(binary, "authors'", fidelity, law, network, tmp_path)
                          for law in (pa.ANALYTICAL, pa.NETWORK))
    expected = (1 - PRELOAD) * BREAKAWAY_EXPECTED
    for run in (analytical, neural):
        assert run.summary["breakaway"] == pytest.approx(expected, abs=BREAKAWAY_TOLERANCE)
    assert neural.summary["breakaway"] == analytical.summary["breakaway"]
    before = analytical.time < analytical.summary["breakaway"] - 1e-12
    # Bit for bit: the stick steps never evaluate the slip law.
    assert np.array_equal(neural.tip_deflection[before], analytical.tip_deflection[before])
    # The stick ramp itself: the preload deflection plus v_b t (u_0 = 1 % of 8 mm), to
    # 1e-9 m, far below the 2 um of one step of the belt.
    ramp = PRELOAD * 8e-3 + 0.02 * analytical.time[before]
    assert np.max(np.abs(analytical.tip_deflection[before] - ramp)) < 1e-9


V_BELT = 0.02  # m/s
U_HIGH = 8e-3  # m: every stick ramp ends here, at the next onset
SLIP = 0.08  # s: the slip's duration, a linear drop


def sawtooth(onsets: list[float], t_end: float = 1.2):
    """Time, tip deflection and stick on the DT grid: stick ramps at V_BELT that reach
    U_HIGH at each onset, then a slip of SLIP s down to where the next ramp starts."""
    t = np.arange(int(round(t_end / DT)) + 1) * DT
    u, stick = np.empty_like(t), np.ones(t.shape, bool)
    ends = list(onsets[1:]) + [onsets[-1] + onsets[-1] - onsets[-2]]
    for i, time in enumerate(t):
        before = [k for k, o in enumerate(onsets) if o <= time + 1e-12]
        if not before:
            u[i] = U_HIGH - V_BELT * (onsets[0] - time)
            continue
        k = before[-1]
        low = U_HIGH - V_BELT * (ends[k] - onsets[k] - SLIP)
        if time < onsets[k] + SLIP - 1e-12:
            u[i] = U_HIGH - (U_HIGH - low) * (time - onsets[k]) / SLIP
            stick[i] = False
        else:
            u[i] = U_HIGH - V_BELT * (ends[k] - time)
    return t, u, stick


def run_of(onsets: list[float]) -> pa.Run:
    t, u, stick = sawtooth(onsets)
    slips = slip_metrics.major_slips(t, u, stick)
    summary = {"major_slips": [{"onset": s.onset} for s in slips],
               "period": slip_metrics.period(slips)}
    return pa.Run("test", "test", "test", summary, t, u)


@pytest.mark.parametrize("delay, spacing, expected_shift, expected_difference", [
    # A pure delay of 12.3 ms at the same period: every onset moves by it.
    (0.0123, 0.2, 0.0123, 0.0),
    # First onset 5 ms earlier and a 5 % longer period: the fourth onset (index 3)
    # comes -5 + 3 x 10 = +25 ms after the reference's.
    (-0.005, 0.21, 0.025, 0.05),
])
def test_phase_shift_of_sawtooth_series_with_a_known_shift(
        delay, spacing, expected_shift, expected_difference):
    reference = run_of([0.4 + 0.2 * i for i in range(4)])
    shifted = run_of([0.4 + delay + spacing * i for i in range(4)])
    assert reference.onsets == pytest.approx([0.4, 0.6, 0.8, 1.0], abs=1e-9)
    phase = pa.shift(reference.onsets, shifted.onsets)
    assert phase.onset_index == 3
    # Onsets are sample times on the DT grid, so each is exact to rounding.
    assert phase.onset_shift == pytest.approx(expected_shift, abs=1e-9)
    assert phase.period_difference == pytest.approx(expected_difference, abs=1e-9)
    if expected_difference == 0.0:
        # The whole-curve estimate: over the last reference period the run is the
        # reference delayed by `delay`, found on the sample grid.
        assert pa.end_lag(shifted, reference) == pytest.approx(delay, abs=1e-9)


def test_shift_of_runs_with_different_slip_counts_uses_the_last_common_onset():
    phase = pa.shift([0.4, 0.6, 0.8], [0.41, 0.58, 0.77, 0.95])
    assert phase.onset_index == 2
    assert phase.onset_shift == pytest.approx(-0.03, abs=1e-12)
    # Mean periods 0.2 and 0.18 s: -10 %.
    assert phase.period_difference == pytest.approx(-0.1, abs=1e-12)
    assert pa.shift([], [0.4]) is None
