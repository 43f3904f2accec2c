"""Parameter sweeps of StickSlipBeam.fmu on Dask, and the stick-slip map.

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

Why Dask: a map is tens of independent runs. A LocalCluster of worker processes uses
every core of this machine; `--scheduler tcp://host:port` sends the same tasks to an
existing cluster instead.

Loading: a WorkerPlugin carries the FMU's bytes to every worker. Its setup unpacks the
archive, loads the shared library and calls fmi2Instantiate once per worker process; each
task then only calls fmi2Reset, sets its parameters, initialises and steps. Every result
row says which worker ran it and how often that worker has loaded the FMU, so a test can
check "loaded once per worker, not once per task". A worker runs its tasks one at a time
on its single instance (a lock guards it if the worker has several threads).

The FMUs are found as in fmu_scene.py ($STICKSLIP_FMU_DIR, else $CARGO_TARGET_DIR/fmu,
else <repo>/target/fmu).

Usage:
  python sweep.py [--scheduler tcp://host:port] [--workers 2] [--set name=value ...]
                  [--grid name=start:stop:count[:log] | name=v1,v2,...] ...
                  [--case LABEL:name=value,name=value ...] [--fidelity modal|beam|plane-stress]
                  [--t-end S] [--step S] [--window F] [--out DIR] [--name BASENAME] [--list]

Several --grid options span their Cartesian product; --set applies to every run. Writes
<out>/<name>.csv (one row per run) and <out>/<name>.png (default out/stick_slip_map.*).
--workers 0 runs in this process without Dask. A remote cluster gets this file through
Client.upload_file; its scheduler and workers need numpy, fmpy and distributed.

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
import difflib
import hashlib
import math
import shutil
import sys
import tempfile
import threading
import time
from dataclasses import dataclass, replace
from itertools import product
from pathlib import Path

import numpy as np
from distributed.diagnostics.plugin import WorkerPlugin
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

HERE = Path(__file__).resolve().parent


def _scene():
    """fmu_scene.py (where the FMUs are, the FIDELITY enumeration), imported on the client
    only: the workers of a remote cluster receive sweep.py alone, while fmu_scene imports
    further modules of python-checks."""
    if str(HERE) not in sys.path:
        sys.path.insert(0, str(HERE))
    import fmu_scene

    return fmu_scene


DEFAULT_T_END = 20.0  # s: the slowest map speed breaks away at 1.6 s; see MAP_SPEEDS
DEFAULT_STEP = 1e-3  # s: communication step and sampling interval of the outputs
DEFAULT_WINDOW = 1.0 / 3.0  # metrics over the last third of the run (after transients)
DEFAULT_WORKERS = 2  # this machine has two cores
DEFAULT_BASENAME = "stick_slip_map"

# Belt speeds of the map (m/s): three per octave from 0.005 to 10.24 m/s, so that the
# paper's 0.02 m/s is a grid point (0.005 * 2^2, exact in binary). The top speed is well
# above where stick-slip stops with either damping case of the map (measured: ~1.1 m/s
# with 2 % Rayleigh damping, ~6 m/s with the FMU's default b = 5e-5 s).
MAP_SPEEDS = tuple(0.005 * 2.0 ** (k / 3) for k in range(34))
MAP_PARAMETER = "belt_speed"
RAYLEIGH_RATIO = 0.02  # damping ratio at modes 1 and 3 of the "2 % Rayleigh" case

# The scene file calls the FMU's two inputs loading.*; accept both spellings.
ALIASES = {"loading.belt_speed": "belt_speed", "loading.normal_force": "normal_force"}
# Causalities whose values a sweep may set before initialisation.
SETTABLE = ("parameter", "input")

# Regimes over the metrics window.
STICK_SLIP = "stick-slip"
SLIDING = "steady sliding"
STUCK = "stuck"
FAILED = "error"

# Euler-Bernoulli cantilever: beta_n L of modes 1 and 3;
# omega_n = (beta_n L)^2 sqrt(EI / (rho A L^4)).
BETA_L = {1: 1.875104, 3: 7.854757}


class SweepError(ValueError):
    """A bad parameter name, value or grid; main() turns it into SystemExit(message)."""


# ----------------------------------------------------------------------------- parameters


@dataclass(frozen=True)
class Variable:
    """One settable variable of the model description."""

    name: str
    vr: int
    kind: str  # Real, Integer, Boolean, Enumeration or String
    causality: str
    unit: str | None
    start: object  # typed start value (enumerations as their item name)
    items: dict[str, int] | None  # enumeration item name -> value
    description: str


class Catalogue:
    """The settable variables of StickSlipBeam's model description, by name."""

    def __init__(self, fmu: Path):
        md = read_model_description(str(fmu))
        self.variables: dict[str, Variable] = {}
        for v in md.modelVariables:
            if v.causality not in SETTABLE:
                continue
            items = None
            if v.type == "Enumeration":
                items = {item.name: int(item.value) for item in v.declaredType.items}
            var = Variable(
                v.name,
                v.valueReference,
                v.type,
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
            f"unknown parameter '{name}'{hint} (`sweep.py --list` prints every settable name)"
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
        if var.kind == "Enumeration":
            by_value = {v: k for k, v in var.items.items()}
            if str(raw) in var.items:
                return str(raw)
            if str(raw).lstrip("-").isdigit() and int(raw) in by_value:
                return by_value[int(raw)]  # enumerations are kept as their item name
            raise ValueError(f"not one of {', '.join(var.items)}")
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
    if var.kind not in ("Real", "Integer"):
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


# ----------------------------------------------------------------------------- physics helpers


def _first_mode(params: dict) -> tuple[float, float, float]:
    """(omega_1 (rad/s), omega_3 (rad/s), total mass M (kg)) of the Euler-Bernoulli cantilever."""
    length = params["geometry.length"]
    area = params["geometry.width"] * params["geometry.height"]  # m^2
    ei = (
        params["material.youngs_modulus"]
        * params["geometry.width"]
        * params["geometry.height"] ** 3
        / 12
    )
    rho_a = params["material.density"] * area  # kg/m
    scale = math.sqrt(ei / (rho_a * length**4))
    return BETA_L[1] ** 2 * scale, BETA_L[3] ** 2 * scale, rho_a * length


def rayleigh_damping(params: dict, ratio: float = RAYLEIGH_RATIO) -> dict:
    """Rayleigh a (1/s), b (s) giving `ratio` at modes 1 and 3: zeta(w) = a/(2w) + b w/2."""
    w1, w3, _ = _first_mode(params)
    return {
        "damping.mass_proportional": 2 * ratio * w1 * w3 / (w1 + w3),
        "damping.stiffness_proportional": 2 * ratio / (w1 + w3),
    }


def sliding_stability_speed(params: dict) -> float | None:
    """Belt speed (m/s) above which steady sliding is linearly stable (mode 1), or None.

    Linearised about steady sliding, the exponential law's slope dF/dv_rel =
    -alpha (mu_s - mu_k) F_n exp(-alpha v_b) feeds the tip velocity back as negative
    damping. A cantilever's mass-normalised modes all have phi_n(L)^2 = 4 / M at the tip,
    so mode 1 (the least damped: 2 zeta_1 omega_1 = a + b omega_1^2) is stable when
    (4 / M) alpha (mu_s - mu_k) F_n exp(-alpha v_b) < a + b omega_1^2. Only for the
    exponential law with the relative sliding velocity; the higher modes and the coupling
    through the static correction are ignored.
    """
    if (
        params.get("friction.model") != "exponential"
        or params.get("contact.sliding_velocity") != "relative"
    ):
        return None
    w1, _, mass = _first_mode(params)
    damping = params["damping.mass_proportional"] + params["damping.stiffness_proportional"] * w1**2
    alpha = params["friction.decay"]
    slope = alpha * (params["friction.static_coefficient"] - params["friction.kinetic_coefficient"])
    gain = 4.0 / mass * slope * params["normal_force"]  # 1/s at v_b = 0
    if alpha <= 0 or gain <= 0:
        return 0.0
    if damping <= 0:
        return math.inf
    return max(0.0, math.log(gain / damping) / alpha)


# ----------------------------------------------------------------------------- FMU on a worker

# fmpy formats the FMU's variadic log calls in a small C proxy that forwards to one Python
# callback per process. Ours records the messages (so a failed run can say why) and prints
# them as fmpy's own callback does, so other FMUs in the same process see no change.
_LOG: list[str] = []
_LOGGER = None
_PROCESS_LOADS = 0  # FMU loads in this process, over every plugin instance


def _install_logger() -> None:
    global _LOGGER
    if _LOGGER is not None:
        return
    from ctypes import byref

    from fmpy.fmi2 import defaultCallbacks, fmi2CallbackLoggerTYPE
    from fmpy.logging import addLoggerProxy

    def record(_env, instance, status, category, message):
        label = ["OK", "WARNING", "DISCARD", "ERROR", "FATAL", "PENDING"][status]
        text = message.decode("utf-8", "replace")
        _LOG.append(f"[{label}] {text}")
        del _LOG[:-20]  # only the last few matter for an error row
        print(f"[{label}] {text}")

    _LOGGER = fmi2CallbackLoggerTYPE(record)  # kept alive for the process lifetime
    # addLoggerProxy stores the Python logger in its process-wide slot and puts its C proxy
    # into the struct; the defaults then reach `record` through the proxy.
    defaultCallbacks.logger = _LOGGER
    addLoggerProxy(byref(defaultCallbacks))


class FmuWorkerPlugin(WorkerPlugin):
    """StickSlipBeam.fmu loaded once per worker process: unpacked, library loaded, instantiated.

    Registered with Client.register_plugin, setup() runs on every worker (and on workers
    that join later). In-process, call setup() and teardown() yourself.
    """

    # Not idempotent: registering again replaces a plugin of the same name on every worker,
    # so a registration that failed earlier (or a stale instance) cannot linger.
    idempotent = False

    def __init__(self, fmu: Path):
        self.data = Path(fmu).read_bytes()
        self.filename = Path(fmu).name
        self.digest = hashlib.sha256(self.data).hexdigest()
        self.name = f"stickslip-fmu-{self.digest[:16]}"
        self.loads = 0
        self._runtime = None

    def __getstate__(self):
        # Only the archive travels; the instance and the temporary folder are per process.
        return {k: getattr(self, k) for k in ("data", "filename", "digest", "name")}

    def __setstate__(self, state):
        self.__dict__.update(state)
        self.loads = 0
        self._runtime = None

    def setup(self, worker=None):
        global _PROCESS_LOADS
        _install_logger()
        folder = Path(tempfile.mkdtemp(prefix="stickslip-sweep-"))
        archive = folder / self.filename
        archive.write_bytes(self.data)
        unzipped = Path(extract(str(archive), unzipdir=str(folder / "unzipped")))
        md = read_model_description(str(archive))
        slave = FMU2Slave(
            guid=md.guid,
            unzipDirectory=str(unzipped),
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=f"sweep-{self.digest[:8]}",
        )
        slave.instantiate()
        vr = {v.name: v.valueReference for v in md.modelVariables}
        kinds = {v.name: v.type for v in md.modelVariables}
        items = {
            v.name: {item.name: int(item.value) for item in v.declaredType.items}
            for v in md.modelVariables
            if v.type == "Enumeration"
        }
        self._runtime = dict(
            folder=folder,
            slave=slave,
            vr=vr,
            kinds=kinds,
            items=items,
            lock=threading.Lock(),
            address=getattr(worker, "address", "in-process"),
        )
        self.loads += 1
        _PROCESS_LOADS += 1

    def teardown(self, worker=None):
        runtime, self._runtime = self._runtime, None
        if runtime is None:
            return
        try:
            runtime["slave"].freeInstance()
        finally:
            shutil.rmtree(runtime["folder"], ignore_errors=True)

    def simulate(
        self, params: dict, fidelity: str, t_end: float, step: float, window: float
    ) -> dict:
        """One run from t = 0 to t_end on this worker's instance; the metrics row."""
        if self._runtime is None:
            raise RuntimeError(f"{self.name}: setup() has not run in this process")
        rt = self._runtime
        with rt["lock"]:
            began = time.perf_counter()
            _LOG.clear()  # so an error row quotes only this run's messages
            try:
                row = _simulate(rt, params, fidelity, t_end, step, window)
            except Exception as error:  # the FMU refused a value or failed: report, go on
                messages = [m for m in _LOG[-5:] if "[OK]" not in m]
                row = {
                    "regime": FAILED,
                    "error": f"{error}; FMU log: {' | '.join(messages) or '-'}",
                }
            row["wall_s"] = time.perf_counter() - began
            row["worker"] = rt["address"]
            row["worker_loads"] = self.loads
            row["process_loads"] = _PROCESS_LOADS
            return row


def _simulate(
    rt: dict, params: dict, fidelity: str, t_end: float, step: float, window: float
) -> dict:
    slave, vr, kinds, items = rt["slave"], rt["vr"], rt["kinds"], rt["items"]
    n = int(round(t_end / step))
    # fmi2Reset returns the instance to its state right after instantiation: the start
    # values, no experiment. It is also the way out of an earlier run's error state.
    slave.reset()
    slave.setupExperiment(startTime=0.0, stopTime=t_end)
    slave.enterInitializationMode()
    values = {"fidelity.level": fidelity, **params}
    for name, value in values.items():
        kind = kinds[name]
        if kind == "Real":
            slave.setReal([vr[name]], [float(value)])
        elif kind == "Integer":
            slave.setInteger([vr[name]], [int(value)])
        elif kind == "Enumeration":
            slave.setInteger([vr[name]], [items[name][value]])
        elif kind == "Boolean":
            slave.setBoolean([vr[name]], [bool(value)])
        else:
            slave.setString([vr[name]], [str(value)])
    slave.exitInitializationMode()

    u = np.empty(n + 1)  # tip deflection (m)
    stick = np.empty(n + 1, bool)
    transitions = np.empty(n + 1, np.int64)  # stick/slip transitions so far, both directions
    r_u, r_stick, r_trans = [vr["tip_deflection"]], [vr["stick"]], [vr["transitions"]]

    def sample(k):
        u[k] = slave.getReal(r_u)[0]
        stick[k] = slave.getBoolean(r_stick)[0]
        transitions[k] = slave.getInteger(r_trans)[0]

    sample(0)
    for k in range(n):
        # k * step, not a running sum, so the communication points carry no rounding drift.
        slave.doStep(currentCommunicationPoint=k * step, communicationStepSize=step)
        sample(k + 1)
    slave.terminate()
    times = np.arange(n + 1) * step
    row = run_metrics(times, u, stick, transitions, window)
    row["tip_sha256"] = hashlib.sha256(
        u.tobytes() + stick.tobytes() + transitions.tobytes()
    ).hexdigest()
    return row


def _simulate_on_worker(
    plugin_name: str, params: dict, fidelity: str, t_end: float, step: float, window: float
) -> dict:
    """Dask task: the run on this worker's already loaded FMU."""
    from distributed import get_worker

    return get_worker().plugins[plugin_name].simulate(params, fidelity, t_end, step, window)


def _worker_loads(plugin_name: str, dask_worker=None) -> int:
    """Loads of `plugin_name` on this worker (for Client.run)."""
    plugin = dask_worker.plugins.get(plugin_name)
    return -1 if plugin is None else plugin.loads


# ----------------------------------------------------------------------------- metrics


def _stick_to_slip(count: int, starts_in_stick: bool) -> int:
    """Stick -> slip transitions among `count` alternating transitions."""
    return (count + 1) // 2 if starts_in_stick else count // 2


def run_metrics(
    times: np.ndarray,
    u: np.ndarray,
    stick: np.ndarray,
    transitions: np.ndarray,
    window: float = DEFAULT_WINDOW,
) -> dict:
    """Metrics of one run sampled at the communication points.

    The transition counts come from the FMU's `transitions` counter, so they include
    stick or slip phases shorter than a sample. The stick fraction and the deflections are
    from the samples. The metrics window is the last `window` of the run. The regime is
    "stick-slip" if the tip sticks again after a slip within the window, "steady sliding"
    if it slips and does not stick again, "stuck" if it sticks through the whole window.
    """
    t_end = float(times[-1])
    i0 = int(np.searchsorted(times, (1.0 - window) * t_end - 1e-12))
    slipped = np.flatnonzero(~stick)
    # Sample times rounded to 1e-12 s: k * step carries binary noise (1.2750000000000001).
    breakaway = round(float(times[slipped[0]]), 12) if slipped.size else None
    n_total = int(transitions[-1] - transitions[0])
    n_window = int(transitions[-1] - transitions[i0])
    s2s_window = _stick_to_slip(n_window, bool(stick[i0]))
    resticks_window = n_window - s2s_window  # slip -> stick within the window
    if resticks_window > 0:
        regime = STICK_SLIP
    elif n_window == 0 and stick[i0]:
        regime = STUCK
    else:
        regime = SLIDING
    w = u[i0:]
    after = u[slipped[0] :] if slipped.size else u[:0]
    note = ""
    if breakaway is not None and breakaway > times[i0]:
        note = "breakaway inside the metrics window: lengthen --t-end"
    return {
        "regime": regime,
        "breakaway_s": breakaway,
        "stick_to_slip": _stick_to_slip(n_total, bool(stick[0])),
        "window_start_s": round(float(times[i0]), 12),
        "window_stick_to_slip": s2s_window,
        "p2p_mm": 1e3 * float(w.max() - w.min()),
        "min_mm": 1e3 * float(w.min()),
        "max_mm": 1e3 * float(w.max()),
        "mean_mm": 1e3 * float(w.mean()),
        "stick_fraction": float(stick[i0:].mean()),
        # The corridor of the whole run after breakaway, as in fmu_scene.py / README.
        "corridor_min_mm": 1e3 * float(after.min()) if after.size else None,
        "corridor_max_mm": 1e3 * float(after.max()) if after.size else None,
        "note": note,
    }


def stick_slip_stop(xs, regimes) -> tuple[float, float] | None:
    """(last x with stick-slip, next x) if every point above the last stick-slip one slides."""
    pairs = sorted(zip(xs, regimes))
    last = max((i for i, (_, r) in enumerate(pairs) if r == STICK_SLIP), default=None)
    if last is None or last == len(pairs) - 1:
        return None
    if any(r != SLIDING for _, r in pairs[last + 1 :]):
        return None
    return pairs[last][0], pairs[last + 1][0]


# ----------------------------------------------------------------------------- running


class SweepResults(list):
    """The rows of a sweep, in the order of the parameter sets, plus the FMU loads.

    `loads` maps each worker (its address, or "in-process") to how often it loaded the FMU
    during this sweep.
    """

    loads: dict[str, int]


def _check_sets(param_sets, fidelity: str, t_end: float, step: float, window: float, fmu: Path):
    """Validated copies of the parameter sets (canonical names, typed values)."""
    levels = _scene().FIDELITY
    if fidelity not in levels:
        raise SweepError(f"unknown fidelity '{fidelity}'; one of {', '.join(levels)}")
    if not (t_end > 0 and step > 0 and math.isfinite(t_end)):
        raise SweepError(f"t_end ({t_end} s) and step ({step} s) must be > 0")
    n = round(t_end / step)
    if n < 3 or abs(n * step - t_end) > 1e-9 * t_end:
        raise SweepError(f"t_end {t_end} s must be a multiple (>= 3) of the step {step} s")
    if not 0 < window <= 1:
        raise SweepError(f"window {window} must be in (0, 1]")
    catalogue = Catalogue(fmu)
    checked = []
    for params in param_sets:
        typed = dict(catalogue.value(name, value) for name, value in params.items())
        if "fidelity.level" in typed:
            raise SweepError(
                "set the structural model with --fidelity (fidelity=...), not fidelity.level"
            )
        checked.append(typed)
    return checked


def beam_fmu(fmu: Path | None = None) -> Path:
    """`fmu`, else StickSlipBeam.fmu where fmu_scene.fmu_paths() finds it; SweepError if
    it is missing (the message says how to build it)."""
    try:
        scene = _scene()
        return Path(fmu) if fmu is not None else scene.fmu_paths()[scene.BEAM]
    except FileNotFoundError as error:
        raise SweepError(str(error)) from None


def run_serial(
    param_sets,
    fidelity: str = "modal",
    t_end: float = DEFAULT_T_END,
    step: float = DEFAULT_STEP,
    window: float = DEFAULT_WINDOW,
    fmu: Path | None = None,
) -> SweepResults:
    """The same runs in this process, one after the other, on one FMU instance."""
    fmu = beam_fmu(fmu)
    sets = _check_sets(param_sets, fidelity, t_end, step, window, fmu)
    plugin = FmuWorkerPlugin(fmu)
    plugin.setup()
    try:
        results = SweepResults(plugin.simulate(p, fidelity, t_end, step, window) for p in sets)
    finally:
        plugin.teardown()
    results.loads = {"in-process": plugin.loads}
    return results


def run_sweep(
    param_sets,
    fidelity: str = "modal",
    t_end: float = DEFAULT_T_END,
    scheduler: str | None = None,
    workers: int = DEFAULT_WORKERS,
    step: float = DEFAULT_STEP,
    window: float = DEFAULT_WINDOW,
    fmu: Path | None = None,
) -> SweepResults:
    """Runs StickSlipBeam.fmu once per parameter set on Dask; the rows in input order.

    param_sets: list of {parameter name: value} (names and enumeration words as in the
    model description; loading.belt_speed / loading.normal_force are accepted aliases).
    scheduler: address of an existing Dask scheduler; None starts a LocalCluster of
    `workers` single-threaded worker processes on 127.0.0.1 (no dashboard), closed after.
    """
    fmu = beam_fmu(fmu)
    sets = _check_sets(param_sets, fidelity, t_end, step, window, fmu)
    from distributed import Client, LocalCluster

    cluster = None
    if scheduler is None:
        if workers < 1:
            raise SweepError("--workers must be >= 1 (or 0 for in-process runs without Dask)")
        # Processes, not threads: each worker is its own process with its own FMU instance,
        # and the runs do not share the GIL.
        cluster = LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
            worker_dashboard_address=None,
        )
        client = Client(cluster)
    else:
        try:
            client = Client(scheduler, timeout="15s")
        except (OSError, TimeoutError, ValueError) as error:
            raise SweepError(f"cannot reach the Dask scheduler at {scheduler}: {error}") from None
    try:
        if scheduler is not None:
            # The scheduler (it unpickles the task graph) and the workers of a cluster
            # started elsewhere need this module: upload_file puts it into their local
            # directories, which are on their sys.path. They need numpy, fmpy and
            # distributed installed, as any Dask cluster needs the client's environment.
            client.upload_file(str(Path(__file__)), load=False)
        plugin = FmuWorkerPlugin(fmu)
        client.register_plugin(plugin)
        futures = client.map(
            _simulate_on_worker,
            [plugin.name] * len(sets),
            sets,
            [fidelity] * len(sets),
            [t_end] * len(sets),
            [step] * len(sets),
            [window] * len(sets),
            pure=False,
        )
        results = SweepResults(client.gather(futures))
        results.loads = client.run(_worker_loads, plugin.name)
        # Free the instances on the workers of an existing cluster (a LocalCluster goes anyway).
        client.unregister_worker_plugin(plugin.name)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return results


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


