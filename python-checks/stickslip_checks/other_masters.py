"""Our FMUs and the SSP systems fmu-build writes, run in other co-simulation masters the
way their users run them:

- libcosim (libcosimpy): `CosimExecution.from_ssp_file` on an `.ssp`, or an execution
  with `CosimLocalSlave`s for a bare FMU;
- Ecos (ecospy): `EcosSimulation(ssp_path=...)` on an `.ssp`, or an
  `EcosSimulationStructure` for a bare FMU, with named parameter sets;
- fmucontainer (fmu-manipulation-toolbox): its command line builds a container FMU from
  the link list fmu-build writes (`<system>.csv`), which fmpy then runs;
- fmpy's SSP runner (`fmpy.ssp.simulation.simulate_ssp`).

Every runner returns a `Series`: the recorded outputs at communication points k h, with
the grid index k of each sample, so that it can be compared point by point with our own
master (`master.py`). h = 1e-3 s is exact in libcosim's integer nanoseconds.

compare_coupled runs the coupled system in each master against our Jacobi and
Gauss-Seidel masters (the library of the masters entry point; that each master equals
ours bit for bit is tests/test_masters.py's check).
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import artifacts, master
from .artifacts import BEAM, FRICTION
from .tables import format_table, frame, write_csv

if TYPE_CHECKING:
    import pandas as pd

H = 1e-3
# Past the breakaway at 0.4 s and into the first slip, where the schemes part.
T_END = 0.7
# The SSP systems and link lists fmu-build writes (fmu_build::ssp::systems), and the
# parameter set name every component carries (fmu_build::ssp::PARAMETER_SET).
COUPLED = "StickSlipCoupled"
# COUPLED with NeuralFriction running the shipped learned law with memory (issue 24).
COUPLED_MEMORY = "StickSlipCoupledMemory"
# COUPLED with NeuralFriction running law = rate-and-state and law = lugre at their
# default parameters (fmu_build::ssp::coupled_rate_and_state, coupled_lugre).
COUPLED_RATE_STATE = "StickSlipCoupledRateState"
COUPLED_LUGRE = "StickSlipCoupledLuGre"
# What each coupled system sets on NeuralFriction (fmu_build::ssp::coupled_with_memory,
# coupled_rate_and_state, coupled_lugre).
FRICTION_SETTINGS = {
    COUPLED: {},
    COUPLED_MEMORY: {"weights": "rate-and-state-learned.json"},
    COUPLED_RATE_STATE: {"law": "rate-and-state"},
    COUPLED_LUGRE: {"law": "lugre"},
}
# StickSlipBeam's external.coupling in each coupled system (the SSD's): both force
# curves tabulated for a law with state (issue 36).
COUPLING_OF = {COUPLED: "signed", COUPLED_MEMORY: "table", COUPLED_RATE_STATE: "table", COUPLED_LUGRE: "table"}
# The law's state output each coupled system is compared on besides the tip deflection
# (NeuralFriction's STATE_VARIABLES outputs; the others keep them at 0).
STATE_OF = {COUPLED_RATE_STATE: ("friction", "state_theta"), COUPLED_LUGRE: ("friction", "bristle_deflection")}
MONOLITHIC = "StickSlipMonolithic"
PARAMETER_SET = "initialValues"
# Instance names of the components in those systems.
INSTANCES = {BEAM: "beam", FRICTION: "friction"}
NANOSECONDS = 1_000_000_000


def ssp_path(system: str) -> Path:
    """target/fmu/2.0/<system>.ssp (next to the FMI 2.0 FMUs it embeds);
    FileNotFoundError with the build command if missing."""
    path = artifacts.fmu_dir() / f"{system}.ssp"
    if not path.is_file():
        raise FileNotFoundError(f"missing {path}: {artifacts.BUILD_HINT}")
    return path


def csv_path(system: str) -> Path:
    """target/fmu/2.0/<system>.csv, fmucontainer's link list of the system."""
    path = artifacts.fmu_dir() / f"{system}.csv"
    if not path.is_file():
        raise FileNotFoundError(f"missing {path}: {artifacts.BUILD_HINT}")
    return path


