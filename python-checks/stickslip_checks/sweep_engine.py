"""The sweep engine: StickSlipBeam.fmu run once per parameter set, on Dask or in this
process, each run reduced to its row (stick_slip_map.run_metrics).

Why Dask: a map is tens of independent runs. A LocalCluster of worker processes uses
every core of this machine; `scheduler="tcp://host:port"` sends the same tasks to an
existing cluster instead. Its scheduler and workers need this package installed
(`pip install <repo>/python-checks`, with numpy, fmpy and distributed), as any Dask
cluster needs the client's environment.

Loading: a WorkerPlugin carries the FMU's bytes to every worker. Its setup unpacks the
archive, loads the shared library and calls fmi2Instantiate once per worker process; each
task then only calls fmi2Reset, sets its parameters, initialises and steps (through the
co-simulation master, master.run). Every result row says which worker ran it and how
often that worker has loaded the FMU, so a test can check "loaded once per worker, not
once per task". A worker runs its tasks one at a time on its single instance (a lock
guards it if the worker has several threads).
"""

from __future__ import annotations

import hashlib
import importlib.util
import math
import os
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path

from distributed.diagnostics.plugin import WorkerPlugin

from . import master
from .artifacts import BEAM, Fmu, fmu_paths
from .parameters import Catalogue, SweepError
from .stick_slip_map import DEFAULT_WINDOW, FAILED, run_metrics

DEFAULT_T_END = 20.0  # s: the slowest map speed breaks away at 1.6 s; see MAP_SPEEDS
DEFAULT_STEP = 1e-3  # s: communication step and sampling interval of the outputs


