"""The FMUs through fmpy alone: validation, the paper's scene and the coupled system.

1. Validates StickSlipBeam.fmu and NeuralFriction.fmu with fmpy.validation.validate_fmu
   (every problem is printed; there must be none).
2. Runs the paper's scene (0 .. 1.2 s, output every 1 ms) through StickSlipBeam.fmu with
   simulate_fmu, at every fidelity (modal, beam, plane-stress) and with the analytical
   exponential law and the neural law (friction.weights = paper-plain.json and
   paper-signed.json).
3. Couples StickSlipBeam (friction.model = external) with NeuralFriction.fmu (law neural
   with paper-plain.json, and law exponential) in a Gauss-Seidel master loop (beam first; cosim_convergence.py compares with Jacobi) with FMU2Slave at
   1 ms: beam relative_velocity -> friction sliding_velocity; friction
   friction_force_magnitude -> beam external.kinetic_force and static_limit -> beam
   external.static_limit. Both FMUs step from the same communication point t to t + 1 ms
   with the inputs exchanged at t held over the step (zero-order hold). At each
   communication point the outputs are exchanged in dependency order (beam -> friction
   -> beam): NeuralFriction has direct feedthrough (no state), so the force handed to the
   beam at t is the law at v_rel(t).
4. For every run: breakaway (first sample with stick false), number of stick/slip
   transitions at 1.2 s, the tip-deflection corridor after breakaway, the sawtooth period
   (mean spacing of major-slip onsets, the idea of src/metrics.rs on the 1 ms samples) and
   the RMS and largest deviation of the tip deflection from the analytical-law run at the
   same fidelity.
5. Prints the table, writes it to out/fmu_validation.csv, and plots
   out/fmu_tip_deflection.png and out/fmu_friction_law.png (NeuralFriction.fmu stepped
   with its velocity input swept from -0.35 to 0.35 m/s at 100 N).

Exits with status 1 if validation reports a problem or if a run's breakaway is not within
1 ms of 0.400 s.

The FMUs are read from $STICKSLIP_FMU_DIR, else $CARGO_TARGET_DIR/fmu, else
<repo>/target/fmu (where `cargo run --release -p fmu-build` writes them).

Usage: python fmu_scene.py [OUT_DIR]   (default: <repo>/out)
"""

from __future__ import annotations

import csv
import os
import shutil
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

import slip_metrics
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave
from fmpy.validation import validate_fmu

REPO = Path(__file__).resolve().parent.parent
BEAM = "StickSlipBeam"
FRICTION = "NeuralFriction"
BUILD_HINT = "run `cargo run --release -p fmu-build` first (it writes <target dir>/fmu/*.fmu)"

T_END = 1.2
DT = 1e-3  # communication step and output interval (s)
BELT_SPEED = 0.02  # m/s (paper)
BREAKAWAY_EXPECTED = 0.400  # s: mu_s F_n = 50 N reached at 8 mm = v_b * 0.4 s
BREAKAWAY_TOLERANCE = 1e-3  # s
PRE_SLIP_TOLERANCE = 1e-12  # m
PLOT_FIDELITY = "plane-stress"  # the paper's mesh

# Enumerations of the model descriptions (FMI enumerations are set as integers).
FIDELITY = {"modal": 1, "beam": 2, "plane-stress": 3}
FRICTION_MODEL = {"exponential": 1, "coulomb": 2, "neural": 3, "external": 4}
LAW = {"neural": 1, "exponential": 2}
WEIGHTS = ("paper-plain.json", "paper-signed.json")


def fmu_dir() -> Path:
    """$STICKSLIP_FMU_DIR, else $CARGO_TARGET_DIR/fmu, else <repo>/target/fmu."""
    if os.environ.get("STICKSLIP_FMU_DIR"):
        return Path(os.environ["STICKSLIP_FMU_DIR"])
    if os.environ.get("CARGO_TARGET_DIR"):
        # Relative to the workspace root, as fmu-build resolves it.
        return REPO / os.environ["CARGO_TARGET_DIR"] / "fmu"
    return REPO / "target" / "fmu"


