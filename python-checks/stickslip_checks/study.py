"""Speed against accuracy: the plot of `stickslip study`.

Reads OUT_DIR/study.csv (every run of the grid) and draws the RMS tip-deflection error
against wall time, log-log, one marker per fidelity level and colour per integrator,
with the Pareto front (no run both faster and more accurate) joined by a line.
Also prints the front and, if present, the fidelity = auto verification table.

A study with a friction-law axis (`stickslip study --laws`, issue 24) has one front per
law, each law's errors against its own reference: study.csv's `law` column. A study.csv
written before that column existed is read as one law, "" (the scene's).

The library of the study_plot entry point.
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import TYPE_CHECKING

from . import plots

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr


def read_rows(path: Path) -> list[dict[str, str]]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def label(row: dict[str, str]) -> str:
    """The configuration of a study.csv row: the front's annotations, and the key that
    compares the front with the CSV's pareto column.

    This re-spells the Display of stickslip::study::Configuration because study.csv has
    no label column, only its fields (level, modes, beam_elements, element_size_m, dt_s,
    integrator, inference; level plane-stress-modal is the modal level on the mesh);
    the time step is written with :g where the Rust uses {:e}.
    The inference is empty unless the study had a friction-law axis (--inferences)."""
    text = f"{resolution(row)}, dt {float(row['dt_s']):g} s, {row['integrator']}"
    if row.get("inference"):
        text += f", {row['inference']} inference"
    return text


def resolution(row: dict[str, str]) -> str:
    """The structural model of a study.csv row, as label() spells it."""
    level = row["level"]
    if level == "modal":
        return f"modal {row['modes']} modes"
    if level == "plane-stress-modal":
        return f"modal {row['modes']} modes of plane stress {row['element_size_m']} m"
    if level == "beam":
        return f"beam {row['beam_elements']} el."
    return f"plane stress {row['element_size_m']} m"


def law(row: dict[str, str]) -> str:
    """The friction law of a study.csv row ("" in a file without the law column)."""
    return row.get("law", "")


def laws(rows: list[dict[str, str]]) -> list[str]:
    """The laws of the study, in the order study.csv lists them."""
    return list(dict.fromkeys(law(r) for r in rows))


def pareto(rows: list[dict[str, str]]) -> list[dict[str, str]]:
    """Rows no other row of the same law beats in both wall time and RMS error, cheapest
    first (recomputed here as a check of the CSV's own column). Each law's errors are
    against its own reference, so rows of different laws are never compared."""
    points = [(law(r), float(r["wall_s"]), float(r["err_rms_m"])) for r in rows]
    front = []
    for k, (lk, t, e) in enumerate(points):
        dominated = any(
            j != k and lj == lk and tj <= t and ej <= e and (tj < t or ej < e)
            for j, (lj, tj, ej) in enumerate(points)
        )
        if not dominated and math.isfinite(e):  # as the Rust marks it: NaN never on it
            front.append(rows[k])
    return sorted(front, key=lambda r: float(r["wall_s"]))


def fronts(rows: list[dict[str, str]]) -> dict[str, list[dict[str, str]]]:
    """Each law's front, cheapest first."""
    front = pareto(rows)
    return {name: [r for r in front if law(r) == name] for name in laws(rows)}


def front_agrees(rows: list[dict[str, str]], front: list[dict[str, str]]) -> bool:
    """Whether the CSV's pareto column marks exactly the front computed here."""
    marked = sorted((r for r in rows if r["pareto"] == "1"), key=lambda r: float(r["wall_s"]))
    key = lambda r: (law(r), label(r))  # noqa: E731
    return sorted(map(key, front)) == sorted(map(key, marked))


def cheapest_under(front: list[dict[str, str]], tolerance: float) -> dict[str, str] | None:
    """The cheapest run of a front (one law's) with an RMS error at most `tolerance` (m)."""
    under = [r for r in front if float(r["err_rms_m"]) <= tolerance]
    return min(under, key=lambda r: float(r["wall_s"]), default=None)


def plot(rows: list[dict[str, str]], front: list[dict[str, str]], path: Path) -> None:
    """pareto.png: every run, the front joined and labelled."""
    plots.pareto(rows, front, [label(r) for r in front], path)


def plot_fronts(rows: list[dict[str, str]], path: Path) -> None:
    """fronts.png: each law's front, in one log-log axes."""
    plots.law_fronts(fronts(rows), path)


GRID = ["law", "resolution", "dt_s", "integrator", "inference"]  # law and what label() spells


def to_frame(path: Path) -> pd.DataFrame:
    """study.csv as a DataFrame indexed by GRID (resolution: the structural model as
    label() spells it, e.g. "beam 10 el."; law and inference "" where the file has no
    such column)."""
    import pandas as pd

    rows = read_rows(path)
    table = pd.read_csv(path).drop(columns=["inference", "law"], errors="ignore")
    table["resolution"] = [resolution(r) for r in rows]
    table["inference"] = [r.get("inference", "") for r in rows]
    table["law"] = [law(r) for r in rows]
    return table.set_index(GRID)


def to_dataset(path: Path) -> xr.Dataset:
    """study.csv over its grid: the dimensions GRID, missing where the grid has no run."""
    return to_frame(path).to_xarray()
