"""FMI 3.0 events in co-simulation (issue 15, item 3; cosim_events): StickSlipBeam 3.0
returning early at a stick/slip switch, with and without Event Mode, coupled to
NeuralFriction 3.0 with the plain network and the signed coupling, against the FMI 2.0
Gauss-Seidel master at the same h and against the monolithic FMU.

What was measured (docs/cosimulation.md, "Coupling error with events"): the masters
that use the switches are closer to the monolithic run over the whole 1.2 s at every h
above the internal step
(ratios 0.84, 0.68, 0.79, 0.30, 0.77 and 0.41 at h = 1e-2 .. 2e-4 s); at h = 1e-4 s,
the internal step, every switch ends a step anyway, so nothing changes. Over the first
slip cycle alone the hold of the tangent during slip dominates and the gain is smaller
or none. The tests assert these facts with the margins given at each.

Needs the FMUs (both versions) built by `cargo run --release -p fmu-build`; without them
every test here FAILS and says how to build them. Runs in about 15 s.
"""

from __future__ import annotations

import numpy as np
import pytest
from conftest import need

from stickslip_checks import events as ce
from stickslip_checks.artifacts import fmu3_paths
from stickslip_checks.convergence import INTERNAL_STEP, STEPS, T_FIRST_CYCLE


@pytest.fixture(scope="module")
def study(built):
    """(runs by (master, h), rows by (master, h), the monolithic switch times)."""
    if isinstance(built, Exception):
        return built
    try:
        paths3 = fmu3_paths()
    except FileNotFoundError as error:
        return error
    _, runs, rows = ce.run_study(built, paths3)
    return runs, {(r.master, r.h): r for r in rows}, ce.monolithic_switches(built)


def test_without_events_fmi3_is_fmi2_bit_for_bit_and_event_mode_is_early_return(study):
    runs, _, _ = need(study)
    for h in STEPS:
        assert np.array_equal(runs[ce.FMI2_GS, h].tip_deflection, runs[ce.FMI3_GS, h].tip_deflection), h
        # Event Mode adds the standard's ceremony around the same exchange at the switch:
        # the numbers must not change.
        assert np.array_equal(
            runs[ce.EARLY_RETURN, h].tip_deflection, runs[ce.EVENT_MODE, h].tip_deflection
        ), h


def test_the_event_master_beats_fmi2_gauss_seidel_over_the_whole_run(study):
    _, rows, _ = need(study)
    for h in STEPS:
        events = rows[ce.EVENT_MODE, h].error_full
        fmi2 = rows[ce.FMI2_GS, h].error_full
        print(f"h = {h:g}: event mode {1e3 * events:.5f} mm, FMI 2.0 GS {1e3 * fmi2:.5f} mm")
        if h > INTERNAL_STEP * 1.5:
            # Measured ratios 0.30 to 0.84: 0.9 leaves room for rounding-level changes
            # and still says "clearly better", not "equal".
            assert events < 0.9 * fmi2, (h, events, fmi2)
        else:
            # h = the internal step: a switch always ends a step, no early return.
            assert rows[ce.EARLY_RETURN, h].beam_steps == round(ce.T_END / h)
            assert events == fmi2


def test_the_event_masters_error_falls_with_h(study):
    _, rows, _ = need(study)
    for measure in ("error_first_cycle", "error_full"):
        errors = [getattr(rows[ce.EVENT_MODE, h], measure) for h in STEPS]
        assert all(b < a for a, b in zip(errors, errors[1:])), (measure, errors)
    # First slip cycle: at least not worse than FMI 2.0 beyond 3 % (measured: 2.5 %
    # worse at 1e-3 s, equal at 1e-2 and 1e-4 s, up to 3.4x better at 5e-3 s).
    for h in STEPS:
        events = rows[ce.EVENT_MODE, h].error_first_cycle
        fmi2 = rows[ce.FMI2_GS, h].error_first_cycle
        assert events <= 1.03 * fmi2, (h, events, fmi2)


def test_the_reported_switches_are_the_monolithic_fmus_transitions(study):
    runs, _, monolithic = need(study)
    reference = [t for t in monolithic if t <= T_FIRST_CYCLE]
    assert len(reference) >= 5, reference
    # One internal step plus rounding: the beam stops at the end of the step that switched.
    tolerance = INTERNAL_STEP * (1 + 1e-6)
    for h in STEPS:
        switches = [t for t in runs[ce.EVENT_MODE, h].switches if t <= T_FIRST_CYCLE]
        # The breakaway happens before the coupling has made any difference.
        assert abs(switches[0] - reference[0]) <= tolerance, (h, switches[0], reference[0])
        if h <= 2e-4:
            # Fine enough that the coupled run follows the monolithic one switch by switch.
            assert len(switches) == len(reference), (h, switches, reference)
            for got, want in zip(switches, reference):
                assert abs(got - want) <= tolerance, (h, got, want)
        # Early return reports the switches inside steps: at most the event count.
        assert len(runs[ce.EARLY_RETURN, h].switches) <= len(runs[ce.EVENT_MODE, h].switches)


def test_the_frame_holds_the_csv_files_values(study):
    """events.to_frame: one row per master and h, as cosim_events.csv."""
    _, rows, _ = need(study)
    frame = ce.to_frame(list(rows.values()))
    assert len(frame) == len(ce.MASTERS) * len(STEPS)
    assert frame["switches"].tolist() == [r.switches for r in rows.values()]
    assert frame[ce.HEADERS[2]].tolist() == [1e3 * r.error_first_cycle for r in rows.values()]
