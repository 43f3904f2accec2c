"""Plots of the command-line main job: tip deflection of the paper scene at every
fidelity (paper Fig. 6a) and the static mesh convergence (paper Fig. 1b).

Usage: python plot_cli.py OUT_DIR   (reads the CSV files the main job wrote there)
"""

import csv
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_columns(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {key: [float(r[key]) if key != "clamp" else r[key] for r in rows] for key in rows[0]}


def plot_deflection(out):
    fig, (ax_u, ax_f) = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    found = False
    for path in sorted(out.glob("paper_*_*.csv")):
        label = path.stem.removeprefix("paper_").replace("_", ", ")
        data = read_columns(path)
        ax_u.plot(data["t"], [1e3 * u for u in data["tip_deflection"]], label=label, lw=1)
        ax_f.plot(data["t"], data["friction_force"], label=label, lw=0.8)
        found = True
    if not found:
        return None
    ax_u.set_ylabel("tip deflection (mm)")
    ax_u.set_title("Paper scene: tip deflection (cf. paper Fig. 6a)")
    ax_u.grid(True, alpha=0.3)
    ax_u.legend(fontsize=8)
    ax_f.axhline(50.0, color="grey", ls="--", lw=0.8)
    ax_f.text(0.01, 51.0, "static limit mu_s F_n = 50 N", fontsize=8, color="grey")
    ax_f.set_xlabel("time t (s)")
    ax_f.set_ylabel("force of the belt on the tip (N)")
    ax_f.set_title("Holding force (stick) and kinetic friction force (slip)")
    ax_f.grid(True, alpha=0.3)
    fig.tight_layout()
    target = out / "tip_deflection_cli.png"
    fig.savefig(target, dpi=120)
    plt.close(fig)
    return target


def plot_convergence(out):
    path = out / "mesh_convergence.csv"
    if not path.exists():
        return None
    data = read_columns(path)
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for clamp in ("neutral-axis", "full"):
        idx = [i for i, c in enumerate(data["clamp"]) if c == clamp]
        nodes = [data["nodes"][i] for i in idx]
        err = [100 * abs(data["error_euler_bernoulli"][i]) for i in idx]
        ax.loglog(nodes, err, "o-", label=f"Q8, {clamp} clamp")
    ax.axhline(0.04, color="grey", ls="--", lw=0.8)
    ax.text(70, 0.045, "paper: 0.04 % at element size 0.02 m", fontsize=8, color="grey")
    ax.set_xlabel("number of nodes")
    ax.set_ylabel("|tip deflection error| vs Euler-Bernoulli (%)")
    ax.set_title("Static mesh convergence, P = 50 N (cf. paper Fig. 1b)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    target = out / "mesh_convergence.png"
    fig.savefig(target, dpi=120)
    plt.close(fig)
    return target


def main():
    out = Path(sys.argv[1] if len(sys.argv) > 1 else "out")
    for target in (plot_deflection(out), plot_convergence(out)):
        if target is not None:
            print(f"wrote {target}")


if __name__ == "__main__":
    main()
