"""Convergence of the co-simulation StickSlipBeam.fmu + NeuralFriction.fmu in the
communication step h, Jacobi and Gauss-Seidel, exponential law and plain network (see
convergence). Prints the monolithic references, the table of errors, the observed
orders and the signed coupling against the exponential law's Gauss-Seidel; writes
cosim_convergence.csv and cosim_convergence.png to OUT_DIR.

Usage: python -m stickslip_checks.cosim_convergence [OUT_DIR]
       (or stickslip-cosim-convergence; default <repo>/out). Exits 2 if the FMUs are
       missing; the checks are pytest's.
"""

from __future__ import annotations

import sys
import time

from . import convergence as cc
from .artifacts import Fmus
from .runner import find_fmus, parser


def main(argv: list[str] | None = None) -> int:
    out = parser("stickslip-cosim-convergence", __doc__).parse_args(argv).out
    began = time.perf_counter()
    paths = find_fmus("cosim_convergence")
    if paths is None:
        return 2
    out.mkdir(parents=True, exist_ok=True)
    fmus = Fmus(paths)
    try:
        references, rows = cc.run_study(fmus)
        independence = cc.step_independence(fmus, references)
    finally:
        fmus.close()
    for law, reference in references.items():
        print(
            f"monolithic reference, {law}: h = {cc.INTERNAL_STEP:g} s ({reference.wall:.2f} s "
            f"wall); max |u(h = 1e-3) - u(h = 1e-4)| at common times = {independence[law]:.3e} m"
        )
    print()
    print(cc.table(rows))
    print("\n".join(cc.summary_lines(rows)))
    csv_path, png_path = cc.write_outputs(rows, out)
    print(f"\nwrote {csv_path}\nwrote {png_path}")
    print(f"total wall time {time.perf_counter() - began:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
