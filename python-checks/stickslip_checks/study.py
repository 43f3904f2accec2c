"""Speed against accuracy: the plot of `stickslip study`.

Reads OUT_DIR/study.csv (every run of the grid) and draws the RMS tip-deflection error
against wall time, log-log, one marker per fidelity level and colour per integrator,
with the Pareto front (no run both faster and more accurate) joined by a line.
Also prints the front and, if present, the fidelity = auto verification table.

The library of the study_plot entry point.
"""

from __future__ import annotations

import csv
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


def pareto(rows: list[dict[str, str]]) -> list[dict[str, str]]:
    """Rows no other row beats in both wall time and RMS error, cheapest first
    (recomputed here as a check of the CSV's own column)."""
    points = [(float(r["wall_s"]), float(r["err_rms_m"])) for r in rows]
    front = []
    for k, (t, e) in enumerate(points):
        dominated = any(
            j != k and tj <= t and ej <= e and (tj < t or ej < e)
            for j, (tj, ej) in enumerate(points)
        )
        if not dominated:
            front.append(rows[k])
    return sorted(front, key=lambda r: float(r["wall_s"]))


def front_agrees(rows: list[dict[str, str]], front: list[dict[str, str]]) -> bool:
    """Whether the CSV's pareto column marks exactly the front computed here."""
    marked = sorted((r for r in rows if r["pareto"] == "1"), key=lambda r: float(r["wall_s"]))
    return [label(r) for r in front] == [label(r) for r in marked]


def plot(rows: list[dict[str, str]], front: list[dict[str, str]], path: Path) -> None:
    """pareto.png: every run, the front joined and labelled."""
    plots.pareto(rows, front, [label(r) for r in front], path)


GRID = ["resolution", "dt_s", "integrator", "inference"]  # what label() spells out


def to_frame(path: Path) -> pd.DataFrame:
    """study.csv as a DataFrame indexed by GRID (resolution: the structural model as
    label() spells it, e.g. "beam 10 el.")."""
    import pandas as pd

    rows = read_rows(path)
    table = pd.read_csv(path).drop(columns="inference", errors="ignore")
    table["resolution"] = [resolution(r) for r in rows]
    table["inference"] = [r.get("inference", "") for r in rows]
    return table.set_index(GRID)


def to_dataset(path: Path) -> xr.Dataset:
    """study.csv over its grid: the dimensions GRID, missing where the grid has no run."""
    return to_frame(path).to_xarray()
