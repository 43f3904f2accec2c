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

The runs: sweep_engine (Dask, one FMU load per worker); the parameters: parameters; the
per-run metrics, the map's cases and where stick-slip stops: stick_slip_map; the figure:
plots.stick_slip_map. The FMUs are found by artifacts (the 2.0/ folder of
$STICKSLIP_FMU_DIR, else of $CARGO_TARGET_DIR/fmu, else of <repo>/target/fmu).

Usage:
  python -m stickslip_checks.sweep (or stickslip-sweep)
                  [--scheduler tcp://host:port] [--workers 2] [--set name=value ...]
                  [--grid name=start:stop:count[:log] | name=v1,v2,...] ...
                  [--case LABEL:name=value,name=value ...] [--fidelity LEVEL]
                  [--t-end S] [--step S] [--window F] [--out DIR] [--name BASENAME] [--list]

LEVEL is a structural model: an item of the FMU's fidelity.level other than auto (read
from its model description; --help lists them).

Several --grid options span their Cartesian product; --set applies to every run. Writes
<out>/<name>.csv (one row per run) and <out>/<name>.png (default out/stick_slip_map.*).
--workers 0 runs in this process without Dask. The scheduler and workers of a remote
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
import csv
import sys
import time
from itertools import product
from pathlib import Path

from . import plots
from .artifacts import DEFAULT_OUT
from .parameters import ALIASES, Catalogue, SweepError, parse_assignment, parse_case, parse_grid
from .stick_slip_map import (
    DEFAULT_WINDOW,
    FAILED,
    MAP_PARAMETER,
    MAP_SPEEDS,
    STICK_SLIP,
    default_cases,
    sliding_stability_speed,
    stick_slip_stop,
)
from .sweep_engine import (
    DEFAULT_STEP,
    DEFAULT_T_END,
    DEFAULT_WORKERS,
    beam_fmu,
    run_serial,
    run_sweep,
)

DEFAULT_BASENAME = "stick_slip_map"
PROG = "stickslip-sweep"  # the console script; also `python -m stickslip_checks.sweep`

# ----------------------------------------------------------------------------- output


def _format(value, digits=4) -> str:
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return str(value)


TABLE = [
    # (header, key, digits)
    ("regime", "regime", None),
    ("breakaway [s]", "breakaway_s", 4),
    ("stick->slip [-]", "stick_to_slip", None),
    ("in window [-]", "window_stick_to_slip", None),
    ("p2p [mm]", "p2p_mm", 4),
    ("min [mm]", "min_mm", 4),
    ("max [mm]", "max_mm", 4),
    ("stick [%]", "stick_pct", 3),
    ("wall [s]", "wall_s", 2),
    ("worker", "worker", None),
]


def print_table(rows: list[dict], swept: list[str]) -> None:
    headers = ["case"] + swept + [h for h, *_ in TABLE]
    lines = []
    for r in rows:
        r = dict(
            r, stick_pct=None if r.get("stick_fraction") is None else 100 * r["stick_fraction"]
        )
        cells = [r["case"]] + [_format(r[name], 5) for name in swept]
        cells += [_format(r.get(key), digits or 4) for _, key, digits in TABLE]
        lines.append(cells)
    widths = [max(len(h), *(len(c[i]) for c in lines)) for i, h in enumerate(headers)]
    print("  ".join(h.ljust(w) for h, w in zip(headers, widths)).rstrip())
    print("  ".join("-" * w for w in widths))
    for cells in lines:
        print("  ".join(c.ljust(w) for c, w in zip(cells, widths)).rstrip())
    for r in rows:
        if r.get("error"):
            print(f"  {r['case']} {', '.join(f'{n}={r[n]}' for n in swept)}: {r['error']}")


