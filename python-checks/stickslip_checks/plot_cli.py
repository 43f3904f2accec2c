"""Plots of the command-line main job (see cli_plots): the tip deflection of the paper
scene at every fidelity (paper Fig. 6a) and the static mesh convergence (paper Fig. 1b),
from the CSV files the main job wrote to OUT_DIR (paper_*_*.csv, mesh_convergence.csv).

Usage: python -m stickslip_checks.plot_cli [OUT_DIR]   (or stickslip-plot-cli; default
<repo>/out). Exits 1 if it finds none of those files.
"""

from __future__ import annotations

import sys

from .cli_plots import plot_all
from .runner import parser


def main(argv: list[str] | None = None) -> int:
    out = parser("stickslip-plot-cli", __doc__).parse_args(argv).out
    written = plot_all(out)
    for target in written:
        print(f"wrote {target}")
    if not written:
        print(f"plot_cli: no paper_*_*.csv or mesh_convergence.csv in {out}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
