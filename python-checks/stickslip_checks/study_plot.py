"""Speed against accuracy: the plot of `stickslip study`.

Reads OUT_DIR/study.csv (every run of the grid) and draws the RMS tip-deflection error
against wall time, log-log, one marker per fidelity level and colour per integrator,
with the Pareto front (no run both faster and more accurate) joined by a line.
Also prints the front and, if present, the fidelity = auto verification table.

Usage: python -m stickslip_checks.study_plot [OUT_DIR]   (or stickslip-study-plot;
default <repo>/out/study). Exits with status 1 if study.csv is missing or its pareto
column disagrees with the front computed here.
"""

from __future__ import annotations

import csv
import sys

from . import plots
from .artifacts import DEFAULT_OUT
from .runner import out_dir


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def label(row):
    """The configuration of a study.csv row: the front's annotations, and the key that
    compares the front with the CSV's pareto column.

    This re-spells the Display of stickslip::study::Configuration because study.csv has
    no label column, only its fields (level, modes, beam_elements, element_size_m, dt_s,
    integrator, inference; level plane-stress-modal is the modal level on the mesh);
    the time step is written with :g where the Rust uses {:e}.
    The inference is empty unless the study had a friction-law axis (--inferences)."""
    level = row["level"]
    if level == "modal":
        resolution = f"modal {row['modes']} modes"
    elif level == "plane-stress-modal":
        resolution = f"modal {row['modes']} modes of plane stress {row['element_size_m']} m"
    elif level == "beam":
        resolution = f"beam {row['beam_elements']} el."
    else:
        resolution = f"plane stress {row['element_size_m']} m"
    text = f"{resolution}, dt {float(row['dt_s']):g} s, {row['integrator']}"
    if row.get("inference"):
        text += f", {row['inference']} inference"
    return text


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


def main(argv: list[str] | None = None) -> int:
    out = out_dir(argv, create=False, default=DEFAULT_OUT / "study")
    study = out / "study.csv"
    if not study.is_file():
        print(f"study_plot: no {study}: run `stickslip study --out {out}` first", file=sys.stderr)
        return 1
    rows = read_rows(study)
    front = pareto(rows)
    marked = sorted((r for r in rows if r["pareto"] == "1"), key=lambda r: float(r["wall_s"]))
    if [label(r) for r in front] != [label(r) for r in marked]:
        print("study_plot: study.csv's pareto column disagrees with the front computed here",
              file=sys.stderr)
        return 1
    path = out / "pareto.png"
    plots.pareto(rows, front, [label(r) for r in front], path)
    print(f"{len(rows)} runs, {len(front)} on the Pareto front; plot {path}")
    verification = out / "auto_verification.csv"
    if verification.exists():
        cases = read_rows(verification)
        holding = sum(c["holds"] == "1" for c in cases)
        print(f"fidelity = auto: {holding} of {len(cases)} verification cases hold")
    return 0


if __name__ == "__main__":
    sys.exit(main())
