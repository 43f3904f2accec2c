"""A sweep as the sweep entry point runs it: the runs its options ask for (build_runs),
their rows with the parameters (Sweep), the printed table and summary, the CSV file,
the figure, and the same rows as a DataFrame or, over the grid, an xarray Dataset.

The runs themselves: sweep_engine; the metrics, the map's cases and where stick-slip
stops: stick_slip_map; the parameters: parameters."""

from __future__ import annotations

from dataclasses import dataclass
from itertools import product
from pathlib import Path
from typing import TYPE_CHECKING

from . import plots
from .parameters import ALIASES, Catalogue, SweepError, parse_assignment, parse_case, parse_grid
from .stick_slip_map import (
    FAILED,
    MAP_PARAMETER,
    MAP_SPEEDS,
    STICK_SLIP,
    default_cases,
    sliding_stability_speed,
    stick_slip_stop,
)
from .sweep_engine import SweepResults
from .tables import format_table, frame, write_csv

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

Run = tuple[str, dict]  # (case label, parameter values)


def build_runs(
    catalogue: Catalogue, sets: list[str], grids: list[str], cases: list[str]
) -> tuple[list[Run], list[str], bool, bool]:
    """(runs, swept names, log spacing of the first, is the default map) from the
    --set, --grid and --case options."""
    fixed = dict(parse_assignment(catalogue, s) for s in sets)
    parsed = [parse_grid(catalogue, g) for g in grids]
    names = [n for n, *_ in parsed]
    if len(set(names)) != len(names):
        raise SweepError(f"a parameter appears in two --grid options: {', '.join(names)}")
    chosen = [parse_case(catalogue, c) for c in cases]
    default_map = not parsed
    if default_map:
        if MAP_PARAMETER in fixed:
            raise SweepError(
                "the default map sweeps belt_speed: drop --set belt_speed or give a --grid"
            )
        parsed = [(MAP_PARAMETER, list(MAP_SPEEDS), True)]
        names = [MAP_PARAMETER]
    case_names = {n for _, values in default_cases(catalogue) for n in values}
    touches_cases = any(n in case_names for n in list(fixed) + names)
    if not chosen:
        # The default map's cases, unless --set/--grid already chose damping or start.
        chosen = default_cases(catalogue) if default_map and not touches_cases else [("as set", {})]
    for name in names:
        if name in fixed or any(name in values for _, values in chosen):
            raise SweepError(f"{name} is both swept (--grid) and fixed (--set/--case)")
    runs = []
    for label, values in chosen:
        for combo in product(*(v for _, v, _ in parsed)):
            runs.append((label, {**fixed, **values, **dict(zip(names, combo))}))
    return runs, names, parsed[0][2], default_map


def parameter_lines(catalogue: Catalogue) -> list[str]:
    """The settable parameters and inputs, one a line, then the aliases."""
    lines = []
    for v in catalogue.variables.values():
        choices = f" {{{', '.join(v.items)}}}" if v.items else ""
        unit = f" [{v.unit}]" if v.unit else ""
        lines.append(
            f"{v.name:32} {v.kind:11} {v.causality:9} start {v.start}{unit}{choices}  "
            f"{v.description}"
        )
    lines.append("aliases: " + ", ".join(f"{a} = {n}" for a, n in ALIASES.items()))
    return lines


@dataclass
class Sweep:
    """The finished runs: one row per run (case, series label, parameters, fidelity,
    t_end_s and the metrics of stick_slip_map.run_metrics), in the order of the runs."""

    catalogue: Catalogue
    runs: list[Run]
    swept: list[str]
    log_x: bool
    default_map: bool
    fidelity: str
    t_end: float
    window: float
    results: SweepResults

    @property
    def rows(self) -> list[dict]:
        rows = []
        for (label, params), result in zip(self.runs, self.results):
            others = [
                f"{n}={params[n]:.4g}" if isinstance(params[n], float) else f"{n}={params[n]}"
                for n in self.swept[1:]
            ]
            rows.append({
                "case": label,
                "series": ", ".join([label] + others),
                **params,
                "fidelity": self.fidelity,
                "t_end_s": self.t_end,
                **result,
            })
        return rows

    @property
    def fixed(self) -> list[str]:
        """The parameters some case sets but no grid sweeps."""
        return sorted({n for _, p in self.runs for n in p} - set(self.swept))

    @property
    def failed(self) -> bool:
        return any(r["regime"] == FAILED for r in self.results)


# ----------------------------------------------------------------------------- the table

def _format(value: object, digits: int = 4) -> str:
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


def table(sweep: Sweep) -> str:
    """One line per run (all columns left-aligned), then the error of each failed run."""
    rows, swept = sweep.rows, sweep.swept
    headers = ["case"] + swept + [h for h, *_ in TABLE]
    lines = []
    for r in rows:
        r = dict(
            r, stick_pct=None if r.get("stick_fraction") is None else 100 * r["stick_fraction"]
        )
        cells = [r["case"]] + [_format(r[name], 5) for name in swept]
        cells += [_format(r.get(key), digits or 4) for _, key, digits in TABLE]
        lines.append(cells)
    errors = [
        f"\n  {r['case']} {', '.join(f'{n}={r[n]}' for n in swept)}: {r['error']}"
        for r in rows
        if r.get("error")
    ]
    return format_table(headers, lines, left=None) + "".join(errors)


Series = tuple[list[dict], tuple[float, float] | None, float | None]


