"""The learned friction law with memory (issue 24): its velocity-step response beside
the rate-and-state law that generated its training records, and the paper scene run
with the shipped learned law beside that law (command line).

Runs `stickslip train-memory` (synthetic tribometer records, 0.2 N noise) with
--step-response, and `stickslip simulate --fidelity modal` with `--friction
rate-and-state` and with `--friction neural --weights weights/rate-and-state-learned.json`;
writes OUT_DIR/learned_memory.png (two panels) and prints the period and corridor of both
runs. The numbers it should show are in docs/learned-friction-with-memory.md.

Usage: python -m stickslip_checks.learned_memory [OUT_DIR]   (default <repo>/out).
"""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

from .artifacts import REPO, find_binary
from .runner import parser


def _step_curves(path: Path) -> dict[str, list[tuple[float, float, float]]]:
    curves: dict[str, list[tuple[float, float, float]]] = {}
    with path.open() as f:
        for row in csv.DictReader(f):
            curves.setdefault(row["step"], []).append(
                (float(row["slip[m]"]), float(row["mu_learned"]), float(row["mu_generating"]))
            )
    return curves


def _tip(path: Path) -> tuple[list[float], list[float]]:
    t, x = [], []
    with path.open() as f:
        for row in csv.DictReader(f):
            t.append(float(row["t"]))
            x.append(float(row["tip_deflection"]))
    return t, x


def main(argv: list[str] | None = None) -> int:
    out = parser("stickslip-learned-memory", __doc__).parse_args(argv).out
    out.mkdir(parents=True, exist_ok=True)
    binary = str(find_binary())
    step_csv = out / "learned_step_response.csv"
    subprocess.run(
        [binary, "train-memory", "--quiet", "--out", str(out / "rate-and-state-learned.json"),
         "--step-response", str(step_csv)],
        check=True,
    )
    runs = {
        "rate-and-state (generating)": ["--friction", "rate-and-state"],
        "learned (weights/rate-and-state-learned.json)": [
            "--friction", "neural", "--weights", str(REPO / "weights" / "rate-and-state-learned.json")],
    }
    summaries = {}
    tips = {}
    for k, (label, args) in enumerate(runs.items()):
        stem = out / f"learned_memory_scene_{k}"
        subprocess.run(
            [binary, "simulate", "--fidelity", "modal", *args, "--out", f"{stem}.csv",
             "--summary-json", f"{stem}.json"],
            check=True, capture_output=True,
        )
        summaries[label] = json.loads(Path(f"{stem}.json").read_text())
        tips[label] = _tip(Path(f"{stem}.csv"))
        s = summaries[label]
        lo, hi = s["corridor"]
        print(f"{label}: breakaway {s['breakaway']:.4f} s, period {s['period']:.4f} s, "
              f"corridor {1e3 * lo:.3f} - {1e3 * hi:.3f} mm")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_step, ax_scene) = plt.subplots(1, 2, figsize=(13, 4.8))
    for (step, rows), color in zip(_step_curves(step_csv).items(), ("tab:blue", "tab:red")):
        slip = [1e6 * r[0] for r in rows]
        ax_step.plot(slip, [r[2] for r in rows], color="black", lw=2.2, alpha=0.35)
        ax_step.plot(slip, [r[1] for r in rows], color=color, lw=1.1, ls="--", label=f"learned, {step}")
    ax_step.plot([], [], color="black", lw=2.2, alpha=0.35, label="generating rate-and-state law")
    ax_step.set_xlabel("slip after the velocity step (um)")
    ax_step.set_ylabel("friction coefficient mu = F / F_n")
    ax_step.set_title("Velocity steps at F_n = 100 N")
    ax_step.legend(fontsize=8)
    for (label, (t, x)), style in zip(tips.items(), (dict(color="black", lw=2.2, alpha=0.35),
                                                      dict(color="tab:green", lw=1.0, ls="--"))):
        ax_scene.plot(t, [1e3 * v for v in x], label=label, **style)
    ax_scene.set_xlabel("time (s)")
    ax_scene.set_ylabel("tip deflection (mm)")
    ax_scene.set_title("Paper scene, modal fidelity")
    ax_scene.legend(fontsize=8)
    fig.tight_layout()
    target = out / "learned_memory.png"
    fig.savefig(target, dpi=120)
    print(f"wrote {target}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
