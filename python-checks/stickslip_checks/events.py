"""Co-simulation with FMI 3.0 events (issue 15, item 3): StickSlipBeam + NeuralFriction
(the FMI 3.0 FMUs, <fmu dir>/3.0/) coupled by a Gauss-Seidel master that lets the beam end
a step at a stick/slip switch, against the FMI 2.0 Gauss-Seidel master of
cosim_convergence at the same communication step h.

Set-up (as cosim_convergence's "plain, GS signed" row): StickSlipBeam at beam fidelity,
internal step 1e-4 s, friction.law = external with the signed coupling
(external.coupling = signed: friction_force, friction_force_slope, evaluated_velocity,
static_limit and friction_force_magnitude wired by master.COUPLINGS["signed"]);
NeuralFriction with the paper's plain network. Reference: StickSlipBeam alone with the
same network embedded, at h = 1e-4 s (cosim_convergence.run_monolithic). Error: max
|tip deflection coupled - monolithic| at the communication points up to 0.7 s and up
to 1.2 s (cosim_convergence.max_error).

Masters (t_k = k h, inputs held over a step; beam first, then the stateless friction
FMU, as cosim_convergence's Gauss-Seidel):
    FMI 2.0 GS          cosim_convergence.run_cosim("plain, GS signed").
    FMI 3.0 GS          the same master over the FMI 3.0 FMUs, instantiated without
                        early return and event mode: must equal FMI 2.0 GS bit for bit.
    FMI 3.0 early return
                        earlyReturnAllowed: when the beam's fmi3DoStep returns early at a
                        switch at t_s (lastSuccessfulTime), the friction FMU is stepped to
                        t_s, the values are exchanged there (beam -> friction ->
                        beam), and the beam goes on from t_s to t_{k+1} (possibly
                        returning early again).
    FMI 3.0 event mode  eventModeUsed and earlyReturnAllowed: the same, but the exchange
                        at t_s happens in the beam's Event Mode (fmi3EnterEventMode,
                        inputs set, fmi3UpdateDiscreteStates, fmi3EnterStepMode), as does
                        the initial exchange (fmi3ExitInitializationMode enters Event
                        Mode). A switch at the end of a step (no early return) is an event
                        too, handled at t_{k+1}.

Only the beam has events; NeuralFriction is instantiated with the same flags (it has
Event Mode but never returns early), and the master enters Event Mode only for the FMU
that asked for it.

The library of the cosim_events entry point; its checks (FMI 3.0 without events equal
to FMI 2.0 bit for bit, event mode equal to early return) are tests/test_cosim_events.py's.
"""

from __future__ import annotations

import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

from . import master
from .artifacts import BEAM, FRICTION, Fmus
from .convergence import (
    FIDELITY_LEVEL,
    INTERNAL_STEP,
    LAWS,
    PLAIN,
    STEPS,
    T_END,
    T_FIRST_CYCLE,
    Series,
    max_error,
    run_cosim,
    run_monolithic,
)
from .tables import format_table, frame, write_csv

if TYPE_CHECKING:
    import pandas as pd

FMI2_GS = "FMI 2.0 GS"
FMI3_GS = "FMI 3.0 GS"
EARLY_RETURN = "FMI 3.0 early return"
EVENT_MODE = "FMI 3.0 event mode"
MASTERS = (FMI2_GS, FMI3_GS, EARLY_RETURN, EVENT_MODE)
# The FMI 3.0 masters: (eventModeUsed, earlyReturnAllowed).
FLAGS = {FMI3_GS: (False, False), EARLY_RETURN: (False, True), EVENT_MODE: (True, True)}
COUPLING = "signed"
LAW = PLAIN