def by_series(sweep: Sweep) -> dict[str, Series]:
    """Per series (a case and the values of the swept parameters but the first): its
    rows, where stick-slip stops along the first swept parameter, and for a sweep over
    belt speed alone the speed above which steady sliding is linearly stable."""
    rows, x_name = sweep.rows, sweep.swept[0]
    defaults = sweep.catalogue.defaults()
    result = {}
    for label in dict.fromkeys(r["series"] for r in rows):
        mine = [r for r in rows if r["series"] == label]
        stops = stick_slip_stop([r[x_name] for r in mine], [r["regime"] for r in mine])
        result[label] = (mine, stops, _stability(sweep, {**defaults, **mine[0]}))
    return result


def summary_lines(sweep: Sweep) -> list[str]:
    """Per series: where stick-slip stops (or its regimes) and where steady sliding is
    stable; then the runs' notes."""
    x_name = sweep.swept[0]
    x_unit = sweep.catalogue.variables[x_name].unit or ""
    lines = []
    for label, (mine, stops, stability) in by_series(sweep).items():
        kinds = sorted({r["regime"] for r in mine})
        if stops:
            lo, hi = stops
            text = f"stick-slip stops between {x_name} = {lo:.4g} and {hi:.4g} {x_unit}"
        elif kinds == [STICK_SLIP]:
            text = f"stick-slip at every {x_name} of the grid"
        else:
            text = "regimes: " + ", ".join(
                f"{k} x{sum(r['regime'] == k for r in mine)}" for k in kinds
            )
        if stability is not None:
            text += f"; steady sliding linearly stable above {stability:.3g} m/s (mode 1 estimate)"
        lines.append(f"{label}: {text}")
    notes = sorted({r["note"] for r in sweep.rows if r.get("note")})
    return lines + [f"note: {note}" for note in notes]


def _stability(sweep: Sweep, params: dict) -> float | None:
    """The mode-1 estimate of where steady sliding becomes stable, for a sweep over belt
    speed alone (None otherwise, or where there is no estimate)."""
    if sweep.swept != [MAP_PARAMETER]:
        return None
    try:
        return sliding_stability_speed(params)
    except (ArithmeticError, ValueError):  # e.g. a negative density: no estimate
        return None


# ----------------------------------------------------------------------------- CSV, frames

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


def csv_headers(sweep: Sweep) -> list[str]:
    units = {n: v.unit for n, v in sweep.catalogue.variables.items()}

    def head(name: str) -> str:
        return f"{name} [{units[name]}]" if units.get(name) else name

    return (
        ["case"]
        + [head(n) for n in sweep.swept + sweep.fixed]
        + ["fidelity", "t_end [s]"]
        + [h for h, _ in CSV_COLUMNS]
    )


def csv_rows(sweep: Sweep) -> list[list]:
    """One row per run: case, swept parameters, the case's fixed parameters, metrics."""
    defaults = sweep.catalogue.defaults()
    rows = []
    for r in sweep.rows:
        # A parameter a case leaves alone has the FMU's start value: write that.
        cells = [r["case"]] + [r.get(n, defaults.get(n, "")) for n in sweep.swept + sweep.fixed]
        cells += [r["fidelity"], r["t_end_s"]]
        for _, key in CSV_COLUMNS:
            value = r.get(key)
            cells.append(
                "" if value is None else repr(value) if isinstance(value, float) else value
            )
        rows.append(cells)
    return rows


def to_frame(sweep: Sweep) -> pd.DataFrame:
    """The rows of the CSV file as a DataFrame."""
    return frame(csv_headers(sweep), csv_rows(sweep))


def to_dataset(sweep: Sweep) -> xr.Dataset:
    """The metrics over the grid: dimensions case and the swept parameters (each
    variable named as in the CSV file), e.g. p2p tip deflection against case and
    belt_speed for the stick-slip map."""
    headers = csv_headers(sweep)
    dims = ["case"] + headers[1 : 1 + len(sweep.swept)]
    table = to_frame(sweep).drop(columns=headers[1 + len(sweep.swept) : -len(CSV_COLUMNS)])
    return table.set_index(dims).to_xarray()


def write_outputs(sweep: Sweep, out: Path, name: str) -> tuple[Path, Path]:
    """<name>.csv and <name>.png in `out`."""
    csv_path, png_path = out / f"{name}.csv", out / f"{name}.png"
    write_csv(csv_path, csv_headers(sweep), csv_rows(sweep))
    rows, swept, defaults = sweep.rows, sweep.swept, sweep.catalogue.defaults()
    series = by_series(sweep)
    stops = {label: stop for label, (_, stop, _) in series.items()}
    stability = {label: speed for label, (_, _, speed) in series.items()}
    x_name = swept[0]
    title = (
        "Stick-slip map of StickSlipBeam.fmu: where stick-slip stops"
        if sweep.default_map
        else f"Sweep of StickSlipBeam.fmu over {', '.join(swept)}"
    )
    starts = {r.get("contact.initial_state", defaults["contact.initial_state"]) for r in rows}
    if len(starts) == 1:
        start_text = f"{starts.pop()} start"
    elif sweep.default_map:
        start_text = "quasi-static start (tip moving with the belt) unless 'start at rest'"
    else:
        start_text = "start per case (contact.initial_state in the CSV)"
    title += (
        f"\n{sweep.fidelity} fidelity, {start_text}; runs 0..{sweep.t_end:g} s, "
        f"metrics over t >= {(1 - sweep.window) * sweep.t_end:.3g} s"
    )
    var = sweep.catalogue.variables[x_name]
    x_label = f"{var.description or x_name} ({x_name})" + (f" ({var.unit})" if var.unit else "")
    plots.stick_slip_map(
        rows, x_name, x_label, sweep.log_x, list(series), stability, stops, title, png_path
    )
    return csv_path, png_path