@dataclass
class Series:
    """Recorded outputs: values[(instance, variable)][j] at grid point index[j] (time
    index[j] h)."""

    index: np.ndarray
    values: dict

    def at_grid(self, name: tuple[str, str], n: int) -> np.ndarray:
        """The values of `name` at grid points 0 .. n (NaN where none was recorded)."""
        out = np.full(n + 1, np.nan)
        keep = self.index <= n
        out[self.index[keep]] = self.values[name][keep]
        return out


def grid_index(times: np.ndarray, h: float) -> np.ndarray:
    """k for each time k h; ValueError if a time is off the grid by more than rounding."""
    k = np.rint(np.asarray(times, dtype=float) / h).astype(np.int64)
    if np.any(np.abs(k * h - times) > 1e-9 * max(1.0, float(np.max(np.abs(times), initial=0)))):
        raise ValueError("recorded times are not on the grid k h")
    return k


# ----------------------------------------------------------------------------- libcosim


def libcosim_quiet() -> None:
    """libcosim's log at warning level (its default prints every FMI call)."""
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    log_output_level(CosimLogLevel.WARNING)


def run_libcosim(
    *,
    ssp: Path | None = None,
    fmu: Path | None = None,
    parameters: dict[str, dict[str, object]] | None = None,
    record: tuple[tuple[str, str], ...] = (("beam", "tip_deflection"),),
    h: float = H,
    t_end: float = T_END,
) -> Series:
    """libcosim's fixed-step algorithm on the system `ssp` (its step is the SSD's OSP
    annotation, which must equal `h`), or on StickSlipBeam `fmu` alone as instance "beam".
    `parameters` {instance: {name: value}} become initial values (choices as codes)."""
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    libcosim_quiet()
    step = round(h * NANOSECONDS)
    if step != h * NANOSECONDS:
        raise ValueError(f"h = {h} s is not a whole number of nanoseconds")
    if ssp is not None:
        execution = CosimExecution.from_ssp_file(str(ssp))
    else:
        execution = CosimExecution.from_step_size(step)
        execution.add_local_slave(CosimLocalSlave(fmu_path=str(fmu), instance_name="beam"))
    slaves = {}
    for instance in {name for name, _ in record} | set(parameters or {}):
        index = execution.slave_index_from_instance_name(instance)
        variables = {v.name.decode(): v for v in execution.slave_variables(index)}
        slaves[instance] = (index, variables)
    setters = {
        CosimVariableType.REAL.value: execution.real_initial_value,
        CosimVariableType.INTEGER.value: execution.integer_initial_value,
        CosimVariableType.BOOLEAN.value: execution.boolean_initial_value,
        CosimVariableType.STRING.value: execution.string_initial_value,
    }
    for instance, values in (parameters or {}).items():
        index, variables = slaves[instance]
        for name, value in values.items():
            v = variables[name]
            if not setters[v.type](index, v.reference, value):
                raise RuntimeError(f"libcosim refused {instance}.{name} = {value!r}")
    observer = CosimObserver.create_time_series()
    execution.add_observer(observer)
    for instance, name in record:
        index, variables = slaves[instance]
        observer.start_time_series(index, variables[name].reference, CosimVariableType.REAL)
    n = round(t_end / h)
    # The observer keeps the values at t = 0, h, ...: n + 1 points need n + 1 steps.
    execution.simulate_until((n + 1) * step)
    values, index = {}, None
    for instance, name in record:
        slave, variables = slaves[instance]
        times, _, samples = observer.time_series_real_samples(
            slave, variables[name].reference, 0, n + 2
        )
        index = np.asarray(times, dtype=np.int64) // step
        if np.any(np.asarray(times, dtype=np.int64) != index * step):
            raise ValueError("libcosim recorded off the step grid")
        values[instance, name] = np.asarray(samples, dtype=float)
    return Series(index, values)


