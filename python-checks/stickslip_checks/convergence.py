"""Convergence of the co-simulation StickSlipBeam.fmu + NeuralFriction.fmu in the
communication step h, for a Jacobi and a Gauss-Seidel master over fmpy's FMU2Slave, with
the exponential law and with the paper's plain network.

Set-up
    StickSlipBeam at beam fidelity (fidelity.level = beam, internal step time.step =
    1e-4 s) with friction.law = external, coupled to NeuralFriction. The normal force
    of both FMUs stays at its start value 100 N. Two laws, each with its coupling
    (StickSlipBeam's external.coupling, master.COUPLINGS):
    - exponential law, magnitude coupling: beam relative_velocity -> friction
      sliding_velocity; friction friction_force_magnitude -> beam external.kinetic_force
      and static_limit -> beam external.static_limit. The beam applies the magnitude
      along its own v_rel: it places the law's jump at v = 0 itself.
    - plain network (weights paper-plain.json), signed coupling: also friction
      friction_force, friction_force_slope and evaluated_velocity -> beam
      external.friction_force, external.friction_slope and external.sliding_velocity.
      The beam solves the law's tangent within its internal steps (see
      stickslip::contact). The network is smooth and steep at v = 0 (-13 N at 0, +50 N
      1 mm/s above), so the magnitude coupling, also run for comparison, flips its sign
      there and a held force alone would be an explicit feedback of gain >> 1.
    Each law's reference is StickSlipBeam alone with that law at the same fidelity
    (friction.law = exponential, or neural with the same weights), run once at
    h = 1e-4 s (its internal step) and sampled at the coarse communication points. That
    the monolithic FMU does not depend on h at the internal grid is checked by comparing
    it with a monolithic run at h = 1e-3 s.

Schemes (t_n = n h; inputs are held constant over a step: zero-order hold; all run by
the co-simulation master, master.run)
    Jacobi        At t_n both FMUs read the other's outputs at t_n, then both step
                  t_n -> t_{n+1}. The friction FMU's output at t_n is the law evaluated
                  at the input it held over the previous step, v_rel(t_{n-1}); so over
                  [t_n, t_{n+1}] the beam sees F(v_rel(t_{n-1})): a delay of one step.
    Gauss-Seidel  Beam first: the beam steps t_n -> t_{n+1} with the friction outputs
                  at t_n. The friction FMU then gets the beam's new relative_velocity
                  v_rel(t_{n+1}) and is evaluated (it is stateless, its outputs follow
                  its inputs directly), and that force F(v_rel(t_{n+1})) feeds the
                  beam's next step. Over [t_n, t_{n+1}] the beam sees F(v_rel(t_n)):
                  no delay beyond the hold itself. (Since NeuralFriction has no state,
                  the order only matters through which beam output the friction FMU
                  sees: t_{n+1} here, t_n in Jacobi.)
    GS friction-first
                  The friction FMU steps first with v_rel(t_n), then the beam steps with
                  its outputs at t_{n+1}, i.e. again F(v_rel(t_n)). For a stateless
                  friction FMU this must reproduce beam-first Gauss-Seidel exactly;
                  it is run as a check of that.

    Both are first order in h with the magnitude coupling: holding a force over a step
    of length h makes an O(h) force error; Jacobi's extra delay of one step adds to the
    lag (same order, larger constant: about 2.8 times the Gauss-Seidel error here). The
    signed coupling holds the law's tangent instead (value and slope at the velocity
    the friction FMU saw; with Jacobi that is v_rel(t_{n-1}), which evaluated_velocity
    tells the beam): the remaining error is that of the linearisation over a step.

Metrics per run: max |tip deflection coupled - monolithic (same law)| over the communication points
in [0, 0.7 s] (the first slip cycle, before the later re-stick bursts decorrelate the
runs) and over [0, 1.2 s]; wall time of the master loop; breakaway (first
communication point with stick false, expected 0.400 s within h). The observed order is
the least-squares slope of log(error to 0.7 s) against log(h) over the asymptotic range
ASYMPTOTIC = 2e-3 .. 1e-4 s, where halving h halves the error to within a few per cent;
at 1e-2 and 5e-3 s Jacobi is not yet asymptotic (error ratio 1.74 for a halving). The
slope over all seven h is printed too. The error to 1.2 s is not monotone in h (the
re-stick bursts after the first cycle decorrelate the runs), so its slope is only
indicative. For the plain network the error to 0.7 s of the signed coupling is compared
with the exponential law's Gauss-Seidel error at every h (the aim: no larger).

The library of the cosim_convergence entry point; the checks (monolithic run independent
of h, breakaway within h, the signed coupling within the exponential law's error) are
tests/test_cosim_convergence.py's and tests/test_signed_coupling.py's.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import master, plots
from .artifacts import BEAM, FRICTION, Fmus
from .tables import format_table, frame, write_csv

if TYPE_CHECKING:
    import pandas as pd

FIDELITY_LEVEL = "beam"
INTERNAL_STEP = 1e-4  # s, StickSlipBeam time.step
STEPS = [1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4]  # communication steps h (s)
ASYMPTOTIC = [2e-3, 1e-3, 5e-4, 2e-4, 1e-4]  # h used for the fitted order
T_END = 1.2
T_FIRST_CYCLE = 0.7

EXPONENTIAL = "exponential"
PLAIN = "plain network"
PLAIN_WEIGHTS = "paper-plain.json"
# Law -> (StickSlipBeam parameters of the monolithic run, NeuralFriction parameters).
LAWS = {
    EXPONENTIAL: ({"friction.law": "exponential"}, {"law": "exponential"}),
    PLAIN: (
        {"friction.law": "neural", "friction.weights": PLAIN_WEIGHTS},
        {"law": "neural", "weights": PLAIN_WEIGHTS},
    ),
}


@dataclass(frozen=True)
class Coupling:
    """How one row's runs are coupled: law, master scheme, stepping order, and
    StickSlipBeam's external.coupling."""

    law: str
    scheme: str
    order: tuple
    coupling: str


