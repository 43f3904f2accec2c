"""Speed against accuracy: the plot of `stickslip study` (see study). Reads
OUT_DIR/study.csv, draws pareto.png (RMS tip-deflection error against wall time, the
Pareto front joined) and prints the size of the front and, if auto_verification.csv is
there or in OUT_DIR/auto (where the main job's `study --verify-auto` writes it), how many
fidelity = auto verification cases hold.

Usage: python -m stickslip_checks.study_plot [OUT_DIR]   (or stickslip-study-plot;
default <repo>/out/study). Exits 1 if study.csv is missing or its pareto column marks
another front than the one computed here (the plot would contradict the CSV).
"""

from __future__ import annotations

import sys

from . import study
from .artifacts import DEFAULT_OUT
from .runner import parser


def main(argv: list[str] | None = None) -> int:
    out = parser("stickslip-study-plot", __doc__, out=DEFAULT_OUT / "study").parse_args(argv).out
    path = out / "study.csv"
    if not path.is_file():
        print(f"study_plot: no {path}: run `stickslip study --out {out}` first", file=sys.stderr)
        return 1
    rows = study.read_rows(path)
    front = study.pareto(rows)
    if not study.front_agrees(rows, front):
        print("study_plot: study.csv's pareto column disagrees with the front computed here",
              file=sys.stderr)
        return 1
    figure = out / "pareto.png"
    study.plot(rows, front, figure)
    print(f"{len(rows)} runs, {len(front)} on the Pareto front; plot {figure}")
    for verification in (out / "auto_verification.csv", out / "auto" / "auto_verification.csv"):
        if not verification.exists():
            continue
        cases = study.read_rows(verification)
        holding = sum(c["holds"] == "1" for c in cases)
        print(f"fidelity = auto: {holding} of {len(cases)} verification cases hold")
    return 0


if __name__ == "__main__":
    sys.exit(main())
