"""Friction reversals in the paper scene (issue 37): for each fidelity, friction law,
integrator and time step, the samples whose friction force opposes the converged run's
at the same time, and the largest tip deviation from the converged run (command line).

The converged run of a fidelity and law is generalised-alpha at the reference step
(default 2e-6 s, 50 steps per paper step). A sample counts as a reversal where both
forces exceed 1 N in magnitude and have opposite signs (1 N: far above the slip solve's
tolerance, far below the 20 to 50 N the paper scene slides at, so that a force passing
through zero at a legitimate reversal is not counted for a sample of timing offset
unless the two runs disagree by more than that). Beside it, as issue 37 counted them,
the samples after breakaway with a force below -1 N. The tip deviation is the largest
|u_tip - u_tip,ref| at the run's samples, over the paper's horizon (1.2 s) and the
whole run.

Writes OUT_DIR/reversals/<run>.csv (references kept in --reference-dir, reused when
present) and prints two markdown tables. The mechanism behind the reversals:
`cargo run --release -p stickslip --example reversals`.

Usage: python -m stickslip_checks.reversals [OUT_DIR] [--fidelities ...] [--laws ...]
[--integrators ...] [--dts ...] [--reference-dt S] [--reference-dir DIR] [--end S]
"""

from __future__ import annotations

import csv
import json
import subprocess
import sys
from pathlib import Path

from .artifacts import REPO, find_binary
from .runner import parser

FIDELITIES = ("modal", "beam", "plane-stress")
LAWS = {
    "exponential": ["--friction", "exponential"],
    "neural-plain": ["--friction", "neural", "--weights", str(REPO / "weights/paper-plain.json")],
    "neural-signed": ["--friction", "neural", "--weights", str(REPO / "weights/paper-signed.json")],
    "lugre": ["--friction", "lugre"],
    "rate-and-state": ["--friction", "rate-and-state"],
}
INTEGRATORS = ("generalized-alpha", "moreau-jean")
DTS = (1e-4, 5e-5, 2e-5)
# Forces below this magnitude (N) have no sign worth comparing (see the docstring).
FORCE_FLOOR = 1.0
# The paper's horizon (s).
HORIZON = 1.2
# The reference is written on this grid (s), a divisor of every step compared with it.
REFERENCE_GRID = 1e-5


def _simulate(binary: str, stem: Path, fidelity: str, law: str, integrator: str, dt: float,
              end: float, every: int) -> tuple[list[tuple[float, float, float]], float]:
    """(t, tip deflection, friction force) per sample, and the breakaway time (s)."""
    if not Path(f"{stem}.csv").exists() or not Path(f"{stem}.json").exists():
        subprocess.run(
            [binary, "simulate", "--fidelity", fidelity, *LAWS[law], "--integrator", integrator,
             "--dt", repr(dt), "--t-end", repr(end), "--every", str(every),
             "--out", f"{stem}.csv", "--summary-json", f"{stem}.json"],
            check=True, capture_output=True,
        )
    with open(f"{stem}.csv") as f:
        rows = [(float(r["t"]), float(r["tip_deflection"]), float(r["friction_force"]))
                for r in csv.DictReader(f)]
    return rows, json.loads(Path(f"{stem}.json").read_text())["breakaway"]


def compare(run: list[tuple[float, float, float]], breakaway: float,
            reference: list[tuple[float, float, float]]) -> dict:
    """Reversals against the reference (sampled on REFERENCE_GRID) and tip deviations."""
    reversals, negative, first = 0, 0, []
    horizon_dev, whole_dev = 0.0, 0.0
    for t, u, force in run:
        k = round(t / REFERENCE_GRID)
        if k >= len(reference):
            break
        _, u_ref, f_ref = reference[k]
        if abs(force) > FORCE_FLOOR and abs(f_ref) > FORCE_FLOOR and force * f_ref < 0.0:
            reversals += 1
            if len(first) < 4:
                first.append(t)
        if t > breakaway and force < -FORCE_FLOOR:
            negative += 1
        deviation = abs(u - u_ref)
        whole_dev = max(whole_dev, deviation)
        if t <= HORIZON + 1e-12:
            horizon_dev = max(horizon_dev, deviation)
    return dict(reversals=reversals, negative=negative, first=first,
                horizon=horizon_dev, whole=whole_dev)


def main(argv: list[str] | None = None) -> int:
    p = parser("stickslip-reversals", __doc__)
    p.add_argument("--fidelities", nargs="+", choices=FIDELITIES, default=list(FIDELITIES))
    p.add_argument("--laws", nargs="+", choices=list(LAWS), default=list(LAWS))
    p.add_argument("--integrators", nargs="+", choices=INTEGRATORS, default=list(INTEGRATORS))
    p.add_argument("--dts", nargs="+", type=float, default=list(DTS))
    p.add_argument("--reference-dt", type=float, default=2e-6)
    p.add_argument("--reference-dir", type=Path, default=None,
                   help="where the converged runs are kept and reused (default OUT_DIR/reversals)")
    p.add_argument("--end", type=float, default=3.0, help="end time (s), default 3")
    args = p.parse_args(argv)
    runs = args.out / "reversals"
    runs.mkdir(parents=True, exist_ok=True)
    references = args.reference_dir or runs
    references.mkdir(parents=True, exist_ok=True)
    binary = str(find_binary())
    every_ref = round(REFERENCE_GRID / args.reference_dt)
    print("| fidelity | law | integrator | dt (s) | reversals against the converged run | "
          "first (s) | samples F < -1 N after breakaway | tip deviation 1.2 s (um) | "
          "tip deviation whole run (um) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for fidelity in args.fidelities:
        for law in args.laws:
            ref_stem = references / f"{fidelity}_{law}_reference_{args.reference_dt:g}_{args.end:g}"
            reference, _ = _simulate(binary, ref_stem, fidelity, law, "generalized-alpha",
                                     args.reference_dt, args.end, every_ref)
            for integrator in args.integrators:
                for dt in args.dts:
                    stem = runs / f"{fidelity}_{law}_{integrator}_{dt:g}_{args.end:g}"
                    run, breakaway = _simulate(binary, stem, fidelity, law, integrator, dt,
                                               args.end, 1)
                    c = compare(run, breakaway, reference)
                    first = ", ".join(f"{t:.4f}" for t in c["first"])
                    print(f"| {fidelity} | {law} | {integrator} | {dt:g} | {c['reversals']} | "
                          f"{first} | {c['negative']} | {1e6 * c['horizon']:.1f} | "
                          f"{1e6 * c['whole']:.1f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
