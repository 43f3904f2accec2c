"""The settable variables of StickSlipBeam.fmu for sweeps: names (and the scene file's
aliases), types, units and start values from its model description, and the parsing of
`--set name=value`, `--grid name=start:stop:count[:log]` / `name=v1,v2,...` and
`--case LABEL:name=value,...` into typed values (choices as their item names).
"""

from __future__ import annotations

import difflib
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .artifacts import Model, fidelities

# The scene file calls the FMU's two inputs loading.*; accept both spellings.
ALIASES = {"loading.belt_speed": "belt_speed", "loading.normal_force": "normal_force"}
# The kind of a choice variable: an FMI Integer whose codes name its values (set by word
# or code).
CHOICE = "Choice"
# Causalities whose values a sweep may set before initialisation.
SETTABLE = ("parameter", "input")


class SweepError(ValueError):
    """A bad parameter name, value or grid; main() turns it into SystemExit(message)."""


@dataclass(frozen=True)
class Variable:
    """One settable variable of the model description."""

    name: str
    kind: str  # Real, Integer, Boolean or String (the model description's type), or CHOICE
    causality: str
    unit: str | None
    start: object  # typed start value (choices as their item name)
    items: dict[str, int] | None  # a choice's word -> integer code (artifacts.choices)
    description: str


class Catalogue:
    """The settable variables of StickSlipBeam's model description, by name, read through
    artifacts.Model (which keeps the value references and sets the values)."""

    def __init__(self, fmu: Path):
        model = Model.read(fmu)
        # The structural models --fidelity accepts (fidelity.level without auto).
        self.fidelities = fidelities(model)
        self.variables: dict[str, Variable] = {}
        for v in model.variables.values():
            if v.causality not in SETTABLE:
                continue
            items = model.choices.get(v.name)
            var = Variable(
                v.name,
                CHOICE if items is not None else v.type,
                v.causality,
                v.unit,
                None,
                items,
                v.description or "",
            )
            if v.start is not None:
                # The XML holds every start value as text; keep it typed like a --set value.
                var = replace(var, start=_parse_value(var, v.start, from_xml=True))
            self.variables[v.name] = var

    def resolve(self, name: str) -> Variable:
        """The variable called `name` (or its scene-file alias); SweepError with close matches."""
        key = ALIASES.get(name, name)
        if key in self.variables:
            return self.variables[key]
        known = list(self.variables) + list(ALIASES)
        close = difflib.get_close_matches(name, known, n=5, cutoff=0.5)
        # A bare last component ("static_coefficient") is a common slip: suggest its group.
        close += [k for k in self.variables if k.split(".")[-1] == name and k not in close]
        hint = f"; close matches: {', '.join(close)}" if close else ""
        raise SweepError(
            f"unknown parameter '{name}'{hint} "
            "(`stickslip-sweep --list` prints every settable name)"
        )

    def value(self, name: str, text) -> tuple[str, object]:
        """(canonical name, typed value) for `name`=`text`; SweepError if it does not fit."""
        var = self.resolve(name)
        return var.name, _parse_value(var, text)

    def defaults(self) -> dict[str, object]:
        """Start values of every settable variable (the FMU's defaults)."""
        return {n: v.start for n, v in self.variables.items()}


def _parse_value(var: Variable, text, from_xml: bool = False):
    """`text` (a string or a number) as a value of `var`'s type."""
    raw = text.strip() if isinstance(text, str) else text
    try:
        if var.items is not None:  # a choice: by item name or integer code
            by_value = {v: k for k, v in var.items.items()}
            if str(raw) in var.items:
                return str(raw)
            if str(raw).lstrip("-").isdigit() and int(raw) in by_value:
                return by_value[int(raw)]  # choices are kept as their item name
            raise ValueError(f"not one of {', '.join(var.items)}")
        if var.kind == "Real":
            value = float(raw)
            if not math.isfinite(value):
                raise ValueError("not finite")
            return value
        if var.kind == "Integer":
            number = float(raw)
            if number != int(number):
                raise ValueError("not an integer")
            return int(number)
        if var.kind == "Boolean":
            if isinstance(raw, (bool, np.bool_)):
                return bool(raw)
            words = {"true": True, "1": True, "false": False, "0": False}
            if str(raw).lower() not in words:
                raise ValueError("not a Boolean (true/false/1/0)")
            return words[str(raw).lower()]
        return str(raw)  # String
    except (TypeError, ValueError) as error:
        if from_xml:
            return None
        raise SweepError(
            f"bad value '{text}' for {var.name} ({var.kind}"
            f"{', ' + var.unit if var.unit else ''}): {error}"
        ) from None