BEAM_FIRST, FRICTION_FIRST = (BEAM, FRICTION), (FRICTION, BEAM)
# Row label -> coupling. The first three are the exponential law's (the labels the
# tests and docs/cosimulation.md use); the others the plain network's.
MASTER = {
    "Jacobi": Coupling(EXPONENTIAL, master.JACOBI, BEAM_FIRST, "magnitude"),
    "Gauss-Seidel": Coupling(EXPONENTIAL, master.GAUSS_SEIDEL, BEAM_FIRST, "magnitude"),
    "GS friction-first": Coupling(EXPONENTIAL, master.GAUSS_SEIDEL, FRICTION_FIRST, "magnitude"),
    "plain, GS signed": Coupling(PLAIN, master.GAUSS_SEIDEL, BEAM_FIRST, "signed"),
    "plain, Jacobi signed": Coupling(PLAIN, master.JACOBI, BEAM_FIRST, "signed"),
    "plain, GS magnitude": Coupling(PLAIN, master.GAUSS_SEIDEL, BEAM_FIRST, "magnitude"),
}
SCHEMES = tuple(MASTER)
# The requirement: the plain network's signed Gauss-Seidel coupling is no further from
# its embedded run than the exponential law's Gauss-Seidel coupling from its own.
SIGNED, BASELINE = "plain, GS signed", "Gauss-Seidel"


@dataclass
class Series:
    """One run sampled at its communication points."""

    scheme: str
    h: float
    time: np.ndarray
    tip_deflection: np.ndarray
    stick: np.ndarray
    wall: float


def _grid(h: float, t_end: float) -> None:
    """ValueError unless h divides t_end."""
    n = int(round(t_end / h))
    if abs(n * h - t_end) > 1e-12:
        raise ValueError(f"h = {h} does not divide t_end = {t_end}")