def ssp_with_beam(system: str, beam: Path, out: Path, keep: tuple[str, ...]) -> Path:
    """The SSP system `system` (fmu-build's) with its StickSlipBeam replaced by `beam`,
    an exported FMU of a user's scene (`stickslip export-fmu`: StickSlipBeam's variables,
    its own start values), written to `out`. The beam component keeps only the parameter
    values named in `keep` (the coupling's: `friction.law`, `external.coupling`); the
    others, which fmu-build wrote at StickSlipBeam's defaults, are dropped so that the
    export's own start values (its scene's) apply. The connections, NeuralFriction's
    parameter set and the step are the system's."""
    import re
    import zipfile

    source = f"resources/{BEAM}.fmu"
    with zipfile.ZipFile(ssp_path(system)) as archive:
        entries = {name: archive.read(name) for name in archive.namelist()}
    if source not in entries:
        raise ValueError(f"{system}.ssp has no {source}")
    ssd = entries["SystemStructure.ssd"].decode()
    start = ssd.index(f'<ssd:Component name="{INSTANCES[BEAM]}"')
    end = ssd.index("</ssd:Component>", start)
    parameter = re.compile(r'^\s*<ssv:Parameter name="([^"]+)">.*</ssv:Parameter>\n', re.M)
    component = parameter.sub(
        lambda m: m.group(0) if m.group(1) in keep else "", ssd[start:end]
    )
    kept = parameter.findall(component)
    if sorted(kept) != sorted(keep):
        raise ValueError(f"{system}.ssp: the beam's parameters {kept}, expected {list(keep)}")
    entries["SystemStructure.ssd"] = (ssd[:start] + component + ssd[end:]).encode()
    entries[source] = Path(beam).read_bytes()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in entries.items():
            archive.writestr(name, data)
    return out


def libcosim_variables(ssp: Path) -> dict[str, dict[str, int]]:
    """{instance: {variable: libcosim type}} of every slave of `ssp` as libcosim sees it
    (variables of a type it does not support are left out)."""
    from libcosimpy.CosimExecution import CosimExecution

    libcosim_quiet()
    execution = CosimExecution.from_ssp_file(str(ssp))
    out = {}
    for info in execution.slave_infos():
        index = execution.slave_index_from_instance_name(info.name.decode())
        out[info.name.decode()] = {
            v.name.decode(): v.type for v in execution.slave_variables(index)
        }
    return out


# ----------------------------------------------------------------------------- Ecos


def run_ecos(
    *,
    ssp: Path | None = None,
    fmu: Path | None = None,
    parameters: dict[str, dict[str, object]] | None = None,
    parameter_set: str | None = PARAMETER_SET,
    record: tuple[tuple[str, str], ...] = (("beam", "tip_deflection"),),
    h: float = H,
    t_end: float = T_END,
    log_level: str = "warn",
) -> Series:
    """Ecos on the system `ssp`, initialised with its parameter set `parameter_set` (Ecos
    applies none unless one is named), or on StickSlipBeam `fmu` alone as instance
    "beam", with `parameters` {instance: {name: value}} as a parameter set (Python types
    pick the FMI type: choices as int codes)."""
    from ecospy import EcosLib, EcosSimulation, EcosSimulationStructure

    EcosLib.set_log_level(log_level)
    if ssp is not None:
        simulation = EcosSimulation(ssp_path=str(ssp), step_size=h)
    else:
        structure = EcosSimulationStructure()
        structure.add_model("beam", str(fmu))
        if parameters:
            flat = {
                f"{instance}::{name}": value
                for instance, values in parameters.items()
                for name, value in values.items()
            }
            structure.add_parameter_set(PARAMETER_SET, flat)
        else:
            parameter_set = None
        simulation = EcosSimulation(structure=structure, step_size=h)
    if not simulation.init(parameter_set=parameter_set):
        raise RuntimeError(f"Ecos could not initialise: {EcosLib.get_last_error()}")
    n = round(t_end / h)
    values = {name: np.empty(n + 1) for name in record}
    identifiers = {name: f"{name[0]}::{name[1]}" for name in record}

    def sample(k: int) -> None:
        for name in record:
            values[name][k] = simulation.get_real(identifiers[name])

    sample(0)
    for k in range(1, n + 1):
        simulation.step()
        sample(k)
    simulation.terminate()
    return Series(np.arange(n + 1), values)


