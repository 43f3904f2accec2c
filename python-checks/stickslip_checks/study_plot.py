"""Speed against accuracy: the plot of `stickslip study`.

Reads OUT_DIR/study.csv (every run of the grid) and draws the RMS tip-deflection error
against wall time, log-log, one marker per fidelity level and colour per integrator,
with the Pareto front (no run both faster and more accurate) joined by a line.
Also prints the front and, if present, the fidelity = auto verification table.

Usage: python -m stickslip_checks.study_plot OUT_DIR   (or stickslip-study-plot;
default out/study)
"""

import csv
import sys
from pathlib import Path

from . import plots


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def label(row):
    level = row["level"]
    if level == "modal":
        resolution = f"modal {row['modes']} modes"
    elif level == "beam":
        resolution = f"beam {row['beam_elements']} el."
    else:
        resolution = f"plane stress {row['element_size_m']} m"
    return f"{resolution}, dt {float(row['dt_s']):g} s, {row['integrator']}"


def pareto(rows):
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


def main():
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("out/study")
    rows = read_rows(out / "study.csv")
    front = pareto(rows)
    marked = sorted((r for r in rows if r["pareto"] == "1"), key=lambda r: float(r["wall_s"]))
    if [label(r) for r in front] != [label(r) for r in marked]:
        raise SystemExit("study.csv's pareto column disagrees with the front computed here")
    path = out / "pareto.png"
    plots.pareto(rows, front, [label(r) for r in front], path)
    print(f"{len(rows)} runs, {len(front)} on the Pareto front; plot {path}")
    verification = out / "auto_verification.csv"
    if verification.exists():
        cases = read_rows(verification)
        holding = sum(c["holds"] == "1" for c in cases)
        print(f"fidelity = auto: {holding} of {len(cases)} verification cases hold")


if __name__ == "__main__":
    main()
