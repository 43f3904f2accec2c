"""The FMUs through fmpy alone: validation, the paper's scene and the coupled system
(the library of the fmu_scene entry point).

1. Validates StickSlipBeam.fmu and NeuralFriction.fmu with fmpy.validation.validate_fmu
   (every problem is printed; there must be none).
2. Runs the paper's scene (0 .. 1.2 s, output every 1 ms) through StickSlipBeam.fmu with
   simulate_fmu, at every structural fidelity (fidelity.level's items but auto, read from
   the model description by artifacts.fidelities) and with the analytical exponential
   law and the neural law (friction.weights = paper-plain.json and paper-signed.json).
3. Couples StickSlipBeam (friction.law = external) with NeuralFriction.fmu (law neural
   with paper-plain.json, and law exponential) with the Gauss-Seidel master (master.run,
   beam first; cosim_convergence compares with Jacobi) over FMU2Slave at 1 ms: beam
   relative_velocity -> friction sliding_velocity; friction friction_force_magnitude ->
   beam external.kinetic_force and static_limit -> beam external.static_limit. The plain
   network, a smooth signed law, goes through the signed coupling (external.coupling =
   signed, master.COUPLINGS): friction friction_force, friction_force_slope and
   evaluated_velocity -> beam external.friction_force, external.friction_slope and
   external.sliding_velocity, the law's tangent. Inputs are held over each step
   (zero-order hold). The beam steps from t to t + 1 ms with the
   force exchanged at t; the friction FMU then gets the beam's v_rel(t + 1 ms), and its
   force goes back to the beam. NeuralFriction has direct feedthrough (no state), so the
   force handed to the beam at t is the law at v_rel(t).
4. For every run: breakaway (first sample with stick false), number of stick/slip
   transitions at 1.2 s, the tip-deflection corridor after breakaway, the sawtooth period
   (mean spacing of major-slip onsets, the idea of src/physics/src/metrics.rs on the 1 ms
   samples) and the RMS and largest deviation of the tip deflection from the
   analytical-law run at the same fidelity.
5. Prints the table, writes it to out/fmu_validation.csv, and plots
   out/fmu_tip_deflection.png and out/fmu_friction_law.png (NeuralFriction.fmu stepped
   with its velocity input swept from -0.35 to 0.35 m/s at its start normal force,
   100 N), and compares its exponential law with paper Eq. 6 (exponential_law).

The checks (no validation problem; every run's breakaway within 1 ms of 0.400 s and no
deviation before it) are tests/test_fmu.py's.

The FMUs are read from the 2.0/ folder of $STICKSLIP_FMU_DIR, else of
$CARGO_TARGET_DIR/fmu, else of <repo>/target/fmu (where
`cargo run --release -p fmu-build` writes them; see artifacts).
The coupled runs and the law sweeps go through the co-simulation master (master.run);
the embedded runs through fmpy's simulate_fmu.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from . import master, plots, slip_metrics
from .artifacts import BEAM, FRICTION, Fmus, Model, fidelities
from .tables import format_table, frame, write_csv

if TYPE_CHECKING:
    import pandas as pd

T_END = 1.2
DT = 1e-3  # communication step and output interval (s)
BREAKAWAY_EXPECTED = 0.400  # s: mu_s F_n = 50 N reached at 8 mm = v_b * 0.4 s
BREAKAWAY_TOLERANCE = 1e-3  # s
PRE_SLIP_TOLERANCE = 1e-12  # m
PLOT_FIDELITY = "plane-stress"  # the paper's mesh
WEIGHTS = ("paper-plain.json", "paper-signed.json")


# ----------------------------------------------------------------------------- metrics


@dataclass
class Run:
    """One simulation, sampled every DT: time (s), tip deflection (m), force of the belt
    on the tip (N; holding force in stick, friction force in slip), stick, transitions."""

    name: str
    fidelity: str
    friction: str
    coupling: str  # "embedded" (one FMU) or "Gauss-Seidel" (two FMUs)
    time: np.ndarray
    tip_deflection: np.ndarray
    friction_force: np.ndarray
    stick: np.ndarray
    transitions: np.ndarray
    wall: float
    metrics: dict = field(default_factory=dict)


def summarise(run: Run, reference: Run | None) -> dict:
    """Breakaway, transitions, corridor, major slips, period, and against `reference`:
    deviation before its breakaway, RMS and largest deviation, phase shift at the end."""
    t, u, stick = run.time, run.tip_deflection, run.stick.astype(bool)
    slips = slip_metrics.major_slips(t, u, stick)
    m: dict = {
        "breakaway": slip_metrics.breakaway(t, stick),
        "transitions": int(run.transitions[-1]),
        "corridor_min": None,
        "corridor_max": None,
        "slips": slips,
        "major_slips": len(slips),
        "first_slip": slips[0].duration if slips else None,
        "period": slip_metrics.period(slips),
        "dev_before_breakaway": None,
        "rms_dev": None,
        "max_dev": None,
        "phase_shift": None,
        "phase_shift_deg": None,
    }
    if m["breakaway"] is not None:
        after = t >= m["breakaway"]
        m["corridor_min"], m["corridor_max"] = float(u[after].min()), float(u[after].max())
    if reference is not None:
        if len(reference.time) != len(t) or np.max(np.abs(reference.time - t)) > 1e-9:
            raise ValueError(f"{run.name}: time grid differs from {reference.name}")
        d = u - reference.tip_deflection
        m["rms_dev"] = float(np.sqrt(np.mean(d**2)))
        m["max_dev"] = float(np.max(np.abs(d)))
        ref = reference.metrics or summarise(reference, None)
        if ref["breakaway"] is not None:
            m["dev_before_breakaway"] = float(np.max(np.abs(d[t < ref["breakaway"] - 1e-12])))
        if ref["period"] is not None:
            tau = slip_metrics.phase_shift(t, u, reference.tip_deflection, ref["period"])
            m["phase_shift"] = tau
            m["phase_shift_deg"] = 360.0 * tau / ref["period"]
    return m


# ----------------------------------------------------------------------------- runs


def _label(law: str, weights: str | None) -> str:
    return "exponential" if law == "exponential" else f"neural {Path(weights or '').stem}"


def run_embedded(
    fmus: Fmus, fidelity: str, law: str, weights: str | None = None, stop_time: float = T_END
) -> Run:
    """The paper scene through StickSlipBeam.fmu alone (simulate_fmu), 0 .. stop_time."""
    beam = fmus.models[BEAM]
    start = {
        "fidelity.level": beam.code("fidelity.level", fidelity),
        "friction.law": beam.code("friction.law", law),
    }
    if weights is not None:
        start["friction.weights"] = weights
    began = time.perf_counter()
    result = simulate_fmu(
        str(fmus.dirs[BEAM]),
        model_description=fmus.descriptions[BEAM],
        start_time=0.0,
        stop_time=stop_time,
        output_interval=DT,
        start_values=start,
        output=["tip_deflection", "friction_force", "stick", "transitions"],
    )
    wall = time.perf_counter() - began
    label = _label(law, weights)
    return Run(
        name=f"{fidelity} / {label}",
        fidelity=fidelity,
        friction=label,
        coupling="embedded",
        time=np.asarray(result["time"], float),
        tip_deflection=np.asarray(result["tip_deflection"], float),
        friction_force=np.asarray(result["friction_force"], float),
        stick=np.asarray(result["stick"], bool),
        transitions=np.asarray(result["transitions"], int),
        wall=wall,
    )


def run_coupled(
    fmus: Fmus, fidelity: str, law: str, weights: str = WEIGHTS[0], coupling: str = "magnitude"
) -> Run:
    """StickSlipBeam (friction.law = external, external.coupling = `coupling`) +
    NeuralFriction, Gauss-Seidel at DT. The normal force of both is the paper's 100 N
    (start values)."""
    friction = {"law": law}
    if law == "neural":
        friction["weights"] = weights
    began = time.perf_counter()
    trace = master.run_coupled(
        fmus,
        DT,
        T_END,
        beam={"fidelity.level": fidelity},
        friction=friction,
        record={BEAM: ["tip_deflection", "friction_force", "stick", "transitions"]},
        coupling=coupling,
    )
    wall = time.perf_counter() - began
    label = _label(law, weights)
    return Run(
        name=f"{fidelity} / coupled {label} ({coupling})",
        fidelity=fidelity,
        friction=f"NeuralFriction.fmu {label}",
        coupling="Gauss-Seidel",
        time=trace.time,
        tip_deflection=trace[BEAM, "tip_deflection"],
        friction_force=trace[BEAM, "friction_force"],
        stick=trace[BEAM, "stick"],
        transitions=trace[BEAM, "transitions"],
        wall=wall,
    )


def drive_friction(
    fmus: Fmus, law: str, weights: str | None, inputs: dict[str, np.ndarray], instance: str
) -> np.ndarray:
    """NeuralFriction.fmu stepped at DT with its inputs set to inputs[name][k] before step
    k; the signed friction_force after each step (the FMU has no state, so each force is
    the law at that step's inputs)."""
    parameters = {"law": law}
    if weights is not None:
        parameters["weights"] = weights
    steps = len(next(iter(inputs.values())))
    trace = master.run_alone(
        fmus,
        FRICTION,
        instance,
        DT,
        steps * DT,
        parameters={FRICTION: parameters},
        signals={FRICTION: inputs},
        record={FRICTION: ["friction_force"]},
        stop_time=False,
    )
    return trace[FRICTION, "friction_force"][1:]


def friction_sweep(
    fmus: Fmus, law: str, weights: str | None = None, normal_force=None, velocities=None
):
    """NeuralFriction.fmu stepped at DT with sliding_velocity swept (default -0.35 .. 0.35
    m/s in steps of 1 mm/s) at `normal_force` (N; default: the start value of its
    normal_force input); returns (velocities, signed friction_force)."""
    if velocities is None:
        velocities = np.linspace(-0.35, 0.35, 701)
    if normal_force is None:
        normal_force = fmus.models[FRICTION].real_start("normal_force")
    inputs = {
        "normal_force": np.full(len(velocities), float(normal_force)),
        "sliding_velocity": velocities,
    }
    return velocities, drive_friction(fmus, law, weights, inputs, "sweep")


def exponential_law(v, friction: Model):
    """Paper Eq. 6, signed with the sliding velocity (N):
    F(v) = sign(v) F_n (mu_k + (mu_s - mu_k) exp(-alpha |v|)).

    An independent oracle of the FMU's exponential law (main prints the largest
    difference): only the formula is written here. Its coefficients are the start values
    of NeuralFriction's model description (`friction`): static_coefficient (mu_s),
    kinetic_coefficient (mu_k), decay (alpha, s/m) and the normal_force input (F_n, N),
    the values friction_sweep runs the FMU at."""
    mu_s, mu_k, decay, normal_force = (
        friction.real_start(name)
        for name in ("static_coefficient", "kinetic_coefficient", "decay", "normal_force")
    )
    return np.sign(v) * normal_force * (mu_k + (mu_s - mu_k) * np.exp(-decay * np.abs(v)))


# ----------------------------------------------------------------------------- output

COLUMNS = [
    # (csv/table header, metric key or callable, format, scale)
    ("run", "name", "{}", None),
    ("coupling", "coupling", "{}", None),
    ("breakaway [s]", "breakaway", "{:.3f}", 1.0),
    ("transitions [-]", "transitions", "{:d}", None),
    ("corridor min [mm]", "corridor_min", "{:.3f}", 1e3),
    ("corridor max [mm]", "corridor_max", "{:.3f}", 1e3),
    ("major slips [-]", "major_slips", "{:d}", None),
    ("1st slip [s]", "first_slip", "{:.3f}", 1.0),
    ("period [s]", "period", "{:.4f}", 1.0),
    ("pre-slip [mm]", "dev_before_breakaway", "{:.1e}", 1e3),
    ("RMS dev [mm]", "rms_dev", "{:.4f}", 1e3),
    ("max dev [mm]", "max_dev", "{:.4f}", 1e3),
    ("shift@1.2s [ms]", "phase_shift", "{:+.0f}", 1e3),
    ("shift@1.2s [deg]", "phase_shift_deg", "{:+.0f}", 1.0),
    ("wall [s]", "wall", "{:.2f}", 1.0),
]
HEADERS = [h for h, *_ in COLUMNS]


def _value(run: Run, key: str):
    if key in ("name", "coupling"):
        return getattr(run, key)
    return run.wall if key == "wall" else run.metrics.get(key)


def table(runs: list[Run]) -> str:
    """The printed table: every column of COLUMNS but the coupling (it is in the run's
    name), names over units, with the footnote."""
    keep = [i for i, h in enumerate(HEADERS) if h != "coupling"]
    names = [HEADERS[i].split(" [")[0] for i in keep]
    units = [("[" + HEADERS[i].split(" [")[1]) if " [" in HEADERS[i] else "" for i in keep]
    rows = []
    for run in runs:
        cells = []
        for i in keep:
            _, key, fmt, scale = COLUMNS[i]
            value = _value(run, key)
            if value is None or isinstance(value, str):
                cells.append("-" if value is None else value)
            else:
                cells.append(fmt.format(value * scale if scale is not None else value))
        rows.append(cells)
    return format_table([names, units], rows) + (
        "\ndev, shift: tip deflection against the analytical (exponential) embedded run at the "
        "same fidelity, over 0 .. 1.2 s at 1 ms;\n"
        "pre-slip dev: largest deviation before that run's breakaway; shift@1.2s: lag that "
        "best aligns the last reference period (positive = behind), in ms and in degrees of "
        "the reference period"
    )


def csv_rows(runs: list[Run]) -> list[list]:
    """The table with every column of COLUMNS, at full precision (the CSV's cells)."""
    rows = []
    for run in runs:
        row = []
        for _, key, _fmt, scale in COLUMNS:
            value = _value(run, key)
            if value is None:
                row.append("")
            elif isinstance(value, str) or (isinstance(value, (int, np.integer)) and scale is None):
                row.append(value if isinstance(value, str) else str(int(value)))
            else:
                row.append(repr(float(value) * (scale or 1.0)))
        rows.append(row)
    return rows


SLIP_HEADERS = [
    "run", "coupling", "slip", "onset [s]", "duration [s]", "cycle min [mm]",
    "cycle max [mm]", "cycle complete",
]


def slip_rows(runs: list[Run]) -> list[list]:
    """One row per major slip of every run (full precision; "" where there is none)."""
    rows = []
    for r in runs:
        for i, slip in enumerate(r.metrics["slips"], start=1):
            row = [
                r.name, r.coupling, i, slip.onset, slip.duration, 1e3 * slip.cycle_min,
                1e3 * slip.cycle_max, slip.cycle_complete,
            ]
            rows.append(["" if v is None else v for v in row])
    return rows


def to_frames(runs: list[Run]) -> tuple[pd.DataFrame, pd.DataFrame]:
    """(the runs, their major slips) as DataFrames: the rows of fmu_validation.csv and
    fmu_slips.csv."""
    return frame(HEADERS, csv_rows(runs)), frame(SLIP_HEADERS, slip_rows(runs))


def slips_text(runs: list[Run], fidelity: str) -> str:
    """Each major slip of the embedded runs at one fidelity, laws side by side."""
    chosen = [r for r in runs if r.fidelity == fidelity and r.coupling == "embedded"]
    count = max(len(r.metrics["slips"]) for r in chosen)
    labels = [r.friction for r in chosen]
    width = max(26, *(len(label) + 2 for label in labels))
    lines = [f"{'':28}" + "".join(label.rjust(width) for label in labels)]
    for i in range(count):
        for title, text in (
            ("onset [s]", lambda s: f"{s.onset:.3f}"),
            ("duration [s]", lambda s: "-" if s.duration is None else f"{s.duration:.3f}"),
            ("cycle min .. max [mm]", lambda s: f"{1e3 * s.cycle_min:.2f} .. "
             f"{1e3 * s.cycle_max:.2f}" + ("" if s.cycle_complete else " (to 1.2 s)")),
        ):
            cells = []
            for r in chosen:
                slips = r.metrics["slips"]
                cells.append(text(slips[i]) if i < len(slips) else "-")
            lines.append(f"  slip {i + 1}, {title:20}" + "".join(c.rjust(width) for c in cells))
    return "\n".join(lines)


# ----------------------------------------------------------------------------- the scene

LAWS = {
    "neural, paper-plain.json": ("neural", WEIGHTS[0]),
    "neural, paper-signed.json": ("neural", WEIGHTS[1]),
    "exponential (paper Eq. 6)": ("exponential", None),
}
EXPONENTIAL = "exponential (paper Eq. 6)"
Sweep = tuple[np.ndarray, np.ndarray]  # (velocities, signed friction force)


@dataclass
class Scene:
    """Everything fmu_scene measures: the runs and NeuralFriction.fmu's laws swept over
    -0.35 .. 0.35 m/s (`sweeps`) and -0.01 .. 0.01 m/s (`zooms`), by LAWS label."""

    runs: list[Run]
    sweeps: dict[str, Sweep]
    zooms: dict[str, Sweep]
    friction: Model  # NeuralFriction's model description (its start values)


def validate(paths: dict[str, Path]) -> dict[str, list[str]]:
    """fmpy.validation's problems of each FMU, by name."""
    return {name: [str(p) for p in validate_fmu(str(path))] for name, path in paths.items()}


def run_all(fmus: Fmus) -> list[Run]:
    """Every run of the scene, summarised against the exponential embedded run of its
    fidelity."""
    runs: list[Run] = []
    for fidelity in fidelities(fmus.models[BEAM]):
        reference = run_embedded(fmus, fidelity, "exponential")
        batch = [reference]
        for weights in WEIGHTS:
            batch.append(run_embedded(fmus, fidelity, "neural", weights))
        # paper-plain.json: a smooth signed law, coupled by its tangent.
        batch.append(run_coupled(fmus, fidelity, "neural", WEIGHTS[0], coupling="signed"))
        batch.append(run_coupled(fmus, fidelity, "exponential"))
        for r in batch:
            r.metrics = summarise(r, reference)
        runs += batch
    return runs


def run_scene(fmus: Fmus) -> Scene:
    """The runs and the friction-law sweeps."""
    fine = np.linspace(-0.01, 0.01, 401)
    return Scene(
        runs=run_all(fmus),
        sweeps={label: friction_sweep(fmus, *law) for label, law in LAWS.items()},
        zooms={label: friction_sweep(fmus, *law, velocities=fine) for label, law in LAWS.items()},
        friction=fmus.models[FRICTION],
    )


def law_lines(scene: Scene) -> list[str]:
    """The FMU's exponential law against paper Eq. 6, and each network against it."""
    v, f_exp = scene.sweeps[EXPONENTIAL]
    law_error = float(np.max(np.abs(f_exp - exponential_law(v, scene.friction))))
    lines = [f"  law exponential vs paper Eq. 6: max |difference| {law_error:.2e} N"]
    away = np.abs(v) >= 0.01  # Eq. 6 jumps by 2 mu_s F_n = 100 N at v = 0
    for label in ("neural, paper-plain.json", "neural, paper-signed.json"):
        _, f = scene.sweeps[label]
        # Against the FMU's exponential law, which equals Eq. 6 (checked just above).
        d = np.abs(f - f_exp)[away]
        _, zf = scene.zooms[label]
        lines.append(
            f"  law {label} vs paper Eq. 6 for |v| >= 0.01 m/s: max |difference| "
            f"{d.max():.2f} N (at {v[away][np.argmax(d)]:+.3f} m/s), RMS "
            f"{np.sqrt(np.mean(d**2)):.2f} N; for |v| < 0.01 m/s: force "
            f"{zf.min():+.1f} .. {zf.max():+.1f} N, at v = 0: {zf[len(zf) // 2]:+.2f} N"
        )
    return lines


def coupling_lines(runs: list[Run]) -> list[str]:
    """Coupled minus embedded tip deflection, same law and fidelity."""
    lines = []
    for r in runs:
        if r.coupling != "Gauss-Seidel":
            continue
        law = "exponential" if r.friction.endswith("exponential") else "neural paper-plain"
        twin = next(
            e for e in runs if e.coupling == "embedded" and e.fidelity == r.fidelity
            and e.friction == law
        )
        d = r.tip_deflection - twin.tip_deflection
        lines.append(
            f"  {r.fidelity:13} {law:19} RMS {1e3 * np.sqrt(np.mean(d**2)):.4f} mm, "
            f"max {1e3 * np.max(np.abs(d)):.4f} mm"
        )
    return lines


def write_outputs(scene: Scene, out: Path) -> list[Path]:
    """fmu_validation.csv, fmu_slips.csv and the three figures in `out`."""
    written = [out / name for name in (
        "fmu_validation.csv", "fmu_slips.csv", "fmu_tip_deflection.png",
        "fmu_friction_force.png", "fmu_friction_law.png",
    )]
    write_csv(written[0], HEADERS, csv_rows(scene.runs))
    write_csv(written[1], SLIP_HEADERS, slip_rows(scene.runs))
    plots.tip_deflection(scene.runs, PLOT_FIDELITY, BREAKAWAY_EXPECTED, written[2])
    plots.friction_force(scene.runs, PLOT_FIDELITY, written[3])
    plots.friction_law(scene.sweeps, scene.zooms, written[4])
    return written
