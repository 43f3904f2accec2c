"""The paper scene with the friction laws with state beside the paper's memoryless law
(issue 24): the exponential law, LuGre (its g(v) the exponential law) and rate-and-state,
each with its default parameters, at beam fidelity over 3 s (command line).

Writes OUT_DIR/memory_laws.png (tip deflection and friction force over time) and
OUT_DIR/memory_laws_<law>.csv, and prints breakaway, period and corridor of each run.
The laws and their defaults: docs/friction-with-memory.md.

Usage: python -m stickslip_checks.memory_laws [OUT_DIR]   (default <repo>/out).
"""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

from .artifacts import find_binary
from .runner import parser

LAWS = ("exponential", "lugre", "rate-and-state")
END_TIME = 3.0


def _series(path: Path) -> dict[str, list[float]]:
    columns: dict[str, list[float]] = {"t": [], "tip_deflection": [], "friction_force": []}
    with path.open() as f:
        for row in csv.DictReader(f):
            for name, values in columns.items():
                values.append(float(row[name]))
    return columns


def main(argv: list[str] | None = None) -> int:
    out = parser("stickslip-memory-laws", __doc__).parse_args(argv).out
    out.mkdir(parents=True, exist_ok=True)
    binary = str(find_binary())
    series = {}
    print("| law | breakaway (s) | period (s) | corridor after breakaway (mm) | slip phases |")
    print("| --- | --- | --- | --- | --- |")
    for law in LAWS:
        stem = out / f"memory_laws_{law}"
        subprocess.run(
            [binary, "simulate", "--fidelity", "beam", "--friction", law, "--t-end", str(END_TIME),
             "--out", f"{stem}.csv", "--summary-json", f"{stem}.json"],
            check=True, capture_output=True,
        )
        summary = json.loads(Path(f"{stem}.json").read_text())
        series[law] = _series(Path(f"{stem}.csv"))
        lo, hi = summary["corridor"]
        period = summary["period"]
        print(f"| {law} | {summary['breakaway']:.4f} | "
              f"{'-' if period is None else f'{period:.4f}'} | {1e3 * lo:.3f} - {1e3 * hi:.3f} | "
              f"{summary['slip_phases']} |")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_tip, ax_force) = plt.subplots(2, 1, figsize=(11, 7), sharex=True)
    styles = {"exponential": dict(color="black", lw=2.0, alpha=0.4),
              "lugre": dict(color="tab:blue", lw=1.0),
              "rate-and-state": dict(color="tab:red", lw=1.0, ls="--")}
    for law, s in series.items():
        ax_tip.plot(s["t"], [1e3 * u for u in s["tip_deflection"]], label=law, **styles[law])
        ax_force.plot(s["t"], s["friction_force"], label=law, **styles[law])
    ax_tip.set_ylabel("tip deflection (mm)")
    ax_tip.set_title("Paper scene, beam fidelity: memoryless law against the laws with state")
    ax_tip.legend(fontsize=8)
    ax_force.set_ylabel("friction force (N)")
    ax_force.set_xlabel("time (s)")
    fig.tight_layout()
    target = out / "memory_laws.png"
    fig.savefig(target, dpi=120)
    print(f"wrote {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
