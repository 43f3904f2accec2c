"""The coupled systems' SSP files in other masters: libcosim, Ecos, fmucontainer and
fmpy.ssp, each against our Jacobi and Gauss-Seidel masters (see other_masters), for
StickSlipCoupled (the plain network) and StickSlipCoupledMemory (the learned law with
memory; libcosim against our master counting time in nanoseconds as it does). Prints the
largest tip-deflection deviation of each; writes masters_coupled.csv and
masters_coupled_memory.csv to OUT_DIR.

Usage: python -m stickslip_checks.masters [OUT_DIR]   (or stickslip-masters; default
<repo>/out). Exits 2 if the FMUs are missing; the checks are pytest's
(tests/test_masters.py).
"""

from __future__ import annotations

import sys

from . import other_masters
from .artifacts import Fmus
from .runner import find_fmus, parser


def main(argv: list[str] | None = None) -> int:
    out = parser("stickslip-masters", __doc__).parse_args(argv).out
    paths = find_fmus("masters")
    if paths is None:
        return 2
    fmus = Fmus(paths)
    out.mkdir(parents=True, exist_ok=True)
    systems = {
        other_masters.COUPLED: "masters_coupled.csv",
        other_masters.COUPLED_MEMORY: "masters_coupled_memory.csv",
    }
    try:
        for system, csv_name in systems.items():
            rows = other_masters.compare_coupled(fmus, system)
            print(
                f"The coupled system ({system}.ssp), h = {other_masters.H} s, "
                f"0 to {other_masters.T_END} s:"
            )
            print("max |tip deflection - our master's| (m)")
            print(other_masters.table(rows))
            print(f"wrote {other_masters.write_outputs(rows, out, csv_name)}")
    finally:
        fmus.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