class Slave3:
    """An FMU3Slave under the FMI 2.0 names master.System and artifacts.Model call
    (getReal, setInteger, ...): value references and choices are the same in both
    versions' descriptions, so the FMI 2.0 model description's Model serves both."""

    def __init__(self, slave: FMU3Slave):
        self.fmu = slave

    def getReal(self, vrs):
        return self.fmu.getFloat64(list(vrs))

    def setReal(self, vrs, values):
        self.fmu.setFloat64(list(vrs), [float(v) for v in values])

    def getInteger(self, vrs):
        return self.fmu.getInt32(list(vrs))

    def setInteger(self, vrs, values):
        self.fmu.setInt32(list(vrs), [int(v) for v in values])

    def getBoolean(self, vrs):
        return self.fmu.getBoolean(list(vrs))

    def setBoolean(self, vrs, values):
        self.fmu.setBoolean(list(vrs), [bool(v) for v in values])

    def getString(self, vrs):
        return self.fmu.getString(list(vrs))

    def setString(self, vrs, values):
        self.fmu.setString(list(vrs), list(values))


@dataclass
class EventRun(Series):
    """A coupled FMI 3.0 run: the Series at the communication points, plus the times at
    which the beam reported a switch (early return or event) and the number of beam
    steps the master made."""

    switches: list = field(default_factory=list)
    beam_steps: int = 0


def run_events(
    fmus: Fmus, paths3: dict, label: str, h: float, t_end: float = T_END
) -> EventRun:
    """The coupled pair through the FMI 3.0 FMUs at communication step h with the master
    `label` (a key of FLAGS). `fmus` (the FMI 2.0 FMUs) supplies the value references and
    choice codes."""
    event_mode, early_return = FLAGS[label]
    n, times = master.grid(h, t_end)
    unpacked = {}
    slaves = {}
    for name, path in paths3.items():
        model = fmus.models[name]
        description = read_model_description(str(path))
        unpacked[name] = extract(str(path))
        slave = FMU3Slave(
            guid=description.guid,
            unzipDirectory=unpacked[name],
            modelIdentifier=model.identifier,
            instanceName=f"{name}-{label}",
        )
        slave.instantiate(eventModeUsed=event_mode, earlyReturnAllowed=early_return)
        slaves[name] = slave
    try:
        return _couple(fmus, slaves, label, h, n, times, event_mode)
    finally:
        for slave in slaves.values():
            slave.freeInstance()
        for folder in unpacked.values():
            shutil.rmtree(folder, ignore_errors=True)


def _couple(fmus, slaves3, label, h, n, times, event_mode) -> EventRun:
    models = fmus.models
    beam3, friction3 = slaves3[BEAM], slaves3[FRICTION]
    slaves = {name: Slave3(s) for name, s in slaves3.items()}
    system = master.System(models, slaves, master.COUPLINGS[COUPLING], master.BEAM_FRICTION_ORDER)
    beam_params, friction_params = LAWS[LAW]
    del beam_params  # the coupled beam runs the external law
    began = time.perf_counter()
    t_end = times[-1]
    for s in slaves3.values():
        s.enterInitializationMode(startTime=0.0, stopTime=t_end)
    models[BEAM].set(
        slaves[BEAM],
        {"fidelity.level": FIDELITY_LEVEL, "friction.law": "external", "external.coupling": COUPLING},
    )
    models[FRICTION].set(slaves[FRICTION], friction_params)
    system.exchange()
    for s in slaves3.values():
        s.exitInitializationMode()
    system.exchange()
    if event_mode:
        # fmi3ExitInitializationMode entered Event Mode: the inputs are consistent, no
        # discrete state to settle; on to Step Mode.
        for s in slaves3.values():
            s.updateDiscreteStates()
            s.enterStepMode()
    read_u = models[BEAM].getter(slaves[BEAM], "tip_deflection")
    read_stick = models[BEAM].getter(slaves[BEAM], "stick")
    deflection = np.empty(n + 1)
    stick = np.empty(n + 1, bool)
    deflection[0], stick[0] = read_u(), read_stick()
    switches = []
    beam_steps = 0
    for k in range(n):
        t, target = times[k], times[k + 1]
        while True:
            event, _, early, last = beam3.doStep(t, target - t)
            beam_steps += 1
            reached = last if early else target
            if event:
                beam3.enterEventMode()
            system.feed(BEAM)
            friction3.doStep(t, reached - t)
            system.feed(FRICTION)
            if event:
                beam3.updateDiscreteStates()
                beam3.enterStepMode()
            if early or event:
                switches.append(float(reached))
            t = reached
            if not early:
                break
        deflection[k + 1], stick[k + 1] = read_u(), read_stick()
    for s in slaves3.values():
        s.terminate()
    wall = time.perf_counter() - began
    return EventRun(label, h, times, deflection, stick, wall, switches, beam_steps)