def run_monolithic(fmus: Fmus, h: float, t_end: float = T_END, law: str = EXPONENTIAL) -> Series:
    """StickSlipBeam alone with `law` embedded (a key of LAWS), stepped at h with
    FMU2Slave."""
    _grid(h, t_end)
    beam, _ = LAWS[law]
    began = time.perf_counter()
    trace = master.run_alone(
        fmus,
        BEAM,
        "monolithic",
        h,
        t_end,
        parameters={BEAM: {"fidelity.level": FIDELITY_LEVEL, **beam}},
        record={BEAM: ["tip_deflection", "stick"]},
    )
    wall = time.perf_counter() - began
    return Series(
        f"monolithic {law}",
        h,
        trace.time,
        trace[BEAM, "tip_deflection"],
        trace[BEAM, "stick"],
        wall,
    )


def run_cosim(fmus: Fmus, scheme: str, h: float, t_end: float = T_END) -> Series:
    """StickSlipBeam (external friction) + NeuralFriction at step h, coupled as row label
    `scheme` of MASTER says."""
    if scheme not in SCHEMES:
        raise ValueError(f"unknown scheme {scheme!r}")
    _grid(h, t_end)
    setup = MASTER[scheme]
    _, friction = LAWS[setup.law]
    began = time.perf_counter()
    trace = master.run_coupled(
        fmus,
        h,
        t_end,
        beam={"fidelity.level": FIDELITY_LEVEL},
        friction=friction,
        record={BEAM: ["tip_deflection", "stick"]},
        scheme=setup.scheme,
        order=setup.order,
        coupling=setup.coupling,
    )
    wall = time.perf_counter() - began
    return Series(
        scheme, h, trace.time, trace[BEAM, "tip_deflection"], trace[BEAM, "stick"], wall
    )


# ----------------------------------------------------------------------------- metrics


def sample(reference: Series, times: np.ndarray) -> np.ndarray:
    """The reference tip deflection at `times` (which must lie on its grid)."""
    idx = np.rint(times / reference.h).astype(int)
    if np.max(np.abs(reference.time[idx] - times)) > 1e-9:
        raise ValueError("times are not on the reference grid")
    return reference.tip_deflection[idx]


def max_error(run: Series, reference: Series, t_max: float) -> float:
    keep = run.time <= t_max + 1e-12
    return float(np.max(np.abs(run.tip_deflection[keep] - sample(reference, run.time[keep]))))


def breakaway(run: Series) -> float | None:
    slipping = np.flatnonzero(~run.stick)
    return float(run.time[slipping[0]]) if slipping.size else None


def observed_order(hs, errors) -> float:
    """Least-squares slope of log(error) against log(h)."""
    return float(np.polyfit(np.log(hs), np.log(errors), 1)[0])


@dataclass
class Row:
    h: float
    scheme: str
    error_first_cycle: float  # m, over [0, 0.7 s]
    error_full: float  # m, over [0, 1.2 s]
    wall: float
    breakaway: float | None


def evaluate(run: Series, reference: Series) -> Row:
    return Row(
        run.h,
        run.scheme,
        max_error(run, reference, T_FIRST_CYCLE),
        max_error(run, reference, T_END),
        run.wall,
        breakaway(run),
    )


# ----------------------------------------------------------------------------- output

HEADERS = [
    "h [s]",
    "scheme",
    f"error to {T_FIRST_CYCLE} s [mm]",
    f"error to {T_END} s [mm]",
    "wall [s]",
    "breakaway [s]",
]


def table(rows: list[Row]) -> str:
    cells = [
        [
            f"{r.h:.0e}",
            r.scheme,
            f"{1e3 * r.error_first_cycle:.5f}",
            f"{1e3 * r.error_full:.5f}",
            f"{r.wall:.2f}",
            "-" if r.breakaway is None else f"{r.breakaway:.4f}",
        ]
        for r in rows
    ]
    return format_table(HEADERS, cells, left={1})


def csv_rows(rows: list[Row]) -> list[list[str]]:
    return [
        [
            repr(r.h),
            r.scheme,
            repr(1e3 * r.error_first_cycle),
            repr(1e3 * r.error_full),
            repr(r.wall),
            "" if r.breakaway is None else repr(r.breakaway),
        ]
        for r in rows
    ]


def to_frame(rows: list[Row]) -> pd.DataFrame:
    """The rows of cosim_convergence.csv as a DataFrame."""
    return frame(HEADERS, csv_rows(rows)).astype({h: float for h in HEADERS if h != "scheme"})


