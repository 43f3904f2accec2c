"""Every figure of the harness (matplotlib, Agg backend). The functions take the numbers
to draw; the entry points compute and pass them.

- fmu_scene: friction_force (paper Fig. 6b), tip_deflection (Fig. 6a through the FMUs),
  friction_law (Fig. 5b through NeuralFriction.fmu)
- cosim_convergence: cosim_convergence
- training: training_history (Fig. 3d), predicted_vs_true (Fig. 5a), friction_curves (Fig. 5b)
- sweep: stick_slip_map
- plot_cli: cli_deflection (Fig. 6a from the command line's CSV), mesh_convergence (Fig. 1b)
- study_plot: pareto, law_fronts
"""

from __future__ import annotations

import math
from itertools import cycle
from pathlib import Path

import numpy as np

from .stick_slip_map import FAILED, SLIDING, STICK_SLIP, STUCK


def _pyplot():
    """matplotlib.pyplot on the Agg backend, imported when the first figure is drawn."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt

# ----------------------------------------------------------------------------- fmu_scene


def friction_force(runs: list, fidelity: str, path: Path) -> None:
    """Paper Fig. 6b: force of the belt on the tip over time, both laws."""
    plt = _pyplot()
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


def tip_deflection(runs: list, fidelity: str, breakaway: float, path: Path) -> None:
    """Tip deflection of every run at one fidelity and its deviation from the
    analytical-law embedded run; `breakaway` is marked."""
    plt = _pyplot()
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
    ax_u.axvline(breakaway, color="grey", lw=0.8, ls="--")
    ax_u.text(breakaway + 0.005, 0.3, f"breakaway {breakaway:.3f} s", color="grey", fontsize=8)
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


def friction_law(
    sweeps: dict[str, tuple[np.ndarray, np.ndarray]],
    zooms: dict[str, tuple[np.ndarray, np.ndarray]],
    path: Path,
) -> None:
    """Paper Fig. 5b through NeuralFriction.fmu: {label: (velocities, forces)} over the
    whole range and near v = 0."""
    plt = _pyplot()
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
    fig.suptitle(
        "Friction force of NeuralFriction.fmu at F_n = 100 N (signed output friction_force)"
    )
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


# ----------------------------------------------------------------------------- cosim_convergence


def cosim_convergence(
    rows: list,
    orders: dict[str, float],
    steps: list[float],
    asymptotic: list[float],
    t_first_cycle: float,
    t_end: float,
    path: Path,
) -> None:
    """Coupling error and wall time against the communication step, per scheme: the
    exponential law with the magnitude coupling (Jacobi, Gauss-Seidel; to both end
    times), the plain network with the signed coupling (Gauss-Seidel, Jacobi) and, for
    comparison, with the magnitude coupling (Gauss-Seidel), each against its own law's
    embedded run."""
    plt = _pyplot()
    fig, (ax_e, ax_w) = plt.subplots(1, 2, figsize=(13, 5.5))
    # label -> (style, also plot the error to t_end)
    styles = {
        "Jacobi": (dict(color="tab:blue", marker="o"), True),
        "Gauss-Seidel": (dict(color="tab:red", marker="s"), True),
        "plain, GS signed": (dict(color="tab:green", marker="D"), True),
        "plain, Jacobi signed": (dict(color="tab:cyan", marker="^"), False),
        "plain, GS magnitude": (dict(color="tab:grey", marker="x"), False),
    }
    names = {"Jacobi": "exponential, Jacobi", "Gauss-Seidel": "exponential, Gauss-Seidel"}
    for scheme, (style, full) in styles.items():
        rs = [r for r in rows if r.scheme == scheme]
        if not rs:
            continue
        hs = np.array([r.h for r in rs])
        name = names.get(scheme, scheme)
        ax_e.loglog(
            hs,
            [1e3 * r.error_first_cycle for r in rs],
            label=f"{name}, to {t_first_cycle} s (order {orders[scheme]:.2f})",
            **style,
        )
        if full:
            ax_e.loglog(
                hs,
                [1e3 * r.error_full for r in rs],
                ls="--",
                alpha=0.5,
                label=f"{name}, to {t_end} s",
                **style,
            )
        ax_w.loglog(hs, [r.wall for r in rs], label=name, **style)
    # Slope-1 reference through half the Gauss-Seidel error at h = 1e-3 (offset so that
    # it does not hide the Gauss-Seidel curve).
    anchor = next(r for r in rows if r.scheme == "Gauss-Seidel" and np.isclose(r.h, 1e-3))
    h_ref = np.array([min(steps), max(steps)])
    ax_e.loglog(
        h_ref,
        0.5e3 * anchor.error_first_cycle * h_ref / 1e-3,
        color="grey",
        ls=":",
        label="slope 1 reference (error ~ h)",
    )
    lo, hi = min(asymptotic), max(asymptotic)
    ax_e.axvspan(lo, hi, color="grey", alpha=0.08, label="range of the fitted order")
    ax_e.set_xlabel("communication step h (s)")
    ax_e.set_ylabel("max |tip deflection coupled - embedded, same law| (mm)")
    ax_e.set_title("Coupling error vs communication step", fontsize=10)
    ax_e.grid(True, which="both", alpha=0.3)
    ax_e.legend(fontsize=7, loc="lower right")
    ax_w.set_xlabel("communication step h (s)")
    ax_w.set_ylabel("wall time of the master loop (s)")
    ax_w.set_title("Wall time per run (0 .. 1.2 s)", fontsize=10)
    ax_w.grid(True, which="both", alpha=0.3)
    ax_w.legend(fontsize=8)
    fig.suptitle(
        "StickSlipBeam.fmu (beam fidelity) + NeuralFriction.fmu: exponential law "
        "(magnitude coupling) and plain network (signed coupling), fmpy FMU2Slave master",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


# ----------------------------------------------------------------------------- training


def training_history(history: dict[str, np.ndarray], report: dict, path: Path) -> None:
    """Paper Fig. 3d: MSE on both sets per L-BFGS iteration (history.csv's columns)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 5))
    it = history["iteration"]
    ax.semilogy(it, history["mse_train"], label=f"MSE, training set ({report['train_samples']} samples)", lw=1.4)
    ax.semilogy(it, history["mse_test"], label=f"MSE, test set ({report['test_samples']} samples)", lw=1.4, ls="--")
    ax.axhline(4.52, color="grey", lw=0.8, ls=":")
    ax.text(it[-1], 4.52 * 1.08, "paper: MSE test 4.52 N^2", fontsize=8, color="grey",
            ha="right")
    ax.set_xlabel("L-BFGS iteration")
    ax.set_ylabel("mean squared error (N^2)")
    ax.set_title(
        "Training history of the paper's network, 3 x 100 tanh, lambda = 0.004 (cf. paper "
        f"Fig. 3d)\nfinal: MSE test {report['mse_test']:.2f} N^2, R2 test "
        f"{report['r2_test']:.5f}, {report['iterations']} iterations, "
        f"{report['seconds']:.1f} s",
        fontsize=10,
    )
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def predicted_vs_true(
    truth: np.ndarray, predicted: np.ndarray, mse: float, r2: float, path: Path
) -> None:
    """Paper Fig. 5a: NeuralFriction.fmu on the test set against the noisy truth."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6.5, 6.2))
    ax.scatter(truth, predicted, s=5, alpha=0.5, label="test samples")
    lim = (min(truth.min(), predicted.min()) - 2, max(truth.max(), predicted.max()) + 2)
    ax.plot(lim, lim, color="black", lw=0.8, label="predicted = true")
    ax.set_xlim(lim)
    ax.set_ylim(lim)
    ax.set_aspect("equal")
    ax.set_xlabel("true friction force, noisy data (N)")
    ax.set_ylabel("NeuralFriction.fmu friction_force (N)")
    ax.set_title(
        f"Test set ({len(truth)} samples) through NeuralFriction.fmu (cf. paper Fig. 5a)\n"
        f"MSE {mse:.2f} N^2, R2 {r2:.5f} (paper: 4.52 N^2, 0.9974)",
        fontsize=10,
    )
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def friction_curves(
    x_train: np.ndarray,
    y_train: np.ndarray,
    curve: tuple[np.ndarray, np.ndarray],
    analytical: np.ndarray,
    path: Path,
) -> None:
    """Training data, the analytical law (`analytical` at the velocities of `curve`) and
    the network (`curve`: velocities, forces)."""
    plt = _pyplot()
    v, f_network = curve
    fig, ax = plt.subplots(figsize=(9, 5.5))
    ax.scatter(x_train[:, 0], y_train, s=3, color="lightgrey",
               label="training data (F_n 90 .. 110 N, noise 0.02 N)")
    ax.plot(v, analytical, color="black", lw=1.4, ls="--",
            label="analytical law (paper Eq. 6), F_n = 100 N")
    ax.plot(v, f_network, color="tab:blue", lw=1.6,
            label="NeuralFriction.fmu, paper-plain.json, F_n = 100 N")
    ax.axhline(0.0, color="grey", lw=0.6)
    ax.axvline(0.0, color="grey", lw=0.6)
    ax.set_xlabel("sliding velocity v (m/s)")
    ax.set_ylabel("friction force (N)")
    ax.set_title("Friction curves: data, analytical law and network (cf. paper Fig. 5b)",
                 fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=9, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


# ----------------------------------------------------------------------------- sweep


def stick_slip_map(
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
    plt = _pyplot()
    fig, (ax, ax_s) = plt.subplots(
        2, 1, figsize=(10, 8.5), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]}
    )
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    # Choice, Boolean or String values (e.g. --grid friction.law=exponential,coulomb)
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


# ----------------------------------------------------------------------------- plot_cli


def cli_deflection(runs: dict[str, dict], path: Path) -> None:
    """Tip deflection and belt force of every command-line run ({label: CSV columns})."""
    plt = _pyplot()
    fig, (ax_u, ax_f) = plt.subplots(2, 1, figsize=(9, 7), sharex=True)
    for label, data in runs.items():
        ax_u.plot(data["t"], [1e3 * u for u in data["tip_deflection"]], label=label, lw=1)
        ax_f.plot(data["t"], data["friction_force"], label=label, lw=0.8)
    ax_u.set_ylabel("tip deflection (mm)")
    ax_u.set_title("Paper scene: tip deflection (cf. paper Fig. 6a)")
    ax_u.grid(True, alpha=0.3)
    ax_u.legend(fontsize=8)
    ax_f.axhline(50.0, color="grey", ls="--", lw=0.8)
    ax_f.text(0.01, 51.0, "static limit mu_s F_n = 50 N", fontsize=8, color="grey")
    ax_f.set_xlabel("time t (s)")
    ax_f.set_ylabel("force of the belt on the tip (N)")
    ax_f.set_title("Holding force (stick) and kinetic friction force (slip)")
    ax_f.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def mesh_convergence(data: dict, path: Path) -> None:
    """Static tip-deflection error against nodes, per clamp (the CSV's columns; the clamps
    in the order the CSV lists them)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for clamp in dict.fromkeys(data["clamp"]):
        idx = [i for i, c in enumerate(data["clamp"]) if c == clamp]
        nodes = [data["nodes"][i] for i in idx]
        err = [100 * abs(data["error_euler_bernoulli"][i]) for i in idx]
        ax.loglog(nodes, err, "o-", label=f"Q8, {clamp} clamp")
    ax.axhline(0.04, color="grey", ls="--", lw=0.8)
    ax.text(70, 0.045, "paper: 0.04 % at element size 0.02 m", fontsize=8, color="grey")
    ax.set_xlabel("number of nodes")
    ax.set_ylabel("|tip deflection error| vs Euler-Bernoulli (%)")
    ax.set_title("Static mesh convergence, P = 50 N (cf. paper Fig. 1b)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


# ----------------------------------------------------------------------------- study_plot

# One marker per fidelity level and one colour per integrator, handed out in the order
# study.csv lists them (the binary's words, not retyped here).
MARKERS = ("o", "s", "^", "D", "v")
COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red")


def pareto(rows: list[dict], front: list[dict], front_labels: list[str], path: Path) -> None:
    """RMS error against wall time of every study run, the front joined and labelled."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(10, 6.5))
    floor = min(float(r["err_rms_m"]) for r in rows if float(r["err_rms_m"]) > 0) / 2
    levels = dict.fromkeys(r["level"] for r in rows)
    schemes = dict.fromkeys(r["integrator"] for r in rows)
    for level, marker in zip(levels, cycle(MARKERS)):
        for scheme, colour in zip(schemes, cycle(COLOURS)):
            pts = [r for r in rows if r["level"] == level and r["integrator"] == scheme]
            if not pts:
                continue
            ax.scatter(
                [float(r["wall_s"]) for r in pts],
                [max(float(r["err_rms_m"]), floor) * 1e3 for r in pts],
                marker=marker,
                facecolors="none",
                edgecolors=colour,
                s=30,
                label=f"{level}, {scheme}",
            )
    ax.plot(
        [float(r["wall_s"]) for r in front],
        [max(float(r["err_rms_m"]), floor) * 1e3 for r in front],
        "k-",
        lw=1,
        marker=".",
        label="Pareto front",
    )
    for r, text in zip(front, front_labels):
        ax.annotate(
            text,
            (float(r["wall_s"]), max(float(r["err_rms_m"]), floor) * 1e3),
            fontsize=6,
            xytext=(4, 2),
            textcoords="offset points",
        )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time of the 1.2 s paper scene (s)")
    ax.set_ylabel("RMS tip-deflection error against the reference (mm)")
    ax.set_title("Speed against accuracy (stickslip study)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def law_fronts(fronts: dict[str, list[dict]], path: Path) -> None:
    """The Pareto front of each friction law of a study (`stickslip study --laws`), RMS
    error against wall time in one log-log axes: each against its own law's reference."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(8, 5.5))
    for (law, front), colour in zip(fronts.items(), cycle(COLOURS + ("tab:purple", "tab:brown"))):
        finite = [r for r in front if float(r["err_rms_m"]) > 0]
        if not finite:
            continue
        ax.plot(
            [float(r["wall_s"]) for r in finite],
            [float(r["err_rms_m"]) * 1e6 for r in finite],
            "-",
            color=colour,
            marker="o",
            ms=4,
            lw=1.2,
            label=law or "the scene's law",
        )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("wall time of the run (s)")
    ax.set_ylabel("RMS tip-deflection error against the law's own reference (um)")
    ax.set_title("Pareto front per friction law (stickslip study --laws)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)