def fmu_paths() -> dict[str, Path]:
    """Paths of both FMUs; FileNotFoundError (with the build command) if one is missing."""
    directory = fmu_dir()
    paths = {name: directory / f"{name}.fmu" for name in (BEAM, FRICTION)}
    missing = [str(p) for p in paths.values() if not p.is_file()]
    if missing:
        raise FileNotFoundError(f"missing FMU(s) {', '.join(missing)}: {BUILD_HINT}")
    return paths


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


class Fmus:
    """Both FMUs, unpacked once into a temporary folder (removed by close())."""

    def __init__(self, paths: dict[str, Path]):
        self.paths = paths
        self.tmp = Path(tempfile.mkdtemp(prefix="fmu-scene-"))
        self.dirs = {n: Path(extract(str(p), unzipdir=str(self.tmp / n))) for n, p in paths.items()}
        self.descriptions = {n: read_model_description(str(p)) for n, p in paths.items()}
        self.vr = {
            n: {v.name: v.valueReference for v in md.modelVariables}
            for n, md in self.descriptions.items()
        }

    def slave(self, name: str, instance: str) -> FMU2Slave:
        md = self.descriptions[name]
        return FMU2Slave(
            guid=md.guid,
            unzipDirectory=str(self.dirs[name]),
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=instance,
        )

    def close(self) -> None:
        shutil.rmtree(self.tmp, ignore_errors=True)


def run_embedded(fmus: Fmus, fidelity: str, law: str, weights: str | None = None) -> Run:
    """The paper scene through StickSlipBeam.fmu alone (simulate_fmu)."""
    start = {"fidelity.level": FIDELITY[fidelity], "friction.model": FRICTION_MODEL[law]}
    if weights is not None:
        start["friction.weights"] = weights
    began = time.perf_counter()
    result = simulate_fmu(
        str(fmus.dirs[BEAM]),
        model_description=fmus.descriptions[BEAM],
        start_time=0.0,
        stop_time=T_END,
        output_interval=DT,
        start_values=start,
        output=["tip_deflection", "friction_force", "stick", "transitions"],
    )
    wall = time.perf_counter() - began
    label = "exponential" if law == "exponential" else f"neural {Path(weights or '').stem}"
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