def run_fmi2(fmus: Fmus, h: float, t_end: float = T_END) -> Series:
    series = run_cosim(fmus, "plain, GS signed", h, t_end)
    series.scheme = FMI2_GS
    return series


def monolithic_switches(fmus: Fmus, t_end: float = T_END) -> list[float]:
    """The monolithic run's stick/slip transitions (s): StickSlipBeam alone with the plain
    network at h = the internal step, where its `transitions` count steps up."""
    beam, _ = LAWS[LAW]
    trace = master.run_alone(
        fmus,
        BEAM,
        "monolithic-switches",
        INTERNAL_STEP,
        t_end,
        parameters={BEAM: {"fidelity.level": FIDELITY_LEVEL, **beam}},
        record={BEAM: ["transitions"]},
    )
    counts = trace[BEAM, "transitions"]
    steps = np.flatnonzero(np.diff(counts))
    if np.any(np.diff(counts) > 1):
        raise ValueError("more than one transition in one internal step")
    return [float(trace.time[i + 1]) for i in steps]


@dataclass
class Row:
    h: float
    master: str
    error_first_cycle: float  # m, to 0.7 s
    error_full: float  # m, to 1.2 s
    switches: int
    beam_steps: int
    wall: float


def run_study(fmus: Fmus, paths3: dict, steps=STEPS, masters=MASTERS, t_end: float = T_END):
    """(reference, runs by (master, h), rows)."""
    reference = run_monolithic(fmus, INTERNAL_STEP, t_end, LAW)
    runs = {}
    rows = []
    for h in steps:
        for label in masters:
            run = run_fmi2(fmus, h, t_end) if label == FMI2_GS else run_events(fmus, paths3, label, h, t_end)
            runs[label, h] = run
            rows.append(
                Row(
                    h,
                    label,
                    max_error(run, reference, min(T_FIRST_CYCLE, t_end)),
                    max_error(run, reference, t_end),
                    len(getattr(run, "switches", [])),
                    getattr(run, "beam_steps", int(round(t_end / h))),
                    run.wall,
                )
            )
    return reference, runs, rows


HEADERS = ["h [s]", "master", f"error to {T_FIRST_CYCLE} s [mm]", f"error to {T_END} s [mm]",
           "switches", "beam steps", "wall [s]"]


def table(rows: list[Row]) -> str:
    cells = [
        [
            f"{r.h:.0e}", r.master, f"{1e3 * r.error_first_cycle:.5f}",
            f"{1e3 * r.error_full:.5f}", str(r.switches), str(r.beam_steps), f"{r.wall:.2f}",
        ]
        for r in rows
    ]
    return format_table(HEADERS, cells, left={1})


def csv_rows(rows: list[Row]) -> list[list]:
    return [
        [repr(r.h), r.master, repr(1e3 * r.error_first_cycle), repr(1e3 * r.error_full),
         r.switches, r.beam_steps, repr(r.wall)]
        for r in rows
    ]


def to_frame(rows: list[Row]) -> pd.DataFrame:
    """The rows of cosim_events.csv as a DataFrame."""
    return frame(HEADERS, csv_rows(rows)).astype({h: float for h in HEADERS if h != "master"})


def switch_lines(runs: dict, mono: list[float]) -> list[str]:
    """The monolithic FMU's switches up to T_FIRST_CYCLE, and those the event-mode master
    reported at every h."""
    first = [t for t in mono if t <= T_FIRST_CYCLE]
    lines = [f"monolithic switches up to {T_FIRST_CYCLE} s: {', '.join(f'{t:.4f}' for t in first)}"]
    for h in STEPS:
        got = [t for t in runs[EVENT_MODE, h].switches if t <= T_FIRST_CYCLE]
        lines.append(f"  event mode h = {h:g}: {', '.join(f'{t:.4f}' for t in got)}")
    return lines


def write_outputs(rows: list[Row], out: Path) -> Path:
    """cosim_events.csv in `out`."""
    path = out / "cosim_events.csv"
    write_csv(path, HEADERS, csv_rows(rows))
    return path
