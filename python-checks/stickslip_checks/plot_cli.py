"""Plots of the command-line main job: tip deflection of the paper scene at every
fidelity (paper Fig. 6a) and the static mesh convergence (paper Fig. 1b).

Usage: python -m stickslip_checks.plot_cli [OUT_DIR]   (or stickslip-plot-cli; default
<repo>/out). Reads the CSV files the main job wrote there (paper_*_*.csv,
mesh_convergence.csv) and plots those it finds; exits with status 1 if it finds none.
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

from . import plots
from .runner import out_dir


def read_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {key: [float(r[key]) if key != "clamp" else r[key] for r in rows] for key in rows[0]}


def plot_deflection(out: Path) -> Path | None:
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
    path = out / "mesh_convergence.csv"
    if not path.exists():
        return None
    target = out / "mesh_convergence.png"
    plots.mesh_convergence(read_columns(path), target)
    return target


def main(argv: list[str] | None = None) -> int:
    out = out_dir(argv, create=False)  # only reads what the main job wrote
    written = [t for t in (plot_deflection(out), plot_convergence(out)) if t is not None]
    for target in written:
        print(f"wrote {target}")
    if not written:
        print(f"plot_cli: no paper_*_*.csv or mesh_convergence.csv in {out}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
