"""The co-simulation master: FMU2Slave instances (fmpy) connected output -> input,
stepped at a fixed communication step h with a Jacobi or a Gauss-Seidel scheme.

Every script that steps an FMU itself runs it through `run`: the coupled
StickSlipBeam + NeuralFriction system (fmu_scene, cosim_convergence), the monolithic
beam (cosim_convergence, the sweep's workers) and NeuralFriction driven by an input
signal (fmu_scene's friction-law sweeps, training's test set).

Communication points are t_k = k h (no running sum). Inputs are held over a step
(zero-order hold). At initialisation, and again after it, the outputs are exchanged in
the system's dependency order (StickSlipBeam -> NeuralFriction -> StickSlipBeam for the
coupled pair), so both FMUs start from consistent inputs: NeuralFriction has direct
feedthrough (no state), its outputs follow its inputs.

Schemes (the pair: beam relative_velocity -> friction sliding_velocity; friction
friction_force_magnitude and static_limit -> beam external.kinetic_force and
external.static_limit; with the signed coupling also friction_force,
friction_force_slope and evaluated_velocity -> beam external.friction_force,
external.friction_slope and external.sliding_velocity, see COUPLINGS):

- Jacobi: at t_k every FMU reads the others' outputs at t_k, then all step. The
  friction FMU's output at t_k is the law at the input it held over the previous step,
  v_rel(t_{k-1}): over [t_k, t_{k+1}] the beam sees F(v_rel(t_{k-1})), one step late.
- Gauss-Seidel: the FMUs step one after the other in the given order, and each one's
  outputs go to the inputs linked to them as soon as it has stepped. Beam first: the
  beam steps with F(v_rel(t_k)); the friction FMU then gets v_rel(t_{k+1}) and its force
  goes back to the beam for the next step. For a stateless friction FMU, friction first
  gives the same numbers (it is evaluated at v_rel(t_k) either way).
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

from .artifacts import BEAM, FRICTION

JACOBI = "Jacobi"
GAUSS_SEIDEL = "Gauss-Seidel"
SCHEMES = (JACOBI, GAUSS_SEIDEL)


@dataclass(frozen=True)
class Link:
    """Output `output` of FMU `source` feeds input `input` of FMU `target` (Real values)."""

    source: str
    output: str
    target: str
    input: str


# StickSlipBeam with friction.law = external, coupled to NeuralFriction.
BEAM_FRICTION_LINKS = (
    Link(BEAM, "relative_velocity", FRICTION, "sliding_velocity"),
    Link(FRICTION, "friction_force_magnitude", BEAM, "external.kinetic_force"),
    Link(FRICTION, "static_limit", BEAM, "external.static_limit"),
)
# The same with the signed law's tangent: value, slope and the velocity they hold at.
BEAM_FRICTION_SIGNED_LINKS = (
    *BEAM_FRICTION_LINKS,
    Link(FRICTION, "friction_force", BEAM, "external.friction_force"),
    Link(FRICTION, "friction_force_slope", BEAM, "external.friction_slope"),
    Link(FRICTION, "evaluated_velocity", BEAM, "external.sliding_velocity"),
)
# The same with the step-consistent tangent of a law with state besides (issue 36):
# the force after one communication step at the velocity held and its slope.
BEAM_FRICTION_STEP_LINKS = (
    *BEAM_FRICTION_SIGNED_LINKS,
    Link(FRICTION, "step_friction_force", BEAM, "external.step_force"),
    Link(FRICTION, "step_friction_slope", BEAM, "external.step_slope"),
    # The step's mean sliding velocity, which commits a law's state (NeuralFriction's
    # state_velocity = auto); Gauss-Seidel hands over the step's own,
    # Jacobi the previous step's.
    Link(BEAM, "mean_relative_velocity", FRICTION, "mean_sliding_velocity"),
)
# How many fixed velocities the table coupling tabulates both curves at
# (stickslip::friction::tabulated::TABLE_VELOCITIES; the FMUs' variables
# table_friction_force_i and external.table_force_i, i = 0 .. TABLE_NODES - 1).
TABLE_NODES = 11
# The same with both force curves of a law with state tabulated (issue 36): the
# instantaneous and the one-step curve at each node.
BEAM_FRICTION_TABLE_LINKS = (
    *BEAM_FRICTION_STEP_LINKS,
    *(
        link
        for i in range(TABLE_NODES)
        for link in (
            Link(FRICTION, f"table_friction_force_{i}", BEAM, f"external.table_force_{i}"),
            Link(FRICTION, f"table_step_friction_force_{i}", BEAM, f"external.table_step_force_{i}"),
        )
    ),
)
# StickSlipBeam's external.coupling -> the links it reads. `magnitude` suits laws
# sign(v) g(|v|) (the exponential law, the signed network); `signed` smooth signed laws
# (the paper's plain network); `table` (the SSP systems') and `step` laws with state
# (LuGre, rate-and-state, the learned law with memory).
COUPLINGS = {
    "magnitude": BEAM_FRICTION_LINKS,
    "signed": BEAM_FRICTION_SIGNED_LINKS,
    "step": BEAM_FRICTION_STEP_LINKS,
    "table": BEAM_FRICTION_TABLE_LINKS,
}
# Dependency order of the pair: the friction FMU's outputs follow the beam's.
BEAM_FRICTION_ORDER = (BEAM, FRICTION)


@dataclass
class Trace:
    """Recorded outputs at the communication points: trace[fmu, name] is an array over
    `time`; Real as float, Boolean as bool, Integer (and choices) as int64."""

    time: np.ndarray
    values: dict

    def __getitem__(self, key: tuple[str, str]) -> np.ndarray:
        return self.values[key]


class System:
    """Instantiated FMU2Slaves by name, their models (artifacts.Model), the links between
    them and the dependency order for the initial exchange (default: the slaves' order)."""

    def __init__(self, models: dict, slaves: dict, links=(), order=None):
        self.models = models
        self.slaves = slaves
        self.order = tuple(order or slaves)
        self.links = tuple(links)
        for link in self.links:
            for fmu, name in ((link.source, link.output), (link.target, link.input)):
                if models[fmu].kind(name) != "Real":
                    raise ValueError(f"link {link}: {fmu}.{name} is not a Real variable")
        # Per (source, target) pair: the value references read from the source at once
        # and written to the target at once.
        self._feeds: dict[str, list] = {name: [] for name in slaves}
        pairs: dict[tuple[str, str], tuple[list, list]] = {}
        for link in self.links:
            outs, ins = pairs.setdefault((link.source, link.target), ([], []))
            outs.append(models[link.source].vr[link.output])
            ins.append(models[link.target].vr[link.input])
        for (source, target), (outs, ins) in pairs.items():
            self._feeds[source].append((target, outs, ins))

    def feed(self, source: str) -> None:
        """The current outputs of `source` into the inputs linked to them."""
        for target, outs, ins in self._feeds[source]:
            self.slaves[target].setReal(ins, self.slaves[source].getReal(outs))

    def exchange(self) -> None:
        """Every FMU's outputs to its linked inputs, in dependency order."""
        for name in self.order:
            self.feed(name)

    def jacobi_exchange(self) -> None:
        """Every linked output read first, then every input set: all from the same instant."""
        pending = [
            (target, ins, self.slaves[source].getReal(outs))
            for source in self.order
            for target, outs, ins in self._feeds[source]
        ]
        for target, ins, values in pending:
            self.slaves[target].setReal(ins, values)


@contextmanager
def instantiated(fmus, instances: dict[str, str]):
    """{fmu name: FMU2Slave}, instantiated (instance names as given), freed on exit."""
    slaves = {name: fmus.slave(name, instance) for name, instance in instances.items()}
    for slave in slaves.values():
        slave.instantiate()
    try:
        yield slaves
    finally:
        for slave in slaves.values():
            slave.freeInstance()


def grid(h: float, t_end: float) -> tuple[int, np.ndarray]:
    """Number of steps and the communication points k h, k = 0 .. n."""
    n = int(round(t_end / h))
    return n, np.arange(n + 1) * h


# How a master counts time: our masters step from k h by h ("float"); libcosim counts in
# integer nanoseconds and gives t_k = (k h_ns) / 1e9 and the step t_k+1 - t_k in double
# (its to_double_time_point and to_double_duration), which is h only to rounding.
CLOCKS = ("float", "nanoseconds")


def step_sizes(h: float, times: np.ndarray, clock: str) -> tuple[np.ndarray, np.ndarray]:
    """The communication points and step sizes of `clock` on the grid `times`."""
    if clock == "float":
        return times, np.full(len(times) - 1, h)
    if clock == "nanoseconds":
        ns = round(h * 1e9)
        points = np.array([(k * ns) / 1e9 for k in range(len(times))])
        return points, np.diff(points)
    raise ValueError(f"unknown clock {clock!r}; one of {', '.join(CLOCKS)}")


def run(
    system: System,
    h: float,
    t_end: float,
    *,
    record: dict[str, list[str]],
    parameters: dict[str, dict] | None = None,
    scheme: str = GAUSS_SEIDEL,
    order=None,
    signals: dict[str, dict[str, np.ndarray]] | None = None,
    stop_time: bool = True,
    clock: str = "float",
) -> Trace:
    """Initialises the (instantiated or reset) slaves of `system`, steps them from 0 to
    t_end at h with `scheme` and terminates them.

    parameters: {fmu: {name: value}} set in initialisation mode (choices by item name).
    order: stepping order of Gauss-Seidel (default: the system's dependency order).
    signals: {fmu: {input: values}}, values[k] set before the step from t_k.
    record: {fmu: [names]} read at t_0 and after every step.
    stop_time: pass t_end to fmi2SetupExperiment as the stop time.
    """
    if scheme not in SCHEMES:
        raise ValueError(f"unknown scheme {scheme!r}; one of {', '.join(SCHEMES)}")
    slaves, models = system.slaves, system.models
    order = tuple(order or system.order)
    n, times = grid(h, t_end)
    points, sizes = step_sizes(h, times, clock)
    recorders = []
    values = {}
    dtypes = {"Real": float, "Boolean": bool, "Integer": np.int64, "String": object}
    for fmu, names in record.items():
        for name in names:
            array = np.empty(n + 1, dtypes[models[fmu].kind(name)])
            values[fmu, name] = array
            recorders.append((array, models[fmu].getter(slaves[fmu], name)))
    inputs = [
        (models[fmu], slaves[fmu], name, series)
        for fmu, named in (signals or {}).items()
        for name, series in named.items()
    ]

    def sample(k: int) -> None:
        for array, read in recorders:
            array[k] = read()

    for name in system.order:
        if stop_time:
            slaves[name].setupExperiment(startTime=0.0, stopTime=t_end)
        else:
            slaves[name].setupExperiment(startTime=0.0)
        slaves[name].enterInitializationMode()
    for fmu, named in (parameters or {}).items():
        models[fmu].set(slaves[fmu], named)
    # Consistent start: outputs at t = 0 -> linked inputs, in dependency order.
    system.exchange()
    for name in system.order:
        slaves[name].exitInitializationMode()
    system.exchange()
    sample(0)
    for k in range(n):
        t, size = points[k], sizes[k]
        for model, slave, name, series in inputs:
            model.set(slave, {name: series[k]})
        if scheme == JACOBI:
            system.jacobi_exchange()
            for name in order:
                slaves[name].doStep(currentCommunicationPoint=t, communicationStepSize=size)
        else:
            for name in order:
                slaves[name].doStep(currentCommunicationPoint=t, communicationStepSize=size)
                system.feed(name)
        sample(k + 1)
    for name in system.order:
        slaves[name].terminate()
    return Trace(times, values)


def run_alone(fmus, name: str, instance: str, h: float, t_end: float, **options) -> Trace:
    """FMU `name` of `fmus` (artifacts.Fmus) by itself, instantiated as `instance` for this
    run; `options` as for `run`."""
    with instantiated(fmus, {name: instance}) as slaves:
        return run(System({name: fmus.models[name]}, slaves), h, t_end, **options)


def run_coupled(
    fmus,
    h: float,
    t_end: float,
    *,
    beam: dict,
    friction: dict,
    record: dict[str, list[str]],
    scheme: str = GAUSS_SEIDEL,
    order=BEAM_FRICTION_ORDER,
    coupling: str = "magnitude",
    clock: str = "float",
) -> Trace:
    """StickSlipBeam (friction.law = external, external.coupling = `coupling`,
    parameters `beam`) coupled to NeuralFriction (parameters `friction`) through
    COUPLINGS[coupling], both instantiated for this run; the normal force of both stays
    at its start value."""
    if coupling not in COUPLINGS:
        raise ValueError(f"unknown coupling {coupling!r}; one of {', '.join(COUPLINGS)}")
    with instantiated(fmus, {BEAM: "beam", FRICTION: "friction"}) as slaves:
        system = System(fmus.models, slaves, COUPLINGS[coupling], BEAM_FRICTION_ORDER)
        return run(
            system,
            h,
            t_end,
            scheme=scheme,
            order=order,
            parameters={
                BEAM: {**beam, "friction.law": "external", "external.coupling": coupling},
                FRICTION: friction,
            },
            record=record,
            clock=clock,
        )
