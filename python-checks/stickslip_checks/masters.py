"""The coupled systems' SSP files in other masters: libcosim, Ecos, fmucontainer and
fmpy.ssp, each against our Jacobi and Gauss-Seidel masters (see other_masters), for
StickSlipCoupled (the plain network), StickSlipCoupledMemory (the learned law with
memory), StickSlipCoupledRateState and StickSlipCoupledLuGre (NeuralFriction with
law = rate-and-state, lugre); libcosim against our master counting time in nanoseconds
as it does. Prints the largest deviation of the tip deflection, and of the law's state
output where the system has one; writes masters_coupled.csv,
masters_coupled_memory.csv, masters_coupled_rate_state.csv and
masters_coupled_lugre.csv to OUT_DIR.

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
        other_masters.COUPLED_RATE_STATE: "masters_coupled_rate_state.csv",
        other_masters.COUPLED_LUGRE: "masters_coupled_lugre.csv",
    }
    try:
        for system, csv_name in systems.items():
            rows = other_masters.compare_coupled(fmus, system)
            print(
                f"The coupled system ({system}.ssp), h = {other_masters.H} s, "
                f"0 to {other_masters.T_END} s:"
            )
            print("max |output - our master's| (m; state_theta in s)")
            print(other_masters.table(rows))
            print(f"wrote {other_masters.write_outputs(rows, out, csv_name)}")
    finally:
        fmus.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