def run_coupled(fmus: Fmus, fidelity: str, law: str, weights: str = WEIGHTS[0]) -> Run:
    """StickSlipBeam (friction.model = external) + NeuralFriction, Gauss-Seidel at DT."""
    vb, vf = fmus.vr[BEAM], fmus.vr[FRICTION]
    beam = fmus.slave(BEAM, "beam")
    fric = fmus.slave(FRICTION, "friction")
    n = int(round(T_END / DT))
    times = np.arange(n + 1) * DT
    u = np.empty(n + 1)
    force = np.empty(n + 1)
    stick = np.empty(n + 1, bool)
    transitions = np.empty(n + 1, int)
    began = time.perf_counter()
    beam.instantiate()
    fric.instantiate()
    try:
        for s in (beam, fric):
            s.setupExperiment(startTime=0.0, stopTime=T_END)
            s.enterInitializationMode()
        beam.setInteger(
            [vb["fidelity.level"], vb["friction.model"]],
            [FIDELITY[fidelity], FRICTION_MODEL["external"]],
        )
        fric.setInteger([vf["law"]], [LAW[law]])
        if law == "neural":
            fric.setString([vf["weights"]], [weights])
        # The normal force of both is the paper's 100 N (start values).

        def exchange():
            """Gauss-Seidel exchange at the current communication point."""
            (v_rel,) = beam.getReal([vb["relative_velocity"]])
            fric.setReal([vf["sliding_velocity"]], [v_rel])

        def feed_beam():
            force, limit = fric.getReal([vf["friction_force_magnitude"], vf["static_limit"]])
            beam.setReal([vb["external.kinetic_force"], vb["external.static_limit"]], [force, limit])

        def record(k):
            u[k], force[k] = beam.getReal([vb["tip_deflection"], vb["friction_force"]])
            stick[k] = beam.getBoolean([vb["stick"]])[0]
            transitions[k] = beam.getInteger([vb["transitions"]])[0]

        # Consistent start: beam outputs at t = 0 -> friction -> beam inputs.
        exchange()
        feed_beam()
        for s in (beam, fric):
            s.exitInitializationMode()
        exchange()
        feed_beam()
        record(0)
        for k in range(n):
            t = times[k]
            # Gauss-Seidel: both step from t with the inputs exchanged at t.
            beam.doStep(currentCommunicationPoint=t, communicationStepSize=DT)
            fric.doStep(currentCommunicationPoint=t, communicationStepSize=DT)
            # Outputs at t + DT: beam first, then the friction law at the new velocity
            # (NeuralFriction has no state: its outputs follow its inputs).
            exchange()
            feed_beam()
            record(k + 1)
        for s in (beam, fric):
            s.terminate()
    finally:
        for s in (beam, fric):
            s.freeInstance()
    wall = time.perf_counter() - began
    label = "exponential" if law == "exponential" else f"neural {Path(weights).stem}"
    return Run(
        name=f"{fidelity} / coupled {label}",
        fidelity=fidelity,
        friction=f"NeuralFriction.fmu {label}",
        coupling="Gauss-Seidel",
        time=times,
        tip_deflection=u,
        friction_force=force,
        stick=stick,
        transitions=transitions,
        wall=wall,
    )


def friction_sweep(
    fmus: Fmus, law: str, weights: str | None = None, normal_force=100.0, velocities=None
):
    """NeuralFriction.fmu stepped at DT with sliding_velocity swept (default -0.35 .. 0.35
    m/s in steps of 1 mm/s); returns (velocities, signed friction_force)."""
    vf = fmus.vr[FRICTION]
    if velocities is None:
        velocities = np.linspace(-0.35, 0.35, 701)
    forces = np.empty_like(velocities)
    fric = fmus.slave(FRICTION, "sweep")
    fric.instantiate()
    try:
        fric.setupExperiment(startTime=0.0)
        fric.enterInitializationMode()
        fric.setInteger([vf["law"]], [LAW[law]])
        if weights is not None:
            fric.setString([vf["weights"]], [weights])
        fric.setReal([vf["normal_force"], vf["sliding_velocity"]], [normal_force, velocities[0]])
        fric.exitInitializationMode()
        t = 0.0
        for k, v in enumerate(velocities):
            fric.setReal([vf["sliding_velocity"]], [v])
            fric.doStep(currentCommunicationPoint=t, communicationStepSize=DT)
            t += DT
            forces[k] = fric.getReal([vf["friction_force"]])[0]
        fric.terminate()
    finally:
        fric.freeInstance()
    return velocities, forces


def exponential_law(v, normal_force=100.0, mu_s=0.5, mu_k=0.2, decay=5.0):
    """Paper Eq. 6, signed with the sliding velocity."""
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


def cell(run: Run, key: str, fmt: str, scale) -> str:
    if key in ("name", "coupling"):
        return getattr(run, key)
    value = run.wall if key == "wall" else run.metrics.get(key)
    if value is None:
        return "-"
    if scale is not None:
        value = value * scale
    return fmt.format(value)


def table_rows(runs: list[Run]) -> list[list[str]]:
    return [[cell(r, key, fmt, scale) for _, key, fmt, scale in COLUMNS] for r in runs]


