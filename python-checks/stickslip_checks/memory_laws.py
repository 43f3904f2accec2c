"""The paper scene with the friction laws with state beside the paper's memoryless law
(issue 24): the exponential law, LuGre (its g(v) the exponential law) and rate-and-state,
each with its default parameters, at beam fidelity over 3 s (command line).

Writes OUT_DIR/memory_laws.png (tip deflection, friction force and the laws' state over
time: LuGre's bristle deflection z, rate-and-state's theta) and
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
# The state column `stickslip simulate` writes for a law with state (its variable's name).
STATE_COLUMNS = ("bristle_deflection", "state_theta")


def _series(path: Path) -> dict[str, list[float]]:
    """The columns the plot uses; a state column only where the run's law has one."""
    with path.open() as f:
        reader = csv.DictReader(f)
        names = ["t", "tip_deflection", "friction_force"]
        names += [c for c in STATE_COLUMNS if c in (reader.fieldnames or [])]
        columns: dict[str, list[float]] = {name: [] for name in names}
        for row in reader:
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

    fig, (ax_tip, ax_force, ax_z) = plt.subplots(3, 1, figsize=(11, 10), sharex=True)
    styles = {"exponential": dict(color="black", lw=2.0, alpha=0.4),
              "lugre": dict(color="tab:blue", lw=1.0),
              "rate-and-state": dict(color="tab:red", lw=1.0, ls="--")}
    s_lugre, s_rs = series["lugre"], series["rate-and-state"]
    for law, s in series.items():
        ax_tip.plot(s["t"], [1e3 * u for u in s["tip_deflection"]], label=law, **styles[law])
        ax_force.plot(s["t"], s["friction_force"], label=law, **styles[law])
    ax_tip.set_ylabel("tip deflection (mm)")
    ax_tip.set_title("Paper scene, beam fidelity: memoryless law against the laws with state")
    ax_tip.legend(fontsize=8)
    ax_force.set_ylabel("friction force (N)")
    # The state: z (um) on the left, theta (s, logarithmic: it heals ~t in stick and falls
    # to D_c / V in slip) on the right.
    ax_z.plot(s_lugre["t"], [1e6 * z for z in s_lugre["bristle_deflection"]],
              label="lugre: bristle deflection z", **styles["lugre"])
    ax_z.set_ylabel("LuGre z (um)", color=styles["lugre"]["color"])
    ax_theta = ax_z.twinx()
    ax_theta.semilogy(s_rs["t"], s_rs["state_theta"], label="rate-and-state: theta",
                      **styles["rate-and-state"])
    ax_theta.set_ylabel("rate-and-state theta (s)", color=styles["rate-and-state"]["color"])
    ax_z.set_xlabel("time (s)")
    fig.tight_layout()
    target = out / "memory_laws.png"
    fig.savefig(target, dpi=120)
    print(f"wrote {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
