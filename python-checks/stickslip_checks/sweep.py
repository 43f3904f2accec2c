"""Parameter sweeps of StickSlipBeam.fmu on Dask, and the stick-slip map: the command line.

What: runs the FMU for many parameter sets (belt speed, normal force, mu_s, damping or any
other parameter or input of its model description) and reduces every run to a few
numbers: breakaway time, stick -> slip transitions, peak-to-peak tip deflection and stick
fraction over the last part of the run, and the regime ("stick-slip" if the tip sticks
again after a slip within that window, else "steady sliding"). Without --grid it draws
the stick-slip map: peak-to-peak tip deflection against belt speed, from 0.005 to 10 m/s,
for the FMU's default damping and for 2 % Rayleigh damping (also started at rest). It
shows where stick-slip stops, and that this depends on damping and on the start: steady
sliding is linearly stable well below the speed at which the stick-slip cycle that
follows the paper's start disappears.

This entry point parses the options and prints; the sweep is sweep_study's (the runs:
sweep_engine, Dask, one FMU load per worker; the parameters: parameters; the per-run
metrics, the map's cases and where stick-slip stops: stick_slip_map). The FMUs are
found by artifacts (the 2.0/ folder of $STICKSLIP_FMU_DIR, else of
$CARGO_TARGET_DIR/fmu, else of <repo>/target/fmu).

Usage:
  python -m stickslip_checks.sweep (or stickslip-sweep)
                  [--scheduler tcp://host:port] [--workers N] [--set name=value ...]
                  [--grid name=start:stop:count[:log] | name=v1,v2,...] ...
                  [--case LABEL:name=value,name=value ...] [--fidelity LEVEL]
                  [--t-end S] [--step S] [--window F] [--out DIR] [--name BASENAME] [--list]

LEVEL is a structural model: an item of the FMU's fidelity.level other than auto (read
from its model description; --help lists them).

Several --grid options span their Cartesian product; --set applies to every run. Writes
<out>/<name>.csv (one row per run) and <out>/<name>.png (default out/stick_slip_map.*).
--workers defaults to the cores this process may use; 0 runs in this process without
Dask. Each finished run is reported on stderr. The scheduler and workers of a remote
cluster need this package installed, with numpy, fmpy and distributed.

Measured map (modal, 20 s, 102 runs, ~15-25 s on two cores): stick-slip stops between
1.02 and 1.28 m/s with 2 % Rayleigh damping and between 5.1 and 6.5 m/s with the FMU's
default damping, from the paper's quasi-static start. From rest with 2 % it stops
between 0.51 and 0.64 m/s, next to the mode-1 estimate (0.61 m/s) of where steady
sliding becomes stable: in between, both regimes are stable. Longer runs (40 s) and the
beam fidelity give the same regimes. With the default damping (mode 1 at 0.09 %) the
oscillation after breakaway decays with a time constant of ~30 s, so the peak-to-peak
values of its sliding points are still large at 20 s; the regime does not change.
"""


from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from . import sweep_study
from .artifacts import DEFAULT_OUT
from .parameters import Catalogue, SweepError
from .runner import progress
from .stick_slip_map import DEFAULT_WINDOW
from .sweep_engine import (
    DEFAULT_STEP,
    DEFAULT_T_END,
    beam_fmu,
    default_workers,
    run_serial,
    run_sweep,
)

DEFAULT_BASENAME = "stick_slip_map"
PROG = "stickslip-sweep"  # the console script; also `python -m stickslip_checks.sweep`