CSV_COLUMNS = [
    ("regime", "regime"),
    ("breakaway [s]", "breakaway_s"),
    ("stick->slip transitions [-]", "stick_to_slip"),
    ("window start [s]", "window_start_s"),
    ("stick->slip in window [-]", "window_stick_to_slip"),
    ("peak-to-peak tip deflection [mm]", "p2p_mm"),
    ("min tip deflection [mm]", "min_mm"),
    ("max tip deflection [mm]", "max_mm"),
    ("mean tip deflection [mm]", "mean_mm"),
    ("stick fraction in window [-]", "stick_fraction"),
    ("corridor min after breakaway [mm]", "corridor_min_mm"),
    ("corridor max after breakaway [mm]", "corridor_max_mm"),
    ("wall [s]", "wall_s"),
    ("worker", "worker"),
    ("note", "note"),
    ("error", "error"),
]


def write_csv(
    rows: list[dict], swept: list[str], fixed: list[str], units: dict, defaults: dict, path: Path
) -> None:
    """One row per run: case, swept parameters, the case's fixed parameters, metrics."""

    def head(name):
        return f"{name} [{units[name]}]" if units.get(name) else name

    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(
            ["case"]
            + [head(n) for n in swept + fixed]
            + ["fidelity", "t_end [s]"]
            + [h for h, _ in CSV_COLUMNS]
        )
        for r in rows:
            # A parameter a case leaves alone has the FMU's start value: write that.
            cells = [r["case"]] + [r.get(n, defaults.get(n, "")) for n in swept + fixed]
            cells += [r["fidelity"], r["t_end_s"]]
            for _, key in CSV_COLUMNS:
                value = r.get(key)
                cells.append(
                    "" if value is None else repr(value) if isinstance(value, float) else value
                )
            writer.writerow(cells)


# ----------------------------------------------------------------------------- command line


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
        default=DEFAULT_WORKERS,
        help="worker processes of the LocalCluster (default 2; 0 = in this process, no Dask)",
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


def build_runs(args, catalogue: Catalogue):
    """(runs, swept names, log spacing of the first, is the default map) from the options."""
    fixed = dict(parse_assignment(catalogue, s) for s in args.set)
    grids = [parse_grid(catalogue, g) for g in args.grid]
    names = [n for n, *_ in grids]
    if len(set(names)) != len(names):
        raise SweepError(f"a parameter appears in two --grid options: {', '.join(names)}")
    cases = [parse_case(catalogue, c) for c in args.case]
    default_map = not grids
    if default_map:
        if MAP_PARAMETER in fixed:
            raise SweepError(
                "the default map sweeps belt_speed: drop --set belt_speed or give a --grid"
            )
        grids = [(MAP_PARAMETER, list(MAP_SPEEDS), True)]
        names = [MAP_PARAMETER]
    case_names = {n for _, values in default_cases(catalogue) for n in values}
    touches_cases = any(n in case_names for n in list(fixed) + names)
    if not cases:
        # The default map's cases, unless --set/--grid already chose damping or start.
        cases = default_cases(catalogue) if default_map and not touches_cases else [("as set", {})]
    for name in names:
        if name in fixed or any(name in values for _, values in cases):
            raise SweepError(f"{name} is both swept (--grid) and fixed (--set/--case)")
    runs = []
    for label, values in cases:
        for combo in product(*(v for _, v, _ in grids)):
            params = {**fixed, **values, **dict(zip(names, combo))}
            runs.append((label, params))
    return runs, names, grids[0][2], default_map


def list_parameters(catalogue: Catalogue) -> None:
    for v in catalogue.variables.values():
        choices = f" {{{', '.join(v.items)}}}" if v.items else ""
        unit = f" [{v.unit}]" if v.unit else ""
        print(
            f"{v.name:32} {v.kind:11} {v.causality:9} start {v.start}{unit}{choices}  "
            f"{v.description}"
        )
    print("aliases: " + ", ".join(f"{a} = {n}" for a, n in ALIASES.items()))