def parse_assignment(catalogue: Catalogue, spec: str) -> tuple[str, object]:
    """'name=value' -> (canonical name, typed value)."""
    name, sep, text = spec.partition("=")
    if not sep or not name.strip() or not text.strip():
        raise SweepError(
            f"bad --set '{spec}': expected name=value, e.g. friction.static_coefficient=0.6"
        )
    return catalogue.value(name.strip(), text)


def parse_grid(catalogue: Catalogue, spec: str) -> tuple[str, list, bool]:
    """'name=start:stop:count[:log]' or 'name=v1,v2,...' -> (name, values, log spacing)."""
    usage = (
        "expected name=start:stop:count[:log] or name=v1,v2,... (e.g. belt_speed=0.005:2:24:log)"
    )
    name, sep, text = spec.partition("=")
    if not sep or not name.strip() or not text.strip():
        raise SweepError(f"bad --grid '{spec}': {usage}")
    var = catalogue.resolve(name.strip())
    if ":" not in text:
        values = [_parse_value(var, part) for part in text.split(",") if part.strip()]
        if not values:
            raise SweepError(f"bad --grid '{spec}': no values; {usage}")
        return var.name, values, False
    if var.items is not None or var.kind not in ("Real", "Integer"):
        raise SweepError(
            f"bad --grid '{spec}': {var.name} is {var.kind}; a range needs a Real or Integer "
            f"parameter (list its values instead: {var.name}=a,b)"
        )
    parts = text.split(":")
    if len(parts) not in (3, 4) or (len(parts) == 4 and parts[3].strip() != "log"):
        raise SweepError(f"bad --grid '{spec}': {usage}")
    try:
        start, stop = float(parts[0]), float(parts[1])
        count = int(parts[2])
    except ValueError:
        raise SweepError(
            f"bad --grid '{spec}': start and stop must be numbers and count an integer; {usage}"
        ) from None
    log = len(parts) == 4
    if not (math.isfinite(start) and math.isfinite(stop)):
        raise SweepError(f"bad --grid '{spec}': start and stop must be finite")
    if count < 1:
        raise SweepError(f"bad --grid '{spec}': count must be >= 1")
    if count == 1 and start != stop:
        raise SweepError(f"bad --grid '{spec}': count 1 needs start == stop")
    if log and (start <= 0 or stop <= 0):
        raise SweepError(f"bad --grid '{spec}': a log grid needs start > 0 and stop > 0")
    values = np.geomspace(start, stop, count) if log else np.linspace(start, stop, count)
    typed = [_parse_value(var, float(v) if var.kind == "Real" else round(float(v))) for v in values]
    if len(set(typed)) != len(typed):
        raise SweepError(
            f"bad --grid '{spec}': {var.name} is an Integer and the grid repeats values"
        )
    return var.name, typed, log


def parse_case(catalogue: Catalogue, spec: str) -> tuple[str, dict]:
    """'LABEL:name=value,name=value' -> (label, {name: value})."""
    label, sep, body = spec.partition(":")
    if not sep or not label.strip():
        raise SweepError(f"bad --case '{spec}': expected LABEL:name=value[,name=value...]")
    values = dict(parse_assignment(catalogue, part) for part in body.split(",") if part.strip())
    return label.strip(), values