def ecos_integers(ssp: Path, names: dict[str, list[str]]) -> dict[tuple[str, str], int]:
    """The Integer variables `names` {instance: [variable]} of `ssp`, read by Ecos after
    initialisation with the SSD's parameter set (KeyError-like Exception if Ecos has no
    such Integer variable)."""
    from ecospy import EcosLib, EcosSimulation

    EcosLib.set_log_level("warn")
    simulation = EcosSimulation(ssp_path=str(ssp), step_size=H)
    simulation.init(parameter_set=PARAMETER_SET)
    out = {
        (instance, name): simulation.get_integer(f"{instance}::{name}")
        for instance, variables in names.items()
        for name in variables
    }
    simulation.terminate()
    return out


# ----------------------------------------------------------------------------- fmucontainer


def fmucontainer_command() -> Path:
    """The `fmucontainer` program of this Python environment."""
    here = Path(sys.executable).parent / "fmucontainer"
    found = here if here.is_file() else shutil.which("fmucontainer")
    if not found:
        raise FileNotFoundError(
            "fmucontainer is not installed (python-checks/requirements-masters.txt)"
        )
    return Path(found)


def build_container(
    csv_text: str, folder: Path, name: str, *, sequential: bool, h: float = H
) -> tuple[Path, str]:
    """Writes `csv_text` as <folder>/<name>.csv next to copies of the FMUs it names and
    runs `fmucontainer -container <name>.csv:<h> -no-auto-input -no-auto-output
    [-sequential]` there. Returns the container FMU's path and fmucontainer's log."""
    folder.mkdir(parents=True, exist_ok=True)
    fmus = artifacts.fmu_paths()
    for line in csv_text.splitlines():
        rule, *fields = line.split(";")
        if rule.upper() == "FMU":
            source = fmus[Path(fields[0]).stem]
            shutil.copyfile(source, folder / fields[0])
    (folder / f"{name}.csv").write_text(csv_text)
    command = [
        str(fmucontainer_command()),
        "-container",
        f"{name}.csv:{h!r}",
        "-fmu-directory",
        str(folder),
        "-no-auto-input",
        "-no-auto-output",
    ]
    if sequential:
        command.append("-sequential")
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    log = done.stdout + done.stderr
    container = folder / f"{name}.fmu"
    if done.returncode != 0 or not container.is_file():
        raise RuntimeError(f"fmucontainer failed ({done.returncode}):\n{log}")
    return container, log


def run_fmpy_fmu(
    fmu: Path,
    record: tuple[str, ...],
    *,
    h: float = H,
    t_end: float = T_END,
    start_values: dict | None = None,
) -> Series:
    """fmpy's `simulate_fmu` (co-simulation, output interval h) on `fmu`; values under
    ("", name)."""
    from fmpy import simulate_fmu

    result = simulate_fmu(
        str(fmu),
        start_time=0.0,
        stop_time=t_end,
        step_size=h,
        output_interval=h,
        output=list(record),
        start_values=start_values or {},
    )
    return Series(
        grid_index(result["time"], h),
        {("", name): np.asarray(result[name], dtype=float) for name in record},
    )


def run_container(container: Path, record: tuple[tuple[str, str], ...]) -> Series:
    """A container of a system (build_container) run by fmpy, its outputs `record`
    (instance, variable) under those names, as the other masters' runs give them (the
    container names them `instance.variable`)."""
    dotted = tuple(f"{instance}.{name}" for instance, name in record)
    run = run_fmpy_fmu(container, dotted)
    return Series(run.index, {o: run.values["", d] for o, d in zip(record, dotted)})


# ----------------------------------------------------------------------------- fmpy.ssp


def ssd_parameter_set(ssp: Path, override: dict[str, dict[str, object]] | None = None):
    """The SSD's parameter values as the one fmpy ParameterSet `simulate_ssp` takes,
    with `override` {instance: {name: value}} applied. fmpy's runner does not apply the
    SSD's own bindings; it addresses a parameter as `instance.name`; it cannot set
    String parameters (its set_value raises "Unsupported type: String"), so those keep
    the FMU's start value; and it tests a Boolean with `value != 0.0`, so the SSD's text
    "false" would set true: Booleans and numbers are passed as Python values."""
    from fmpy.ssp.ssd import Parameter, ParameterSet, read_ssd

    convert = {"Real": float, "Integer": int, "Boolean": lambda text: text == "true"}
    values: dict[str, object] = {}
    ssd = read_ssd(str(ssp))
    for component in ssd.system.elements:
        for binding in component.parameterBindings:
            for parameter_set in binding.parameterValues:
                for p in parameter_set.parameters:
                    if p.type in convert:
                        values[f"{component.name}.{p.name}"] = convert[p.type](p.value)
    for instance, named in (override or {}).items():
        for name, value in named.items():
            values[f"{instance}.{name}"] = value
    out = ParameterSet(name=PARAMETER_SET)
    out.parameters = [Parameter(name=name, value=value) for name, value in values.items()]
    return out