def _parser(fidelities: tuple[str, ...] | None) -> argparse.ArgumentParser:
    """The options; `fidelities` are the choices of --fidelity (None when the FMU is
    missing: --help still works, and a run then stops with the build hint)."""
    p = argparse.ArgumentParser(
        prog=PROG,
        description="Sweep StickSlipBeam.fmu over parameters on Dask; by default the "
        "stick-slip map "
        "(peak-to-peak tip deflection against belt speed).",
    )
    p.add_argument(
        "--scheduler", help="address of an existing Dask scheduler (default: a LocalCluster)"
    )
    p.add_argument(
        "--workers",
        type=int,
        default=default_workers(),
        help="worker processes of the LocalCluster (default: the cores this process may "
        "use, here %(default)s; 0 = in this process, no Dask)",
    )
    p.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a parameter or input for every run (repeatable)",
    )
    p.add_argument(
        "--grid",
        action="append",
        default=[],
        metavar="NAME=START:STOP:COUNT[:log]",
        help="a swept parameter (repeatable: Cartesian product); also NAME=V1,V2,...",
    )
    p.add_argument(
        "--case",
        action="append",
        default=[],
        metavar="LABEL:NAME=VALUE[,...]",
        help="a named set of values; every case runs the whole grid (repeatable)",
    )
    p.add_argument(
        "--fidelity", default="modal", choices=list(fidelities) if fidelities else None
    )
    p.add_argument(
        "--t-end",
        type=float,
        default=DEFAULT_T_END,
        help=f"end time, s (default {DEFAULT_T_END:g})",
    )
    p.add_argument(
        "--step",
        type=float,
        default=DEFAULT_STEP,
        help=f"communication step and sampling interval, s (default {DEFAULT_STEP:g})",
    )
    p.add_argument(
        "--window",
        type=float,
        default=DEFAULT_WINDOW,
        help="metrics over this last fraction of the run (default 1/3)",
    )
    p.add_argument(
        "--out", type=Path, default=DEFAULT_OUT, help="output folder (default <repo>/out)"
    )
    p.add_argument(
        "--name",
        default=DEFAULT_BASENAME,
        help=f"basename of the CSV and PNG (default {DEFAULT_BASENAME})",
    )
    p.add_argument("--list", action="store_true", help="print the settable parameters and exit")
    return p


def _progress(done: int, total: int, row: dict) -> None:
    progress(f"{PROG}: {done}/{total} runs done ({row['regime']}, {row['wall_s']:.2f} s)")


def main(argv: list[str] | None = None) -> int:
    try:
        catalogue = Catalogue(beam_fmu(None))
    except SweepError:
        catalogue = None  # reported below, after --help had its chance
    args = _parser(catalogue.fidelities if catalogue else None).parse_args(argv)
    try:
        fmu = beam_fmu(None)
        if args.list:
            print("\n".join(sweep_study.parameter_lines(catalogue)))
            return 0
        runs, swept, log_x, default_map = sweep_study.build_runs(
            catalogue, args.set, args.grid, args.case
        )
        param_sets = [p for _, p in runs]
        began = time.perf_counter()
        common = dict(
            fidelity=args.fidelity, t_end=args.t_end, step=args.step, window=args.window,
            fmu=fmu, progress=_progress,
        )
        if args.workers == 0 and args.scheduler is None:
            results = run_serial(param_sets, **common)
        else:
            results = run_sweep(
                param_sets, scheduler=args.scheduler, workers=args.workers, **common
            )
        wall = time.perf_counter() - began
    except SweepError as error:
        raise SystemExit(f"{PROG}: {error}") from None
    sweep = sweep_study.Sweep(
        catalogue, runs, swept, log_x, default_map, args.fidelity, args.t_end, args.window,
        results,
    )
    print(f"StickSlipBeam.fmu: {fmu}")
    print(
        f"{len(runs)} runs, {args.fidelity} fidelity, 0 .. {args.t_end:g} s at {args.step:g} s; "
        f"metrics over the last {args.window:.3g} of each run"
    )
    print(sweep_study.table(sweep))
    print()
    print("\n".join(sweep_study.summary_lines(sweep)))
    load_text = ", ".join(f"{w}: {n}" for w, n in sorted(results.loads.items()))
    print(f"FMU loads per worker: {load_text} ({len(runs)} runs)")
    args.out.mkdir(parents=True, exist_ok=True)
    csv_path, png_path = sweep_study.write_outputs(sweep, args.out, args.name)
    print(f"wrote {csv_path}")
    print(f"wrote {png_path}")
    print(f"wall time {wall:.1f} s for the runs ({time.perf_counter() - began:.1f} s in all)")
    # A failed run is an error of the sweep (its row says why), not a check.
    return 1 if sweep.failed else 0


if __name__ == "__main__":
    sys.exit(main())
