"""The paper scene through the FMI 2.0 and the FMI 3.0 FMUs side by side (issue 15).

Both versions are the same library over the same variable tables, so at the same
settings every output must be equal bit for bit. This runs StickSlipBeam on the paper
scene (0 .. 1.2 s, 1 ms output, fmpy's simulate_fmu) at every structural model (modal,
beam, plane-stress) with the exponential law and the plain network, through <fmu root>/2.0/StickSlipBeam.fmu and
<fmu root>/3.0/StickSlipBeam.fmu, and NeuralFriction over a velocity sweep with both
laws, and prints one row per run with both versions' breakaway, transitions and largest
tip deflection next to each other and the largest difference between them. About 7 s
here (2 shared cores), most of it plane stress.

The library of the fmi_versions entry point; that every run is equal bit for bit is
tests/test_fmi3.py's check.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from fmpy import simulate_fmu

from . import slip_metrics
from .artifacts import BEAM, FRICTION, Model, fidelities
from .tables import format_table

if TYPE_CHECKING:
    import pandas as pd

T_END = 1.2  # s: the paper scene
DT = 1e-3  # s: communication step and output interval
LAWS = ("exponential", "neural")
BEAM_OUTPUTS = [
    "tip_deflection",
    "tip_velocity",
    "relative_velocity",
    "friction_force",
    "holding_force",
    "stick",
    "transitions",
]


@dataclass
class Row:
    """One run through both versions."""

    name: str
    breakaway: tuple[float | None, float | None]  # s, FMI 2.0 and 3.0
    transitions: tuple[int, int]
    peak: tuple[float, float]  # largest |tip deflection| or |friction force|
    peak_unit: str
    max_difference: float  # largest |3.0 - 2.0| over every output and sample
    identical: bool  # every output equal bit for bit
    wall: tuple[float, float]  # s


def _difference(r2, r3) -> tuple[float, bool]:
    worst, identical = 0.0, r2.dtype.names == r3.dtype.names
    for column in r2.dtype.names:
        a, b = np.asarray(r2[column], float), np.asarray(r3[column], float)
        identical = identical and np.array_equal(r2[column], r3[column])
        worst = max(worst, float(np.max(np.abs(a - b))))
    return worst, identical


def _both_versions(paths: dict, name: str, **settings) -> tuple[list, list[float]]:
    """fmpy's simulate_fmu of FMU `name` with `settings` through FMI 2.0, then 3.0: the
    results and the wall times (s)."""
    results, walls = [], []
    for version in ("2.0", "3.0"):
        began = time.perf_counter()
        results.append(simulate_fmu(str(paths[version][name]), **settings))
        walls.append(time.perf_counter() - began)
    return results, walls


def beam_row(paths: dict, fidelity: str, law: str, t_end: float = T_END) -> Row:
    """StickSlipBeam on the paper scene at `fidelity` with `law`, through both versions."""
    model = Model.read(paths["2.0"][BEAM])
    start = {
        "fidelity.level": model.code("fidelity.level", fidelity),
        "friction.law": model.code("friction.law", law),
    }
    results, walls = _both_versions(
        paths, BEAM, stop_time=t_end, output_interval=DT, start_values=start, output=BEAM_OUTPUTS
    )
    r2, r3 = results
    worst, identical = _difference(r2, r3)

    def breakaway(r):
        return slip_metrics.breakaway(np.asarray(r["time"]), np.asarray(r["stick"], bool))

    return Row(
        name=f"StickSlipBeam {fidelity} / {law}",
        breakaway=(breakaway(r2), breakaway(r3)),
        transitions=(int(r2["transitions"][-1]), int(r3["transitions"][-1])),
        peak=tuple(float(np.max(np.abs(r["tip_deflection"]))) * 1e3 for r in results),
        peak_unit="mm",
        max_difference=worst,
        identical=identical,
        wall=(walls[0], walls[1]),
    )


def friction_row(paths: dict, law: str) -> Row:
    """NeuralFriction with `law`, its velocity input swept over -0.35 .. 0.35 m/s (one
    value per 1 ms step) at 100 N, through both versions."""
    model = Model.read(paths["2.0"][FRICTION])
    t = np.arange(0, 701) * DT
    inputs = np.array(
        list(zip(t, np.linspace(-0.35, 0.35, t.size), np.full(t.size, 100.0))),
        dtype=[("time", float), ("sliding_velocity", float), ("normal_force", float)],
    )
    results, walls = _both_versions(
        paths, FRICTION, stop_time=float(t[-1]), output_interval=DT, input=inputs,
        start_values={"law": model.code("law", law)},
    )
    worst, identical = _difference(*results)
    return Row(
        name=f"NeuralFriction {law}, v swept",
        breakaway=(None, None),
        transitions=(0, 0),
        peak=tuple(float(np.max(np.abs(r["friction_force"]))) for r in results),
        peak_unit="N",
        max_difference=worst,
        identical=identical,
        wall=(walls[0], walls[1]),
    )


HEADERS = [
    "run", "breakaway 2.0 [s]", "3.0 [s]", "transitions 2.0", "3.0", "peak 2.0", "3.0",
    "max |3.0 - 2.0|", "bits", "wall 2.0 [s]", "3.0 [s]",
]


def table(rows: list[Row]) -> str:
    """One line per run, both versions side by side, with the footnote."""

    def seconds(v: float | None) -> str:
        return "-" if v is None else f"{v:.3f}"

    cells = [
        [
            r.name,
            seconds(r.breakaway[0]),
            seconds(r.breakaway[1]),
            str(r.transitions[0]) if r.peak_unit == "mm" else "-",
            str(r.transitions[1]) if r.peak_unit == "mm" else "-",
            f"{r.peak[0]:.4f} {r.peak_unit}",
            f"{r.peak[1]:.4f} {r.peak_unit}",
            f"{r.max_difference:.1e}",
            "equal" if r.identical else "DIFFER",
            f"{r.wall[0]:.2f}",
            f"{r.wall[1]:.2f}",
        ]
        for r in rows
    ]
    return format_table(HEADERS, cells) + (
        "\npeak: largest |tip deflection| (StickSlipBeam) or |friction_force| (NeuralFriction); "
        "max |3.0 - 2.0|: over every output at every sample"
    )


def to_frame(rows: list[Row]) -> pd.DataFrame:
    """One row per run, a column per version and quantity."""
    import pandas as pd

    return pd.DataFrame(
        {
            "run": r.name,
            "breakaway 2.0 [s]": r.breakaway[0], "breakaway 3.0 [s]": r.breakaway[1],
            "transitions 2.0": r.transitions[0], "transitions 3.0": r.transitions[1],
            "peak 2.0": r.peak[0], "peak 3.0": r.peak[1], "peak unit": r.peak_unit,
            "max |3.0 - 2.0|": r.max_difference, "identical": r.identical,
            "wall 2.0 [s]": r.wall[0], "wall 3.0 [s]": r.wall[1],
        }
        for r in rows
    )


def compare_all(paths: dict[str, dict[str, Path]], t_end: float = T_END) -> list[Row]:
    """Every structural model with both laws, then NeuralFriction with both laws."""
    structural = fidelities(Model.read(paths["2.0"][BEAM]))
    rows = [beam_row(paths, fidelity, law, t_end) for fidelity in structural for law in LAWS]
    return rows + [friction_row(paths, law) for law in LAWS]
