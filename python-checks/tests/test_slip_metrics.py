"""The stick-slip metrics of the validation table (slip_metrics): on a constructed
sawtooth whose every number is known in closed form, and on the paper scene through the
FMU against the command line's own summary (src/physics/src/metrics.rs, exact transition
times).

The FMU part needs the FMUs and the release binary (see test_fmu.py); runs in ~2 s.
"""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest
from conftest import need
from fmpy import simulate_fmu

from stickslip_checks import slip_metrics
from stickslip_checks.artifacts import BEAM, find_binary

DT = 1e-3  # s
V_BELT = 0.02  # m/s
U_HIGH, U_LOW = 8e-3, 4.8e-3  # m: breakaway and re-stick deflection of the sawtooth
SLIP_SAMPLES = 130  # 0.130 s slip
RAMP_SAMPLES = 160  # (8 - 4.8) mm / 0.02 m/s = 0.160 s back on the belt


def sawtooth(n: int = 1201, burst: bool = True):
    """Stick ramp at v_b to 8 mm (t = 0.4 s), then slips of 0.13 s down to 4.8 mm (linear)
    and ramps of 0.16 s back up: onsets at 0.40, 0.69, 0.98 s, period 0.29 s.
    With `burst`, each slip has a 3-sample re-stick 30 ms in, before the deflection
    crosses the mid-level (the higher modes do this in the beam); it must not end the slip.
    """
    t = np.arange(n) * DT
    u = np.empty(n)
    stick = np.ones(n, bool)
    first = 400
    u[: first + 1] = V_BELT * t[: first + 1]
    k = first
    onsets = []
    while k < n:
        onsets.append(k)
        for j in range(SLIP_SAMPLES):
            if k + j >= n:
                break
            # Sample k + j is after j steps of slip: linear from U_HIGH to U_LOW.
            u[k + j] = U_HIGH - (U_HIGH - U_LOW) * j / SLIP_SAMPLES
            stick[k + j] = burst and 30 <= j < 33
        k += SLIP_SAMPLES
        for j in range(RAMP_SAMPLES):
            if k + j >= n:
                break
            u[k + j] = U_LOW + V_BELT * DT * j
            stick[k + j] = True
        k += RAMP_SAMPLES
    return t, u, stick, [o * DT for o in onsets]


@pytest.mark.parametrize("burst", [False, True])
def test_sawtooth_slips_durations_and_cycle_corridors(burst):
    t, u, stick, onsets = sawtooth(burst=burst)
    assert slip_metrics.breakaway(t, stick) == pytest.approx(0.400, abs=1e-12)
    slips = slip_metrics.major_slips(t, u, stick)
    assert [s.onset for s in slips] == pytest.approx(onsets, abs=1e-12)
    assert onsets == pytest.approx([0.40, 0.69, 0.98], abs=1e-12)
    for s in slips:
        assert s.duration == pytest.approx(SLIP_SAMPLES * DT, abs=1e-12)
    for s in slips[:-1]:
        assert s.cycle_complete
        assert s.cycle_max == pytest.approx(U_HIGH, abs=1e-12)
        # The lowest sample of a slip is one step before re-stick, then the ramp starts
        # at U_LOW exactly.
        assert s.cycle_min == pytest.approx(U_LOW, abs=1e-12)
    assert not slips[-1].cycle_complete
    assert slip_metrics.period(slips) == pytest.approx(0.29, abs=1e-12)


@pytest.mark.parametrize("lag_samples", [0, 30, -20, 100])
def test_phase_shift_recovers_a_known_delay(lag_samples):
    # The run is the sawtooth delayed by lag_samples: u(t) = u_ref(t - tau).
    t, u_ref, _, _ = sawtooth(n=1601, burst=False)
    u = np.roll(u_ref, lag_samples)
    tau = slip_metrics.phase_shift(t[200:], u[200:], u_ref[200:], 0.29)
    assert tau == pytest.approx(lag_samples * DT, abs=1e-12)


def test_phase_shift_refuses_a_run_shorter_than_its_search_window():
    t, u, _, _ = sawtooth(n=300, burst=False)
    with pytest.raises(ValueError, match="shorter"):
        slip_metrics.phase_shift(t, u, u, 0.29)


def test_no_slip_gives_no_metrics():
    t = np.arange(100) * DT
    stick = np.ones(100, bool)
    assert slip_metrics.breakaway(t, stick) is None
    assert slip_metrics.major_slips(t, V_BELT * t, stick) == []
    assert slip_metrics.period([]) is None


def test_fmu_slips_agree_with_the_command_line_summary(built, tmp_path):
    """Modal fidelity (fast): the metrics of the FMU's 1 ms samples against the CLI's
    summary from exact transition times (0.1 ms steps). A sampled transition is seen at
    the first 1 ms sample after it, so onsets and ends may be up to 1 ms late each."""
    fmus = need(built)
    result = simulate_fmu(
        str(fmus.paths[BEAM]),
        start_time=0.0,
        stop_time=1.2,
        output_interval=DT,
        start_values={"fidelity.level": fmus.models[BEAM].code("fidelity.level", "modal")},
        output=["tip_deflection", "stick"],
    )
    t, u, stick = result["time"], result["tip_deflection"], result["stick"].astype(bool)
    slips = slip_metrics.major_slips(t, u, stick)

    summary_path = tmp_path / "modal.json"
    command = [str(find_binary()), "simulate", "--fidelity", "modal",
               "--summary-json", str(summary_path), "--out", str(tmp_path / "modal.csv")]
    subprocess.run(command, check=True, capture_output=True, text=True)
    summary = json.loads(summary_path.read_text())

    assert slip_metrics.breakaway(t, stick) == pytest.approx(summary["breakaway"], abs=1e-9)
    assert len(slips) == len(summary["major_slips"]) == 3
    for ours, theirs in zip(slips, summary["major_slips"]):
        assert 0.0 <= ours.onset - theirs["onset"] < DT + 1e-9
        assert ours.duration == pytest.approx(theirs["duration"], abs=DT + 1e-9)
    assert slip_metrics.period(slips) == pytest.approx(summary["period"], abs=DT)
    # The run against itself: no shift.
    assert slip_metrics.phase_shift(t, u, u, summary["period"]) == 0.0
