"""The paper scene under two transient algorithms, each with two friction laws (issue 26,
second part): this project's (`stickslip simulate --preset paper`) and the paper
authors' (`--preset paper-authors`: preload, damping beta = 1e-2 s only in slip,
finite-difference tip velocity, no friction force over the first slip step, the slip
force lagged one step; docs/paper-authors-scene.md), with the analytical law
(paper Eq. 6) and with the authors' own network (their fitrnet, converted to ONNX as
paper_authors.convert does), at every fidelity (modal, beam, plane-stress), 0 .. 1.2 s
as in the paper, through the command line (artifacts.find_binary: $STICKSLIP_BIN or the
release binary).

Prints a table, one row per run: algorithm, fidelity, law, breakaway, period, the
corridor of the tip deflection after breakaway, the number of major slips (all from the
command line's --summary-json, exact transition times), and on the network's row its
phase shift against the analytical law of the same algorithm and fidelity:
- the time shift of the last major-slip onset both runs have (network minus analytical;
  positive: the network's slip comes later), with that onset's index;
- the relative period difference (P_network - P_analytical) / P_analytical;
- the lag over the last analytical period (slip_metrics.phase_shift on the tip
  deflection, 1e-4 s samples), a second estimate from the whole curve.
Then, per law, the spread of each number over the three fidelities beside the
difference between the two algorithms: what a user's choice of scene changes against
what the choice of fidelity changes.

Writes OUT_DIR/paper_authors_algorithms.csv (the table) and
OUT_DIR/paper_authors_algorithms.png (tip deflection at plane stress: our algorithm
above, theirs below, both laws in each).

Usage: python -m stickslip_checks.paper_algorithms [OUT_DIR]   (or
stickslip-paper-algorithms; default <repo>/out). The checks are pytest's
(tests/test_paper_algorithms.py).
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import paper_authors, plots, slip_metrics
from .artifacts import find_binary
from .runner import parser, progress
from .tables import format_table, write_csv

ALGORITHMS = {"ours": "paper", "authors'": "paper-authors"}  # table name -> --preset
FIDELITIES = ("modal", "beam", "plane-stress")
TITLES = {"ours": "our transient algorithm", "authors'": "the paper authors' algorithm"}
ANALYTICAL, NETWORK = "analytical", "authors' network"
T_END = 1.2  # s, the paper's run
PLOT_FIDELITY = "plane-stress"  # the paper's mesh


@dataclass
class Run:
    """One `stickslip simulate`: its summary (the --summary-json dict) and the tip
    deflection (m) against time (s) of its CSV."""

    algorithm: str
    fidelity: str
    law: str
    summary: dict
    time: np.ndarray
    tip_deflection: np.ndarray

    @property
    def onsets(self) -> list[float]:
        return [s["onset"] for s in self.summary["major_slips"]]


def law_arguments(law: str, weights: Path) -> list[str]:
    """The command line's friction arguments of `law`."""
    if law == ANALYTICAL:
        return ["--friction", "analytical"]
    return ["--friction", "neural", "--weights", str(weights)]


def simulate(binary: Path, algorithm: str, fidelity: str, law: str, weights: Path,
             folder: Path) -> Run:
    """One run of the scene through the command line; its files go to `folder`."""
    stem = folder / f"{ALGORITHMS[algorithm]}_{fidelity}_{'network' if law == NETWORK else law}"
    command = [str(binary), "simulate", "--preset", ALGORITHMS[algorithm],
               "--fidelity", fidelity, "--t-end", str(T_END), *law_arguments(law, weights),
               "--out", f"{stem}.csv", "--summary-json", f"{stem}.json"]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed: {done.stderr.strip()}")
    summary = json.loads(Path(f"{stem}.json").read_text())
    columns = np.loadtxt(f"{stem}.csv", delimiter=",", skiprows=1, usecols=(0, 1))
    return Run(algorithm, fidelity, law, summary, columns[:, 0], columns[:, 1])


@dataclass
class Shift:
    """The phase of a run against a reference run (see shift())."""

    onset_index: int  # 0-based index of the last major slip both runs have
    onset_shift: float  # s: its onset in the run minus in the reference
    period_difference: float | None  # (P - P_ref) / P_ref; None without two slips each


def mean_period(onsets: Sequence[float]) -> float | None:
    """Mean spacing of the onsets (s), the command line's and slip_metrics' period."""
    if len(onsets) < 2:
        return None
    return (onsets[-1] - onsets[0]) / (len(onsets) - 1)


def shift(reference: Sequence[float], onsets: Sequence[float]) -> Shift | None:
    """The run's major-slip `onsets` against the `reference` run's (both in s): the time
    shift of the last onset both have (onset k of each, k = the shorter list's last) and
    the relative difference of the mean periods. None if either run has no major slip."""
    if not reference or not onsets:
        return None
    k = min(len(reference), len(onsets)) - 1
    p_ref, p = mean_period(reference), mean_period(onsets)
    difference = None if p_ref is None or p is None else (p - p_ref) / p_ref
    return Shift(k, onsets[k] - reference[k], difference)


def end_lag(run: Run, reference: Run) -> float | None:
    """slip_metrics.phase_shift of the run's tip deflection behind the reference's over
    the reference's last period (s); None without a reference period."""
    period = reference.summary.get("period")
    if period is None:
        return None
    return slip_metrics.phase_shift(run.time, run.tip_deflection, reference.tip_deflection,
                                    period)


def run_all(binary: Path, weights: Path, folder: Path) -> list[Run]:
    """Every algorithm x fidelity x law, in the table's order."""
    runs = []
    for algorithm in ALGORITHMS:
        for fidelity in FIDELITIES:
            progress(f"  {algorithm} algorithm, {fidelity} ...")
            for law in (ANALYTICAL, NETWORK):
                runs.append(simulate(binary, algorithm, fidelity, law, weights, folder))
    return runs