def print_table(runs: list[Run]) -> None:
    # The coupling is in the run's name; the CSV keeps it as a column of its own.
    keep = [i for i, (h, *_) in enumerate(COLUMNS) if h != "coupling"]
    names = [COLUMNS[i][0].split(" [")[0] for i in keep]
    units = [("[" + COLUMNS[i][0].split(" [")[1]) if " [" in COLUMNS[i][0] else "" for i in keep]
    rows = [[row[i] for i in keep] for row in table_rows(runs)]
    widths = [
        max(len(n), len(u), *(len(r[i]) for r in rows)) for i, (n, u) in enumerate(zip(names, units))
    ]

    def line(values):
        parts = [
            v.ljust(w) if i == 0 else v.rjust(w) for i, (v, w) in enumerate(zip(values, widths))
        ]
        return "  ".join(parts).rstrip()

    print(line(names))
    print(line(units))
    print("  ".join("-" * w for w in widths))
    for row in rows:
        print(line(row))
    print(
        "dev, shift: tip deflection against the analytical (exponential) embedded run at the "
        "same fidelity, over 0 .. 1.2 s at 1 ms;\n"
        "pre-slip dev: largest deviation before that run's breakaway; shift@1.2s: lag that "
        "best aligns the last reference period (positive = behind), in ms and in degrees of "
        "the reference period"
    )


SLIP_HEADERS = [
    "run", "coupling", "slip", "onset [s]", "duration [s]", "cycle min [mm]",
    "cycle max [mm]", "cycle complete",
]


def slip_rows(runs: list[Run]) -> list[list]:
    """One row per major slip of every run (full precision)."""
    rows = []
    for r in runs:
        for i, slip in enumerate(r.metrics["slips"], start=1):
            rows.append([
                r.name, r.coupling, i, slip.onset, slip.duration, 1e3 * slip.cycle_min,
                1e3 * slip.cycle_max, slip.cycle_complete,
            ])
    return rows


def print_slips(runs: list[Run], fidelity: str) -> None:
    """Each major slip of the embedded runs at one fidelity, laws side by side."""
    chosen = [r for r in runs if r.fidelity == fidelity and r.coupling == "embedded"]
    count = max(len(r.metrics["slips"]) for r in chosen)
    labels = [r.friction for r in chosen]
    width = max(26, *(len(label) + 2 for label in labels))
    print(f"{'':28}" + "".join(label.rjust(width) for label in labels))
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
            print(f"  slip {i + 1}, {title:20}" + "".join(c.rjust(width) for c in cells))


def write_csv(runs: list[Run], path: Path) -> None:
    """The table with the printed columns and units, at full precision."""
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow([h for h, *_ in COLUMNS])
        for run in runs:
            row = []
            for _, key, _fmt, scale in COLUMNS:
                if key in ("name", "coupling"):
                    row.append(getattr(run, key))
                    continue
                value = run.wall if key == "wall" else run.metrics.get(key)
                if value is None:
                    row.append("")
                elif isinstance(value, (int, np.integer)) and scale is None:
                    row.append(str(int(value)))
                else:
                    row.append(repr(float(value) * (scale or 1.0)))
            writer.writerow(row)


def write_slips_csv(runs: list[Run], path: Path) -> None:
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(SLIP_HEADERS)
        for row in slip_rows(runs):
            writer.writerow(["" if v is None else v for v in row])


