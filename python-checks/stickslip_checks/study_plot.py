"""Speed against accuracy: the plot of `stickslip study` (see study). Reads
OUT_DIR/study.csv, draws pareto.png (RMS tip-deflection error against wall time, the
Pareto front joined) and prints the size of the front and, if auto_verification.csv is
there or in OUT_DIR/auto (where the main job's `study --verify-auto` writes it), how many
fidelity = auto verification cases hold. A study of several friction laws (`--laws`)
gets fronts.png instead (each law's front in one axes) and, per law, its front's size and
its cheapest runs under 1e-5 m and 1e-6 m RMS.

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
    if len(study.laws(rows)) > 1:
        figure = out / "fronts.png"
        study.plot_fronts(rows, figure)
        print(f"{len(rows)} runs, {len(front)} on the Pareto fronts of "
              f"{len(study.laws(rows))} laws; plot {figure}")
        for law, law_front in study.fronts(rows).items():
            cheapest = {tol: study.cheapest_under(law_front, tol) for tol in (1e-5, 1e-6)}
            text = "; ".join(
                f"under {tol:g} m: " + (
                    f"{study.label(r)} ({float(r['wall_s']):.4f} s)" if r else "none")
                for tol, r in cheapest.items())
            print(f"  {law}: {len(law_front)} on its front; {text}")
    else:
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