def default_workers() -> int:
    """One worker per core this process may run on (its CPU affinity where the OS has
    one, else the machine's cores)."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


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
        fmu = Fmu(archive, folder)
        slave = fmu.slave(f"sweep-{self.digest[:8]}")
        slave.instantiate()
        self._runtime = dict(
            fmu=fmu,
            system=master.System({BEAM: fmu.model}, {BEAM: slave}),
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
            runtime["system"].slaves[BEAM].freeInstance()
        finally:
            runtime["fmu"].close()

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
    system = rt["system"]
    # fmi2Reset returns the instance to its state right after instantiation: the start
    # values, no experiment. It is also the way out of an earlier run's error state.
    system.slaves[BEAM].reset()
    trace = master.run(
        system,
        step,
        t_end,
        parameters={BEAM: {"fidelity.level": fidelity, **params}},
        record={BEAM: ["tip_deflection", "stick", "transitions"]},
    )
    u = trace[BEAM, "tip_deflection"]  # m
    stick = trace[BEAM, "stick"]
    transitions = trace[BEAM, "transitions"]  # stick/slip transitions so far, both directions
    row = run_metrics(trace.time, u, stick, transitions, window)
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


def _check_cluster(client, scheduler: str) -> None:
    """SweepError unless the scheduler (it unpickles the task graph) and every worker of
    an existing cluster can import this package."""
    package = __package__

    def can_import(dask_scheduler=None) -> bool:
        # A local function travels by value (cloudpickle), so a process without this
        # package can run it.
        return importlib.util.find_spec(package) is not None

    found = {f"the scheduler {scheduler}": client.run_on_scheduler(can_import)}
    found.update((f"the worker {w}", ok) for w, ok in client.run(can_import).items())
    missing = [where for where, ok in found.items() if not ok]
    if missing:
        raise SweepError(
            f"{' and '.join(missing)} cannot import {package}: install it there "
            "(pip install <repo>/python-checks), as numpy, fmpy and distributed"
        )


def _worker_loads(plugin_name: str, dask_worker=None) -> int:
    """Loads of `plugin_name` on this worker (for Client.run)."""
    plugin = dask_worker.plugins.get(plugin_name)
    return -1 if plugin is None else plugin.loads


# ----------------------------------------------------------------------------- running


# Called after each finished run: (runs done, runs in all, the run's row).
Progress = Callable[[int, int, dict], None]


class SweepResults(list):
    """The rows of a sweep, in the order of the parameter sets, plus the FMU loads.

    `loads` maps each worker (its address, or "in-process") to how often it loaded the FMU
    during this sweep.
    """

    loads: dict[str, int]


def _check_sets(param_sets, fidelity: str, t_end: float, step: float, window: float, fmu: Path):
    """Validated copies of the parameter sets (canonical names, typed values)."""
    catalogue = Catalogue(fmu)
    levels = catalogue.fidelities
    if fidelity not in levels:
        raise SweepError(f"unknown fidelity '{fidelity}'; one of {', '.join(levels)}")
    if not (t_end > 0 and step > 0 and math.isfinite(t_end)):
        raise SweepError(f"t_end ({t_end} s) and step ({step} s) must be > 0")
    n = round(t_end / step)
    if n < 3 or abs(n * step - t_end) > 1e-9 * t_end:
        raise SweepError(f"t_end {t_end} s must be a multiple (>= 3) of the step {step} s")
    if not 0 < window <= 1:
        raise SweepError(f"window {window} must be in (0, 1]")
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
    """`fmu`, else StickSlipBeam.fmu where artifacts.fmu_paths() finds it; SweepError if
    it is missing (the message says how to build it)."""
    try:
        return Path(fmu) if fmu is not None else fmu_paths()[BEAM]
    except FileNotFoundError as error:
        raise SweepError(str(error)) from None


def run_serial(
    param_sets,
    fidelity: str = "modal",
    t_end: float = DEFAULT_T_END,
    step: float = DEFAULT_STEP,
    window: float = DEFAULT_WINDOW,
    fmu: Path | None = None,
    progress: Progress | None = None,
) -> SweepResults:
    """The same runs in this process, one after the other, on one FMU instance."""
    fmu = beam_fmu(fmu)
    sets = _check_sets(param_sets, fidelity, t_end, step, window, fmu)
    plugin = FmuWorkerPlugin(fmu)
    plugin.setup()
    try:
        results = SweepResults()
        for done, params in enumerate(sets, start=1):
            results.append(plugin.simulate(params, fidelity, t_end, step, window))
            if progress is not None:
                progress(done, len(sets), results[-1])
    finally:
        plugin.teardown()
    results.loads = {"in-process": plugin.loads}
    return results


def run_sweep(
    param_sets,
    fidelity: str = "modal",
    t_end: float = DEFAULT_T_END,
    scheduler: str | None = None,
    workers: int | None = None,
    step: float = DEFAULT_STEP,
    window: float = DEFAULT_WINDOW,
    fmu: Path | None = None,
    progress: Progress | None = None,
) -> SweepResults:
    """Runs StickSlipBeam.fmu once per parameter set on Dask; the rows in input order.

    param_sets: list of {parameter name: value} (names and enumeration words as in the
    model description; loading.belt_speed / loading.normal_force are accepted aliases).
    scheduler: address of an existing Dask scheduler; None starts a LocalCluster of
    `workers` (default: default_workers()) single-threaded worker processes on 127.0.0.1
    (no dashboard), closed after. `progress` is called as each run finishes.
    """
    fmu = beam_fmu(fmu)
    sets = _check_sets(param_sets, fidelity, t_end, step, window, fmu)
    from distributed import Client, LocalCluster, as_completed

    cluster = None
    if scheduler is None:
        workers = default_workers() if workers is None else workers
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
            _check_cluster(client, scheduler)
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
        if progress is not None:
            for done, future in enumerate(as_completed(futures), start=1):
                progress(done, len(futures), future.result())
        results = SweepResults(client.gather(futures))
        results.loads = client.run(_worker_loads, plugin.name)
        # Free the instances on the workers of an existing cluster (a LocalCluster goes anyway).
        client.unregister_worker_plugin(plugin.name)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return results