def plot_map(
    rows: list[dict],
    x_name: str,
    x_label: str,
    log_x: bool,
    series: list[str],
    stability: dict[str, float | None],
    stops: dict[str, tuple | None],
    title: str,
    path: Path,
) -> None:
    """Peak-to-peak tip deflection and stick fraction against the first swept parameter.

    Filled markers: the tip re-sticks within the metrics window (stick-slip); open
    markers: it slides without sticking again, and the peak-to-peak value is what is left
    of the oscillation that followed breakaway.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax_s) = plt.subplots(
        2, 1, figsize=(10, 8.5), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]}
    )
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    # Enumeration, Boolean or String values (e.g. --grid friction.model=exponential,coulomb)
    # go at evenly spaced positions with their names as tick labels.
    categories = list(dict.fromkeys(r[x_name] for r in rows))
    categorical = any(isinstance(c, (str, bool)) for c in categories)

    def position(x):
        return categories.index(x) if categorical else x

    unit = x_label.rsplit("(", 1)[-1].rstrip(")") if x_label.endswith(")") else ""
    for i, label in enumerate(series):
        colour = colours[i % len(colours)]
        mine = [r for r in rows if r["series"] == label]
        if not categorical:
            mine.sort(key=lambda r: r[x_name])
        ok = [r for r in mine if r["regime"] != FAILED]
        xs = np.array([position(r[x_name]) for r in ok], float)
        # Log axis: a run that never moves (p2p = 0) is drawn at 1e-6 mm.
        p2p = np.array([max(r["p2p_mm"], 1e-6) for r in ok])
        ax.plot(xs, p2p, color=colour, lw=1.0, alpha=0.5)
        ax_s.plot(
            xs,
            [100 * r["stick_fraction"] for r in ok],
            color=colour,
            lw=1.0,
            marker="o",
            ms=3.5,
            label=label,
        )
        for regime, marker, face, text in (
            (STICK_SLIP, "o", colour, "stick-slip (re-sticks)"),
            (SLIDING, "o", "white", "steady sliding (no re-stick)"),
            (STUCK, "s", colour, "stuck (never slides in the window)"),
        ):
            pick = np.array([r["regime"] == regime for r in ok], bool)
            if pick.any():
                ax.plot(
                    xs[pick],
                    p2p[pick],
                    ls="none",
                    marker=marker,
                    ms=6,
                    mfc=face,
                    mec=colour,
                    color=colour,
                    label=f"{label}: {text}",
                )
        if stops.get(label):
            lo, hi = stops[label]
            ax.axvspan(
                lo,
                hi,
                color=colour,
                alpha=0.18,
                label=f"{label}: stick-slip stops between {lo:.3g} and {hi:.3g} {unit}",
            )
    # One dashed line per distinct threshold (cases that differ only in the start share it).
    for value in dict.fromkeys(v for v in stability.values() if v and math.isfinite(v)):
        owners = [label for label in series if stability.get(label) == value]
        ax.axvline(
            value,
            color=colours[series.index(owners[0]) % len(colours)],
            lw=1.2,
            ls="--",
            label=f"{' | '.join(owners)}: steady sliding linearly stable above "
            f"{value:.2f} {unit} (mode 1)",
        )
    if log_x and not categorical:
        ax.set_xscale("log")
    if categorical:
        ax_s.set_xticks(range(len(categories)), [str(c) for c in categories])
    ax.set_yscale("log")
    ax.set_ylabel("peak-to-peak tip deflection (mm)\nover the metrics window")
    ax.set_title(title, fontsize=10.5)
    ax.grid(True, which="major", alpha=0.35)
    ax.grid(True, which="minor", alpha=0.12)
    ax_s.set_ylabel("time in stick (%)\nover the metrics window")
    ax_s.set_xlabel(x_label)
    ax_s.set_ylim(-2, 102)
    ax_s.grid(True, which="major", alpha=0.35)
    ax_s.legend(fontsize=8, loc="upper right")
    # The map's legend goes below the axes, where it hides no point.
    handles, labels = ax.get_legend_handles_labels()
    legend_height = 0.2 + 0.165 * len(labels)  # inches, one entry per line at 8 pt
    fig.set_size_inches(10, 8.5 + legend_height)
    fig.legend(handles, labels, loc="lower center", ncol=1, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, legend_height / (8.5 + legend_height), 1, 1))
    fig.savefig(path, dpi=120)
    plt.close(fig)


# ----------------------------------------------------------------------------- command line


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="sweep.py",
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
    p.add_argument("--fidelity", default="modal", choices=list(_scene().FIDELITY))
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
        "--out", type=Path, default=_scene().REPO / "out", help="output folder (default <repo>/out)"
    )
    p.add_argument(
        "--name",
        default=DEFAULT_BASENAME,
        help=f"basename of the CSV and PNG (default {DEFAULT_BASENAME})",
    )
    p.add_argument("--list", action="store_true", help="print the settable parameters and exit")
    return p


def default_cases(catalogue: Catalogue) -> list[tuple[str, dict]]:
    """The map's cases: two dampings from the quasi-static start, and 2 % from rest.

    The FMU's default damping (b = 5e-5 s, stiffness-proportional only) damps mode 1 by
    0.09 %; the physics notes' 2 % Rayleigh damping at modes 1 and 3 is the other case.
    Stick-slip and steady sliding can both be stable at one belt speed, so the start
    matters: the quasi-static start (tip moving with the belt, paper scene) begins in
    stick and breaks away at 8 mm. The start at rest (beam at rest, belt moving) breaks
    away in the first step above ~0.03 m/s and slides from zero deflection, only
    mu(v_b) F_n / k = 3.2 mm from the steady-sliding state. The CSV holds each case's
    parameter values.
    """
    defaults = catalogue.defaults()
    b = defaults["damping.stiffness_proportional"]
    rayleigh = rayleigh_damping(defaults)
    percent = f"{100 * RAYLEIGH_RATIO:g} % Rayleigh"
    return [
        (f"default damping b = {b:g} s", {}),
        (percent, rayleigh),
        (f"{percent}, start at rest", {**rayleigh, "contact.initial_state": "at-rest"}),
    ]


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
    args = _parser().parse_args(argv)
    try:
        fmu = beam_fmu(None)
        catalogue = Catalogue(fmu)
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
        raise SystemExit(f"sweep.py: {error}") from None

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
    plot_map(rows, x_name, x_label, log_x, series, stability, stops, title, png_path)
    print(f"wrote {csv_path}")
    print(f"wrote {png_path}")
    print(f"wall time {wall:.1f} s for the runs ({time.perf_counter() - began:.1f} s in all)")
    return 0 if not any(r["regime"] == FAILED for r in rows) else 1


if __name__ == "__main__":
    # Run through the importable module so that Dask pickles `sweep.FmuWorkerPlugin` by
    # reference: its workers import sweep.py (it is on their sys.path) instead of
    # receiving by-value copies of __main__.
    import sweep

    sys.exit(sweep.main())
