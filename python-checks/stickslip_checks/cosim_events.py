"""Co-simulation with FMI 3.0 events: StickSlipBeam + NeuralFriction coupled by a
Gauss-Seidel master that lets the beam end a step at a stick/slip switch (early return,
Event Mode), against the FMI 2.0 Gauss-Seidel master (see events). Prints the table of
errors and the switches; writes cosim_events.csv to OUT_DIR.

Usage: python -m stickslip_checks.cosim_events [OUT_DIR]   (or stickslip-cosim-events;
default <repo>/out). Exits 2 if the FMUs are missing; the checks are pytest's.
"""

from __future__ import annotations

import sys
import time

from . import events
from .artifacts import Fmus, fmu3_paths
from .runner import find_fmus, parser


def main(argv: list[str] | None = None) -> int:
    out = parser("stickslip-cosim-events", __doc__).parse_args(argv).out
    began = time.perf_counter()
    paths = find_fmus("cosim_events")
    if paths is None:
        return 2
    try:
        paths3 = fmu3_paths()
    except FileNotFoundError as error:
        print(f"cosim_events: {error}", file=sys.stderr)
        return 2
    fmus = Fmus(paths)
    try:
        _, runs, rows = events.run_study(fmus, paths3)
        mono = events.monolithic_switches(fmus)
    finally:
        fmus.close()
    print(events.table(rows))
    print()
    print("\n".join(events.switch_lines(runs, mono)))
    out.mkdir(parents=True, exist_ok=True)
    path = events.write_outputs(rows, out)
    print(f"\nwrote {path}\ntotal wall time {time.perf_counter() - began:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