# ----------------------------------------------------------------------------- the study


def run_study(fmus: Fmus, steps=STEPS, schemes=SCHEMES, t_end: float = T_END):
    """(references, rows): the monolithic run of each law the schemes use, at the
    internal step, by law, and one row per run against its law's reference."""
    laws = {MASTER[s].law for s in schemes}
    references = {
        law: run_monolithic(fmus, INTERNAL_STEP, t_end, law) for law in LAWS if law in laws
    }
    rows = [
        evaluate(run_cosim(fmus, s, h, t_end), references[MASTER[s].law])
        for h in steps
        for s in schemes
    ]
    return references, rows


def step_independence(fmus: Fmus, references: dict[str, Series]) -> dict[str, float]:
    """By law: max |u(h = 1e-3) - u(h = INTERNAL_STEP)| of the monolithic run at the
    common times (m); the monolithic FMU must not depend on h."""
    coarse = {law: run_monolithic(fmus, 1e-3, T_END, law) for law in references}
    return {
        law: float(np.max(np.abs(coarse[law].tip_deflection - sample(ref, coarse[law].time))))
        for law, ref in references.items()
    }


def orders(rows: list[Row]) -> dict[str, float]:
    """Observed order of each scheme's error to T_FIRST_CYCLE over ASYMPTOTIC."""
    result = {}
    for scheme in SCHEMES:
        rs = [r for r in rows if r.scheme == scheme and r.h in ASYMPTOTIC]
        result[scheme] = observed_order([r.h for r in rs], [r.error_first_cycle for r in rs])
    return result


def summary_lines(rows: list[Row]) -> list[str]:
    """The observed orders, beam-first against friction-first Gauss-Seidel and the signed
    coupling against the exponential law's Gauss-Seidel at every h."""
    lines = [""]
    fitted = orders(rows)
    for scheme in SCHEMES:
        rs = [r for r in rows if r.scheme == scheme and r.h in ASYMPTOTIC]
        full = observed_order([r.h for r in rs], [r.error_full for r in rs])
        lines.append(
            f"observed order {scheme:17}: {fitted[scheme]:.3f} (error to {T_FIRST_CYCLE} s), "
            f"{full:.3f} (to {T_END} s), least squares over h = "
            f"{', '.join(f'{h:g}' for h in ASYMPTOTIC)} s"
        )
    for scheme in SCHEMES:
        rs = [r for r in rows if r.scheme == scheme]
        lines.append(
            f"  (over all h {STEPS[0]:g} .. {STEPS[-1]:g} s, {scheme}: "
            f"{observed_order([r.h for r in rs], [r.error_first_cycle for r in rs]):.3f})"
        )
    gs = {r.h: r for r in rows if r.scheme == BASELINE}
    ff = {r.h: r for r in rows if r.scheme == "GS friction-first"}
    same = max(abs(gs[h].error_full - ff[h].error_full) for h in gs)
    lines.append(f"GS beam-first vs friction-first: largest difference of the errors {same:.1e} m")
    signed = {r.h: r for r in rows if r.scheme == SIGNED}
    lines.append(
        f"\n{SIGNED} against the exponential law's {BASELINE} (error to {T_FIRST_CYCLE} s, "
        "each against its own embedded run):"
    )
    for h in STEPS:
        ratio = signed[h].error_first_cycle / gs[h].error_first_cycle
        lines.append(
            f"  h = {h:g} s: {1e3 * signed[h].error_first_cycle:.5f} mm against "
            f"{1e3 * gs[h].error_first_cycle:.5f} mm (ratio {ratio:.2f})"
        )
    return lines


def write_outputs(rows: list[Row], out: Path) -> list[Path]:
    """cosim_convergence.csv and cosim_convergence.png in `out`."""
    csv_path, png_path = out / "cosim_convergence.csv", out / "cosim_convergence.png"
    write_csv(csv_path, HEADERS, csv_rows(rows))
    plots.cosim_convergence(rows, orders(rows), STEPS, ASYMPTOTIC, T_FIRST_CYCLE, T_END, png_path)
    return [csv_path, png_path]
