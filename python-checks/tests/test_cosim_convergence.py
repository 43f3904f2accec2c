"""Convergence of the Jacobi and Gauss-Seidel co-simulation (cosim_convergence) at
h = 2e-3, 1e-3, 5e-4 s: the error to 0.7 s against the monolithic StickSlipBeam run falls
monotonically, the fitted order is first order (0.7 .. 1.5: the force is held over each
step) and breakaway stays at 0.400 s within h.

Needs the FMUs built by `cargo run --release -p fmu-build`; without them every test here
FAILS (it is not skipped) and says how to build them. Runs in a few seconds.
"""

from __future__ import annotations

import pytest
from conftest import need

from stickslip_checks import convergence as cc
from stickslip_checks.scene import BREAKAWAY_EXPECTED

STEPS = [2e-3, 1e-3, 5e-4]
SCHEMES = ["Jacobi", "Gauss-Seidel"]


@pytest.fixture(scope="module")
def study(built):
    """(reference, rows) over STEPS and SCHEMES, or the error that says how to build."""
    if isinstance(built, Exception):
        return built
    return cc.run_study(built, steps=STEPS, schemes=SCHEMES, t_end=cc.T_FIRST_CYCLE)


def rows_of(study, scheme):
    _, rows = need(study)
    rs = sorted((r for r in rows if r.scheme == scheme), key=lambda r: -r.h)
    assert [r.h for r in rs] == STEPS
    return rs


@pytest.mark.parametrize("scheme", SCHEMES)
def test_error_decreases_monotonically(study, scheme):
    errors = [r.error_first_cycle for r in rows_of(study, scheme)]
    assert all(b < a for a, b in zip(errors, errors[1:])), errors


@pytest.mark.parametrize("scheme", SCHEMES)
def test_first_order(study, scheme):
    rs = rows_of(study, scheme)
    order = cc.observed_order([r.h for r in rs], [r.error_first_cycle for r in rs])
    assert 0.7 <= order <= 1.5, order


@pytest.mark.parametrize("scheme", SCHEMES)
def test_breakaway_within_h(study, scheme):
    for r in rows_of(study, scheme):
        assert r.breakaway is not None, f"h = {r.h}: no slip"
        assert abs(r.breakaway - BREAKAWAY_EXPECTED) <= r.h + 1e-12, (r.h, r.breakaway)


def test_gauss_seidel_beats_jacobi(study):
    """Jacobi feeds the beam a force one step older: same order, larger error."""
    for j, g in zip(rows_of(study, "Jacobi"), rows_of(study, "Gauss-Seidel")):
        assert g.error_first_cycle < j.error_first_cycle, (j.h, g.error_first_cycle)


@pytest.fixture(scope="module")
def main_job_study(built):
    """The main job's study: every scheme at every h to 1.2 s, and the monolithic runs'
    dependence on h."""
    if isinstance(built, Exception):
        return built
    references, rows = cc.run_study(built)
    return cc.step_independence(built, references), rows


def test_the_monolithic_reference_does_not_depend_on_h(main_job_study):
    """StickSlipBeam alone steps internally at 1e-4 s whatever the communication step:
    sampled at common times, h = 1e-3 s and 1e-4 s agree to rounding (1e-12 m)."""
    independence, _ = need(main_job_study)
    assert set(independence) == set(cc.LAWS)
    for law, difference in independence.items():
        assert difference <= 1e-12, (law, difference)


def test_every_scheme_breaks_away_within_h(main_job_study):
    _, rows = need(main_job_study)
    for r in rows:
        assert r.breakaway is not None, (r.scheme, r.h)
        assert abs(r.breakaway - BREAKAWAY_EXPECTED) <= r.h + 1e-12, (r.scheme, r.h, r.breakaway)


def test_the_signed_coupling_is_within_the_exponential_laws_error_at_every_asymptotic_h(
    main_job_study,
):
    _, rows = need(main_job_study)
    error = {(r.scheme, r.h): r.error_first_cycle for r in rows}
    for h in cc.ASYMPTOTIC:
        assert error[cc.SIGNED, h] <= error[cc.BASELINE, h], (h, error[cc.SIGNED, h])


def test_the_frame_holds_the_csv_files_values(main_job_study):
    """convergence.to_frame: one row per run, the errors in mm, as cosim_convergence.csv."""
    _, rows = need(main_job_study)
    frame = cc.to_frame(rows)
    assert len(frame) == len(rows) == len(cc.STEPS) * len(cc.SCHEMES)
    assert frame["scheme"].tolist() == [r.scheme for r in rows]
    assert frame[cc.HEADERS[2]].tolist() == [1e3 * r.error_first_cycle for r in rows]