def run_fmpy_ssp(
    ssp: Path,
    *,
    parameters=None,
    record: tuple[tuple[str, str], ...] = (("beam", "tip_deflection"),),
    h: float = H,
    t_end: float = T_END,
) -> Series:
    """fmpy's SSP runner on `ssp` with the fmpy ParameterSet `parameters`. Its rows are
    labelled with the time a step starts from but hold the outputs after the step, so
    row j is grid point j + 1."""
    from fmpy.ssp.simulation import simulate_ssp

    result = simulate_ssp(
        str(ssp), stop_time=t_end, step_size=h, parameter_set=parameters
    )
    index = grid_index(result["time"], h) + 1
    return Series(
        index,
        {name: np.asarray(result[f"{name[0]}.{name[1]}"], dtype=float) for name in record},
    )


# ----------------------------------------------------------------------------- our master


def reference_coupled(
    fmus,
    scheme: str,
    *,
    h: float = H,
    t_end: float = T_END,
    system: str = COUPLED,
    clock: str = "float",
) -> np.ndarray:
    """Our master (master.run_coupled) on the coupled system `system` as its SSP file
    sets it up (its COUPLING_OF; NeuralFriction with the system's FRICTION_SETTINGS),
    counting time as `clock` says (master.CLOCKS): the beam's tip deflection at
    0, h, ..., t_end."""
    tip = ("beam", "tip_deflection")
    return reference_outputs(fmus, scheme, (tip,), h=h, t_end=t_end, system=system, clock=clock)[tip]


def reference_outputs(
    fmus,
    scheme: str,
    outputs: tuple[tuple[str, str], ...],
    *,
    h: float = H,
    t_end: float = T_END,
    system: str = COUPLED,
    clock: str = "float",
) -> dict[tuple[str, str], np.ndarray]:
    """As reference_coupled, for the `outputs` (instance, variable) of either FMU."""
    fmu_of = {instance: fmu for fmu, instance in INSTANCES.items()}
    record: dict[str, list[str]] = {}
    for instance, name in outputs:
        record.setdefault(fmu_of[instance], []).append(name)
    trace = master.run_coupled(
        fmus,
        h,
        t_end,
        beam={},
        friction=FRICTION_SETTINGS[system],
        record=record,
        scheme=scheme,
        coupling=COUPLING_OF[system],
        clock=clock,
    )
    return {(instance, name): trace[fmu_of[instance], name] for instance, name in outputs}


def reference_beam(fmus, parameters: dict, *, h: float = H, t_end: float = T_END) -> np.ndarray:
    """StickSlipBeam alone in our master with `parameters` (choices by word or code)."""
    trace = master.run_alone(
        fmus,
        BEAM,
        "beam",
        h,
        t_end,
        record={BEAM: ["tip_deflection"]},
        parameters={BEAM: parameters},
    )
    return trace[BEAM, "tip_deflection"]


def deviation(a: np.ndarray, b: np.ndarray) -> float:
    """Largest |a - b| over the points both have (NaN where a master recorded nothing)."""
    both = ~(np.isnan(a) | np.isnan(b))
    return float(np.max(np.abs(a[both] - b[both]))) if both.any() else float("nan")


# The scheme each master runs, as test_masters.py establishes it: the one whose result it
# must equal bit for bit. fmpy's SSP runner equals neither (it starts the connected
# inputs at 0); it is reported only.
SCHEME_OF = {
    "libcosim (SSP)": master.JACOBI,
    "Ecos (SSP)": master.JACOBI,
    "fmucontainer": master.JACOBI,
    "fmucontainer -sequential": master.GAUSS_SEIDEL,
    "fmpy.ssp": None,
}

