"""The paper scene through the FMI 2.0 and the FMI 3.0 FMUs side by side (see versions):
StickSlipBeam at every structural model with the exponential law and the plain network,
NeuralFriction over a velocity sweep with both laws. Prints one row per run with both
versions' breakaway, transitions and peak, and the largest difference between them.

Usage: python -m stickslip_checks.fmi_versions   (or stickslip-fmi-versions). Exits 2 if
the FMUs are missing; that both versions agree bit for bit is pytest's check
(tests/test_fmi3.py).
"""

from __future__ import annotations

import sys
import time

from . import versions
from .artifacts import fmu3_paths, fmu_paths
from .runner import parser


def main(argv: list[str] | None = None) -> int:
    parser("stickslip-fmi-versions", __doc__, out=None).parse_args(argv)
    began = time.perf_counter()
    try:
        paths = {"2.0": fmu_paths(), "3.0": fmu3_paths()}
    except FileNotFoundError as error:
        print(f"fmi_versions: {error}", file=sys.stderr)
        return 2
    print(f"FMI 2.0: {', '.join(str(p) for p in paths['2.0'].values())}")
    print(f"FMI 3.0: {', '.join(str(p) for p in paths['3.0'].values())}")
    print(versions.table(versions.compare_all(paths)))
    print(f"total wall time {time.perf_counter() - began:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