def main(argv: list[str] | None = None) -> int:
    try:
        catalogue = Catalogue(beam_fmu(None))
    except SweepError:
        catalogue = None  # reported below, after --help had its chance
    args = _parser(catalogue.fidelities if catalogue else None).parse_args(argv)
    try:
        fmu = beam_fmu(None)
        if args.list:
            list_parameters(catalogue)
            return 0
        runs, swept, log_x, default_map = build_runs(args, catalogue)
        param_sets = [p for _, p in runs]
        began = time.perf_counter()
        common = dict(
            fidelity=args.fidelity, t_end=args.t_end, step=args.step, window=args.window, fmu=fmu
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

    defaults = catalogue.defaults()
    fixed_names = sorted({n for _, p in runs for n in p} - set(swept))
    rows = []
    for (label, params), result in zip(runs, results):
        others = [
            f"{n}={params[n]:.4g}" if isinstance(params[n], float) else f"{n}={params[n]}"
            for n in swept[1:]
        ]
        rows.append(
            {
                "case": label,
                "series": ", ".join([label] + others),
                **params,
                "fidelity": args.fidelity,
                "t_end_s": args.t_end,
                **result,
            }
        )

    print(f"StickSlipBeam.fmu: {fmu}")
    print(
        f"{len(rows)} runs, {args.fidelity} fidelity, 0 .. {args.t_end:g} s at {args.step:g} s; "
        f"metrics over the last {args.window:.3g} of each run"
    )
    print_table(rows, swept)

    series = list(dict.fromkeys(r["series"] for r in rows))
    x_name = swept[0]
    stability, stops = {}, {}
    for label in series:
        mine = [r for r in rows if r["series"] == label]
        stops[label] = stick_slip_stop([r[x_name] for r in mine], [r["regime"] for r in mine])
        if x_name == MAP_PARAMETER and len(swept) == 1:
            try:
                stability[label] = sliding_stability_speed({**defaults, **mine[0]})
            except (ArithmeticError, ValueError):  # e.g. a negative density: no estimate
                stability[label] = None
    x_unit = catalogue.variables[x_name].unit or ""
    print()
    for label in series:
        mine = [r for r in rows if r["series"] == label]
        kinds = sorted({r["regime"] for r in mine})
        if stops[label]:
            lo, hi = stops[label]
            text = f"stick-slip stops between {x_name} = {lo:.4g} and {hi:.4g} {x_unit}"
        elif kinds == [STICK_SLIP]:
            text = f"stick-slip at every {x_name} of the grid"
        else:
            text = "regimes: " + ", ".join(
                f"{k} x{sum(r['regime'] == k for r in mine)}" for k in kinds
            )
        if stability.get(label) is not None:
            text += (
                f"; steady sliding linearly stable above {stability[label]:.3g} m/s "
                "(mode 1 estimate)"
            )
        print(f"{label}: {text}")
    notes = sorted({r["note"] for r in rows if r.get("note")})
    for note in notes:
        print(f"note: {note}")
    load_text = ", ".join(f"{w}: {n}" for w, n in sorted(results.loads.items()))
    print(f"FMU loads per worker: {load_text} ({len(rows)} runs)")

    args.out.mkdir(parents=True, exist_ok=True)
    csv_path, png_path = args.out / f"{args.name}.csv", args.out / f"{args.name}.png"
    units = {n: v.unit for n, v in catalogue.variables.items()}
    write_csv(rows, swept, fixed_names, units, defaults, csv_path)
    title = (
        "Stick-slip map of StickSlipBeam.fmu: where stick-slip stops"
        if default_map
        else f"Sweep of StickSlipBeam.fmu over {', '.join(swept)}"
    )
    starts = {r.get("contact.initial_state", defaults["contact.initial_state"]) for r in rows}
    if len(starts) == 1:
        start_text = f"{starts.pop()} start"
    elif default_map:
        start_text = "quasi-static start (tip moving with the belt) unless 'start at rest'"
    else:
        start_text = "start per case (contact.initial_state in the CSV)"
    title += (
        f"\n{args.fidelity} fidelity, {start_text}; runs 0..{args.t_end:g} s, "
        f"metrics over t >= {(1 - args.window) * args.t_end:.3g} s"
    )
    var = catalogue.variables[x_name]
    x_label = f"{var.description or x_name} ({x_name})" + (f" ({var.unit})" if var.unit else "")
    plots.stick_slip_map(rows, x_name, x_label, log_x, series, stability, stops, title, png_path)
    print(f"wrote {csv_path}")
    print(f"wrote {png_path}")
    print(f"wall time {wall:.1f} s for the runs ({time.perf_counter() - began:.1f} s in all)")
    return 0 if not any(r["regime"] == FAILED for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