# How each master counts time (master.CLOCKS): libcosim in integer nanoseconds, so that
# its step sizes are h only to rounding; with a law with state (COUPLED_MEMORY) that moves
# the bits, and our master counting the same way gives libcosim's bits again.
CLOCK_OF = {"libcosim (SSP)": "nanoseconds"}


@dataclass
class Comparison:
    """One master on the coupled system, one output (the beam's tip deflection, or the
    law's state): the largest |output - ours| against our Jacobi and Gauss-Seidel
    masters, the scheme it runs (None: neither) and whether it produced a NaN after the
    start."""

    label: str
    scheme: str | None
    jacobi: float
    gauss_seidel: float
    nan: bool
    output: str = "beam.tip_deflection"


def compare_coupled(fmus: artifacts.Fmus, system: str = COUPLED) -> list[Comparison]:
    """The coupled system `system` (COUPLED, COUPLED_MEMORY, COUPLED_RATE_STATE or
    COUPLED_LUGRE) in libcosim, Ecos, fmucontainer (parallel and sequential) and
    fmpy.ssp, each against our masters: one row per master for the tip deflection, and
    one per master for the law's state output (STATE_OF) where the system has one."""
    outputs = (("beam", "tip_deflection"), *((STATE_OF[system],) if system in STATE_OF else ()))
    n = round(T_END / H)
    clocks = {"float", *CLOCK_OF.values()}
    reference = {
        (s, c): reference_outputs(fmus, s, outputs, system=system, clock=c)
        for s in master.SCHEMES
        for c in clocks
    }
    ssp = ssp_path(system)
    series = {
        "libcosim (SSP)": run_libcosim(ssp=ssp, record=outputs),
        "Ecos (SSP)": run_ecos(ssp=ssp, record=outputs),
    }
    with tempfile.TemporaryDirectory(prefix="stickslip-container-") as tmp:
        links = csv_path(system).read_text()
        for sequential in (False, True):
            label = "fmucontainer -sequential" if sequential else "fmucontainer"
            folder = Path(tmp) / ("sequential" if sequential else "parallel")
            container, _ = build_container(links, folder, system, sequential=sequential)
            series[label] = run_container(container, outputs)
    series["fmpy.ssp"] = run_fmpy_ssp(ssp, parameters=ssd_parameter_set(ssp), record=outputs)
    rows = []
    for output in outputs:
        for label, run in series.items():
            x = run.at_grid(output, n)
            clock = CLOCK_OF.get(label, "float")
            rows.append(
                Comparison(
                    label,
                    SCHEME_OF[label],
                    deviation(x, reference[master.JACOBI, clock][output]),
                    deviation(x, reference[master.GAUSS_SEIDEL, clock][output]),
                    bool(np.isnan(x[1:]).any()),
                    ".".join(output),
                )
            )
    return rows


HEADERS = ["master", "scheme", "output", "max_dev_from_jacobi", "max_dev_from_gauss_seidel"]


def table(rows: list[Comparison]) -> str:
    """max |output - our master's| (in the output's unit), one line per master and output."""
    cells = [
        [r.label, r.scheme or "neither", r.output, f"{r.jacobi:.4g}", f"{r.gauss_seidel:.4g}"]
        for r in rows
    ]
    return format_table(["master", "runs", "output", "Jacobi", "Gauss-Seidel"], cells)


def csv_rows(rows: list[Comparison]) -> list[list[str]]:
    return [[r.label, r.scheme or "", r.output, repr(r.jacobi), repr(r.gauss_seidel)] for r in rows]


def to_frame(rows: list[Comparison]) -> pd.DataFrame:
    """The rows of masters_coupled.csv as a DataFrame."""
    return frame(HEADERS, csv_rows(rows)).astype({h: float for h in HEADERS[3:]})


def write_outputs(rows: list[Comparison], out: Path, name: str = "masters_coupled.csv") -> Path:
    """`name` (masters_coupled.csv) in `out`."""
    path = out / name
    write_csv(path, HEADERS, csv_rows(rows))
    return path
