"""Plots of the command-line main job: tip deflection of the paper scene at every
fidelity (paper Fig. 6a) and the static mesh convergence (paper Fig. 1b).

Usage: python -m stickslip_checks.plot_cli OUT_DIR   (or stickslip-plot-cli; reads the
CSV files the main job wrote there: paper_*_*.csv, mesh_convergence.csv)
"""

import csv
import sys
from pathlib import Path

from . import plots


def read_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {key: [float(r[key]) if key != "clamp" else r[key] for r in rows] for key in rows[0]}


def plot_deflection(out):
    runs = {
        path.stem.removeprefix("paper_").replace("_", ", "): read_columns(path)
        for path in sorted(out.glob("paper_*_*.csv"))
    }
    if not runs:
        return None
    target = out / "tip_deflection_cli.png"
    plots.cli_deflection(runs, target)
    return target


def plot_convergence(out):
    path = out / "mesh_convergence.csv"
    if not path.exists():
        return None
    target = out / "mesh_convergence.png"
    plots.mesh_convergence(read_columns(path), target)
    return target


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "out")
    for target in (plot_deflection(out), plot_convergence(out)):
        if target is not None:
            print(f"wrote {target}")


if __name__ == "__main__":
    main()