HEADERS = ["algorithm", "fidelity", "law", "breakaway (s)", "period (s)",
           "corridor min (mm)", "corridor max (mm)", "major slips",
           "last common onset", "onset shift (ms)", "period difference (%)",
           "lag over last period (ms)"]


def _reference(runs: list[Run], run: Run) -> Run:
    return next(r for r in runs if r.law == ANALYTICAL and r.algorithm == run.algorithm
                and r.fidelity == run.fidelity)


def rows(runs: list[Run]) -> list[list]:
    """The table's rows as numbers (None where a number does not apply)."""
    result = []
    for run in runs:
        s = run.summary
        corridor = s.get("corridor") or (None, None)
        row = [run.algorithm, run.fidelity, run.law, s.get("breakaway"), s.get("period"),
               None if corridor[0] is None else 1e3 * corridor[0],
               None if corridor[1] is None else 1e3 * corridor[1],
               len(s["major_slips"]), None, None, None, None]
        if run.law == NETWORK:
            reference = _reference(runs, run)
            phase = shift(reference.onsets, run.onsets)
            lag = end_lag(run, reference)
            if phase is not None:
                row[8] = phase.onset_index + 1
                row[9] = 1e3 * phase.onset_shift
                if phase.period_difference is not None:
                    row[10] = 100 * phase.period_difference
            row[11] = None if lag is None else 1e3 * lag
        result.append(row)
    return result


FORMATS = [None, None, None, ".4f", ".4f", ".3f", ".3f", "d", "d", "+.1f", "+.2f", "+.1f"]


def text_rows(numbers: list[list]) -> list[list[str]]:
    return [["-" if v is None else (v if f is None else format(v, f))
             for v, f in zip(row, FORMATS)] for row in numbers]


def spread_lines(numbers: list[list]) -> list[str]:
    """Per law: the largest difference of breakaway, period and corridor between the
    fidelities (within each algorithm) and between the two algorithms (at each
    fidelity)."""
    lines = []
    columns = {"breakaway": (3, 1e3, "ms"), "period": (4, 1e3, "ms"),
               "corridor min": (5, 1.0, "mm"), "corridor max": (6, 1.0, "mm")}
    for law in (ANALYTICAL, NETWORK):
        mine = [r for r in numbers if r[2] == law]
        parts = []
        for name, (column, scale, unit) in columns.items():
            fidelity = max(_spread([r[column] for r in mine if r[0] == a]) for a in ALGORITHMS)
            algorithm = max(_spread([r[column] for r in mine if r[1] == f]) for f in FIDELITIES)
            parts.append(f"{name} {scale * fidelity:.2f} / {scale * algorithm:.2f} {unit}")
        lines.append(f"  {law}: spread over fidelities / between algorithms: "
                     + "; ".join(parts))
    return lines


def _spread(values: list) -> float:
    """max - min of the numbers in `values` (NaN if one is missing: a run without slip)."""
    return float(np.ptp(values)) if None not in values else float("nan")


def plot(runs: list[Run], path: Path) -> None:
    """Tip deflection at PLOT_FIDELITY: one row per algorithm, both laws in each."""
    plt = plots._pyplot()
    fig, axes = plt.subplots(len(ALGORITHMS), 1, figsize=(10, 7), sharex=True, sharey=True)
    legend = {ANALYTICAL: "analytical law (paper Eq. 6)", NETWORK: "the authors' network"}
    styles = {ANALYTICAL: dict(color="black", lw=1.4), NETWORK: dict(color="tab:red", lw=1.0)}
    for axis, algorithm in zip(axes, ALGORITHMS):
        for law in (ANALYTICAL, NETWORK):
            run = next(r for r in runs if (r.algorithm, r.fidelity, r.law)
                       == (algorithm, PLOT_FIDELITY, law))
            period = run.summary.get("period")
            label = legend[law] + ("" if period is None else f", period {1e3 * period:.1f} ms")
            axis.plot(run.time, 1e3 * run.tip_deflection, label=label, **styles[law])
        axis.set_title(f"{TITLES[algorithm]} (--preset {ALGORITHMS[algorithm]})", fontsize=10)
        axis.set_ylabel("tip deflection (mm)")
        axis.grid(True, alpha=0.3)
        axis.legend(fontsize=9, loc="lower right")
    axes[-1].set_xlabel("time t (s)")
    fig.suptitle(f"Paper scene, {PLOT_FIDELITY} fidelity: the analytical law and the paper "
                 "authors' network under two transient algorithms", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    out = parser("stickslip-paper-algorithms", __doc__).parse_args(argv).out
    out.mkdir(parents=True, exist_ok=True)
    binary = find_binary()
    weights = paper_authors.convert(out / "paper_authors_network.onnx").resolve()
    print(f"== Paper scene, 0 .. {T_END:g} s, two algorithms x {len(FIDELITIES)} fidelities "
          f"x (analytical law, the authors' network {weights.name}), via {binary}")
    with tempfile.TemporaryDirectory() as folder:
        runs = run_all(binary, weights, Path(folder))
    numbers = rows(runs)
    print(format_table(HEADERS, text_rows(numbers), left=(0, 1, 2)))
    print("\n".join(spread_lines(numbers)))
    table = out / "paper_authors_algorithms.csv"
    write_csv(table, HEADERS, [["" if v is None else v for v in row] for row in numbers])
    figure = out / "paper_authors_algorithms.png"
    plot(runs, figure)
    print(f"wrote {table}, {figure}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
