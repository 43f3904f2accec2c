"""Plots of the command-line main job (the library of the plot_cli entry point): tip
deflection of the paper scene at every fidelity (paper Fig. 6a) from paper_*_*.csv and
the static mesh convergence (paper Fig. 1b) from mesh_convergence.csv."""

from __future__ import annotations

import csv
from pathlib import Path

from . import plots


def read_columns(path: Path) -> dict[str, list]:
    """A CSV file by column, numbers as floats (the clamp column as words)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {key: [float(r[key]) if key != "clamp" else r[key] for r in rows] for key in rows[0]}


def plot_deflection(out: Path) -> Path | None:
    """tip_deflection_cli.png from every paper_*_*.csv in `out` (None if there is none)."""
    runs = {
        path.stem.removeprefix("paper_").replace("_", ", "): read_columns(path)
        for path in sorted(out.glob("paper_*_*.csv"))
    }
    if not runs:
        return None
    target = out / "tip_deflection_cli.png"
    plots.cli_deflection(runs, target)
    return target


def plot_convergence(out: Path) -> Path | None:
    """mesh_convergence.png from `out`/mesh_convergence.csv (None if it is missing)."""
    path = out / "mesh_convergence.csv"
    if not path.exists():
        return None
    target = out / "mesh_convergence.png"
    plots.mesh_convergence(read_columns(path), target)
    return target


def plot_all(out: Path) -> list[Path]:
    """Every figure whose CSV file is in `out`."""
    return [t for t in (plot_deflection(out), plot_convergence(out)) if t is not None]