def plot_friction_force(runs: list[Run], fidelity: str, path: Path) -> None:
    """Paper Fig. 6b: force of the belt on the tip over time, both laws."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    chosen = [r for r in runs if r.fidelity == fidelity and r.coupling == "embedded"]
    styles = {
        "exponential": dict(color="black", lw=1.4),
        "neural paper-plain": dict(color="tab:blue", lw=1.0),
        "neural paper-signed": dict(color="tab:orange", lw=1.0, ls="--"),
    }
    fig, (ax, ax_z) = plt.subplots(2, 1, figsize=(10, 7.5), gridspec_kw={"height_ratios": [3, 2]})
    for r in chosen:
        style = styles.get(r.friction, {})
        ax.plot(r.time, r.friction_force, label=f"{r.friction} law", **style)
        first = r.metrics["slips"][0] if r.metrics["slips"] else None
        window = (r.time >= 0.39) & (r.time <= 0.56)
        ax_z.plot(1e3 * r.time[window], r.friction_force[window], **style)
        if first is not None and first.duration is not None:
            ax_z.axvline(1e3 * (first.onset + first.duration), color=style.get("color"), lw=0.6,
                         ls=":")
    for axis in (ax, ax_z):
        for level in (50.0, 20.0):
            axis.axhline(level, color="grey", lw=0.7, ls="--")
        axis.grid(True, alpha=0.3)
        axis.set_ylabel("friction force on the tip (N)")
    ax.text(0.01, 51.5, "static limit mu_s F_n = 50 N", fontsize=8, color="grey")
    ax.text(0.01, 21.5, "kinetic level mu_k F_n = 20 N", fontsize=8, color="grey")
    ax.set_xlabel("time t (s)")
    ax.set_title(
        f"Paper scene through StickSlipBeam.fmu, {fidelity} fidelity: friction force "
        "(cf. paper Fig. 6b)\nstick: holding force (rises with the deflection); slip: "
        "kinetic friction law",
        fontsize=10,
    )
    ax.legend(fontsize=9, loc="lower right")
    ax_z.set_xlabel("time t (ms)")
    ax_z.set_title("First slip (dotted: its end, the first re-stick)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_tip_deflection(runs: list[Run], fidelity: str, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    chosen = [r for r in runs if r.fidelity == fidelity]
    reference = next(r for r in chosen if r.coupling == "embedded" and r.friction == "exponential")
    fig, (ax_u, ax_d) = plt.subplots(
        2, 1, figsize=(10, 7.5), sharex=True, gridspec_kw={"height_ratios": [3, 2]}
    )
    styles = {
        "exponential": dict(color="black", lw=1.6),
        "neural paper-plain": dict(color="tab:blue", lw=1.1),
        "neural paper-signed": dict(color="tab:orange", lw=1.1),
        "NeuralFriction.fmu neural paper-plain": dict(color="tab:green", lw=1.1, ls="--"),
        "NeuralFriction.fmu exponential": dict(color="tab:red", lw=1.1, ls=":"),
    }
    for r in chosen:
        if r.coupling == "embedded":
            label = f"StickSlipBeam.fmu, {r.friction} law"
        else:
            label = f"coupled (Gauss-Seidel, 1 ms) with {r.friction}"
        style = styles.get(r.friction, {})
        ax_u.plot(r.time, 1e3 * r.tip_deflection, label=label, **style)
        if r is not reference:
            ax_d.plot(r.time, 1e3 * (r.tip_deflection - reference.tip_deflection), **style)
    ax_u.axvline(BREAKAWAY_EXPECTED, color="grey", lw=0.8, ls="--")
    ax_u.text(BREAKAWAY_EXPECTED + 0.005, 0.3, "breakaway 0.400 s", color="grey", fontsize=8)
    ax_u.set_ylabel("tip deflection (mm)")
    ax_u.set_title(f"Paper scene through the FMUs (fmpy), {fidelity} fidelity")
    ax_u.grid(True, alpha=0.3)
    ax_u.legend(fontsize=8, loc="lower right")
    ax_d.axhline(0.0, color="black", lw=0.8)
    ax_d.set_xlabel("time t (s)")
    ax_d.set_ylabel("deviation from analytical (mm)")
    ax_d.set_title("Tip deflection minus the analytical-law run (same fidelity)", fontsize=10)
    ax_d.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_friction_law(
    sweeps: dict[str, tuple[np.ndarray, np.ndarray]],
    zooms: dict[str, tuple[np.ndarray, np.ndarray]],
    path: Path,
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, ax_z) = plt.subplots(
        1, 2, figsize=(12, 5.2), gridspec_kw={"width_ratios": [3, 2]}
    )
    styles = {
        "neural, paper-plain.json": dict(color="tab:blue", lw=1.6),
        "neural, paper-signed.json": dict(color="tab:orange", lw=1.6),
        "exponential (paper Eq. 6)": dict(color="black", lw=1.2, ls="--"),
    }
    for axis, data, scale, unit in ((ax, sweeps, 1.0, "m/s"), (ax_z, zooms, 1e3, "mm/s")):
        for label, (v, f) in data.items():
            axis.plot(scale * v, f, label=f"law {label}", **styles.get(label, {}))
        axis.axhline(0.0, color="grey", lw=0.6)
        axis.axvline(0.0, color="grey", lw=0.6)
        for level in (50.0, -50.0):
            axis.axhline(level, color="grey", lw=0.6, ls=":")
        axis.set_xlabel(f"sliding velocity v_rel ({unit})")
        axis.set_ylabel("friction force (N)")
        axis.grid(True, alpha=0.3)
    ax.text(-0.345, 51.5, "static limit mu_s F_n = 50 N", fontsize=8, color="grey")
    ax.set_title("NeuralFriction.fmu, velocity input swept (1 mm/s per 1 ms step)", fontsize=10)
    ax.set_xlim(-0.36, 0.36)
    ax.legend(fontsize=9, loc="lower right")
    ax_z.set_title("near v_rel = 0 (0.05 mm/s per step)", fontsize=10)
    ax_z.set_xlim(-10.0, 10.0)
    fig.suptitle("Friction force of NeuralFriction.fmu at F_n = 100 N (signed output friction_force)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


# ----------------------------------------------------------------------------- main


def validate(paths: dict[str, Path]) -> dict[str, list[str]]:
    return {name: [str(p) for p in validate_fmu(str(path))] for name, path in paths.items()}


def run_all(fmus: Fmus) -> list[Run]:
    runs: list[Run] = []
    for fidelity in FIDELITY:
        reference = run_embedded(fmus, fidelity, "exponential")
        batch = [reference]
        for weights in WEIGHTS:
            batch.append(run_embedded(fmus, fidelity, "neural", weights))
        batch.append(run_coupled(fmus, fidelity, "neural", WEIGHTS[0]))
        batch.append(run_coupled(fmus, fidelity, "exponential"))
        for r in batch:
            r.metrics = summarise(r, reference)
        runs += batch
    return runs


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    out = Path(argv[0]) if argv else REPO / "out"
    out.mkdir(parents=True, exist_ok=True)
    began = time.perf_counter()
    try:
        paths = fmu_paths()
    except FileNotFoundError as error:
        print(f"fmu_scene: {error}", file=sys.stderr)
        return 2
    print(f"FMUs: {', '.join(str(p) for p in paths.values())}")

    failures: list[str] = []
    print("== fmpy.validation.validate_fmu")
    for name, problems in validate(paths).items():
        print(f"  {name}.fmu: {len(problems)} problem(s)")
        for p in problems:
            print(f"    {p}")
        if problems:
            failures.append(f"{name}.fmu: {len(problems)} validation problem(s)")

    fmus = Fmus(paths)
    try:
        runs = run_all(fmus)
        laws = {
            "neural, paper-plain.json": ("neural", WEIGHTS[0]),
            "neural, paper-signed.json": ("neural", WEIGHTS[1]),
            "exponential (paper Eq. 6)": ("exponential", None),
        }
        sweeps = {label: friction_sweep(fmus, *law) for label, law in laws.items()}
        fine = np.linspace(-0.01, 0.01, 401)
        zooms = {
            label: friction_sweep(fmus, *law, velocities=fine) for label, law in laws.items()
        }
    finally:
        fmus.close()

    print()
    print("== Paper scene through the FMUs (0 .. 1.2 s, 1 ms output)")
    print_table(runs)
    for r in runs:
        b = r.metrics["breakaway"]
        if b is None or abs(b - BREAKAWAY_EXPECTED) > BREAKAWAY_TOLERANCE + 1e-12:
            failures.append(
                f"{r.name} ({r.coupling}): breakaway {b} s, expected "
                f"{BREAKAWAY_EXPECTED:.3f} +- {BREAKAWAY_TOLERANCE:g} s"
            )
        # In stick the kinetic law is never evaluated, so every law must give the same
        # curve up to the first slip; 1e-12 m leaves room for rounding only.
        pre = r.metrics["dev_before_breakaway"]
        if pre is None or pre > PRE_SLIP_TOLERANCE:
            failures.append(f"{r.name} ({r.coupling}): deviates {pre} m before breakaway")
    print()
    print(f"== Major slips, {PLOT_FIDELITY} fidelity (the paper's mesh), both laws")
    print_slips(runs, PLOT_FIDELITY)

    print()
    print("== NeuralFriction.fmu, friction force at F_n = 100 N, -0.35 .. 0.35 m/s")
    v, f_exp = sweeps["exponential (paper Eq. 6)"]
    law_error = float(np.max(np.abs(f_exp - exponential_law(v))))
    print(f"  law exponential vs paper Eq. 6: max |difference| {law_error:.2e} N")
    away = np.abs(v) >= 0.01  # Eq. 6 jumps by 2 mu_s F_n = 100 N at v = 0
    for label in ("neural, paper-plain.json", "neural, paper-signed.json"):
        _, f = sweeps[label]
        d = np.abs(f - exponential_law(v))[away]
        zv, zf = zooms[label]
        print(
            f"  law {label} vs paper Eq. 6 for |v| >= 0.01 m/s: max |difference| "
            f"{d.max():.2f} N (at {v[away][np.argmax(d)]:+.3f} m/s), RMS "
            f"{np.sqrt(np.mean(d**2)):.2f} N; for |v| < 0.01 m/s: force "
            f"{zf.min():+.1f} .. {zf.max():+.1f} N, at v = 0: {zf[len(zf) // 2]:+.2f} N"
        )

    print()
    print("== Coupling error: coupled (Gauss-Seidel, 1 ms) minus embedded run, same law and fidelity")
    for r in runs:
        if r.coupling != "Gauss-Seidel":
            continue
        law = "exponential" if r.friction.endswith("exponential") else "neural paper-plain"
        twin = next(
            e for e in runs if e.coupling == "embedded" and e.fidelity == r.fidelity
            and e.friction == law
        )
        d = r.tip_deflection - twin.tip_deflection
        print(
            f"  {r.fidelity:13} {law:19} RMS {1e3 * np.sqrt(np.mean(d**2)):.4f} mm, "
            f"max {1e3 * np.max(np.abs(d)):.4f} mm"
        )

    written = [out / name for name in (
        "fmu_validation.csv", "fmu_slips.csv", "fmu_tip_deflection.png",
        "fmu_friction_force.png", "fmu_friction_law.png",
    )]
    write_csv(runs, written[0])
    write_slips_csv(runs, written[1])
    plot_tip_deflection(runs, PLOT_FIDELITY, written[2])
    plot_friction_force(runs, PLOT_FIDELITY, written[3])
    plot_friction_law(sweeps, zooms, written[4])
    print()
    for p in written:
        print(f"wrote {p}")
    print(f"total wall time {time.perf_counter() - began:.1f} s")
    return report_failures(failures)


def report_failures(failures: list[str]) -> int:
    """Prints the failed checks to stderr; the script's exit status (1 if any)."""
    if not failures:
        return 0
    print("\nFAILED:", file=sys.stderr)
    for f in failures:
        print(f"  {f}", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
