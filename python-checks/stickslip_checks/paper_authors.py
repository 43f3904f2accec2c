"""The paper authors' own network (their MATLAB fitrnet, data/paper-authors/) in the
paper scene, beside the analytical law, through StickSlipBeam.fmu (fmpy).

1. Converts data/paper-authors/trained_regression_nn_friction_model.mat to ONNX
   (stickslip_checks.fitrnet: Fn and vs standardised, 3 x 100 tanh, linear output Ff,
   the signed friction force: our plain variant) into OUT_DIR/paper_authors_network.onnx,
   and evaluates it through NeuralFriction.fmu on their test file (MSE, R^2; the paper:
   4.52 N^2, 0.9974).
2. Runs the paper scene (0 .. STOP s, 1 ms output) at every structural fidelity with
   the analytical exponential law and with their network (friction.weights = the .onnx
   file), and prints per fidelity the stick-slip period of each (mean spacing of the
   major-slip onsets, slip_metrics.period) and their relative difference, and the same
   difference from a least-squares line through the onsets (a second estimate: the two
   differ by what the cycles' irregularity leaves uncertain).
3. Plots the tip deflection of both at plane-stress fidelity, the paper's mesh, and
   their difference: OUT_DIR/paper_authors_network.png.

Usage: python -m stickslip_checks.paper_authors [OUT_DIR]   (or stickslip-paper-authors;
default <repo>/out). Exits 2 if the FMUs are missing; the checks are pytest's
(tests/test_paper_authors_network.py).
"""

from __future__ import annotations

import dataclasses
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import fitrnet, plots, scene, sklearn_peer
from .artifacts import BEAM, REPO, Fmus, fidelities
from .friction_points import fmi2_forces
from .runner import find_fmus, parser, progress

FOLDER = REPO / "data" / "paper-authors"
MAT = FOLDER / "trained_regression_nn_friction_model.mat"
TEST_CSV = FOLDER / "exponential_friction_model_samples_test.csv"
# s: about 75 major slips. The sawtooth is not strictly periodic (the beam's higher modes
# make bursts of short slips that move an onset by up to 30 ms), so the period needs many
# cycles: over 10 s the plane-stress difference reads -2.8 %, over 20 s -2.4 %.
STOP = 20.0
PLOT_FIDELITY = scene.PLOT_FIDELITY
PLOT_SECONDS = 3.0  # the figure shows the first 3 s (about 11 cycles); the periods use all


def convert(path: Path) -> Path:
    """Their network as ONNX at `path` (roles and ranges from its predictor names and
    stored training inputs)."""
    import onnx

    network = fitrnet.read_fitrnet(MAT)
    onnx.save(fitrnet.to_onnx(network, network.features()), path)
    return path


def test_points() -> tuple[np.ndarray, np.ndarray]:
    """Their test file as (v [m/s], F_n [N]) rows and the friction force Ff (N)."""
    data = np.genfromtxt(TEST_CSV, delimiter=",", names=True)
    return np.column_stack([data["vs"], data["Fn"]]), np.asarray(data["Ff"], float)


@dataclass
class Comparison:
    """The paper scene at one fidelity with the analytical law and with their network
    (scene.Run, metrics filled; the network's against the analytical run)."""

    fidelity: str
    analytical: scene.Run
    network: scene.Run

    @property
    def period_difference(self) -> float | None:
        """(P_network - P_analytical) / P_analytical; None without two major slips each."""
        ours, theirs = self.analytical.metrics["period"], self.network.metrics["period"]
        if ours is None or theirs is None:
            return None
        return (theirs - ours) / ours

    @property
    def fitted_difference(self) -> float | None:
        """The same from the slope of a least-squares line through each run's major-slip
        onsets (onset against its index) after the first, which ends the start's longer
        cycle; None without four major slips each."""
        slopes = []
        for run in (self.analytical, self.network):
            onsets = np.array([s.onset for s in run.metrics["slips"]])[1:]
            if len(onsets) < 3:
                return None
            slopes.append(np.polyfit(np.arange(len(onsets)), onsets, 1)[0])
        return (slopes[1] - slopes[0]) / slopes[0]


def compare(fmus: Fmus, weights: str, fidelity: str, stop_time: float = STOP) -> Comparison:
    """Both runs at `fidelity` over 0 .. stop_time, with their metrics."""
    analytical = scene.run_embedded(fmus, fidelity, "exponential", stop_time=stop_time)
    network = scene.run_embedded(fmus, fidelity, "neural", weights, stop_time=stop_time)
    analytical.friction, network.friction = "exponential", "neural paper authors"
    analytical.metrics = scene.summarise(analytical, None)
    network.metrics = scene.summarise(network, analytical)
    return Comparison(fidelity, analytical, network)


def line(c: Comparison) -> str:
    """The printed line of one fidelity: both periods and their relative difference."""
    a, n = c.analytical.metrics, c.network.metrics
    if c.fitted_difference is None:
        return (f"{c.fidelity}: fewer than four major slips in {c.analytical.time[-1]:.1f} s "
                f"(analytical {a['major_slips']}, network {n['major_slips']})")
    return (f"{c.fidelity}: period analytical law {1e3 * a['period']:.2f} ms, authors' network "
            f"{1e3 * n['period']:.2f} ms, relative difference {100 * c.period_difference:+.2f} % "
            f"({a['major_slips']} and {n['major_slips']} major slips in "
            f"{c.analytical.time[-1]:.0f} s; least-squares fit of the onsets: "
            f"{100 * c.fitted_difference:+.2f} %)")


def plot(c: Comparison, path: Path) -> None:
    """Tip deflection of both runs and the network's minus the analytical one."""
    plt = plots._pyplot()
    fig, (ax_u, ax_d) = plt.subplots(2, 1, figsize=(10, 7), sharex=True,
                                     gridspec_kw={"height_ratios": [3, 2]})
    a, n = c.analytical, c.network
    window = a.time <= PLOT_SECONDS
    a, n = _head(a, window), _head(n, window)
    ax_u.plot(a.time, 1e3 * a.tip_deflection, color="black", lw=1.4,
              label=f"analytical law (Eq. 6), period {1e3 * a.metrics['period']:.1f} ms")
    ax_u.plot(n.time, 1e3 * n.tip_deflection, color="tab:red", lw=1.1,
              label=f"the paper authors' network (fitrnet, via ONNX), period "
                    f"{1e3 * n.metrics['period']:.1f} ms")
    ax_u.set_ylabel("tip deflection (mm)")
    ax_u.set_title(f"Paper scene through StickSlipBeam.fmu (fmpy), {c.fidelity} fidelity: the "
                   f"authors' network beside the analytical law\nperiods over "
                   f"{c.analytical.time[-1]:.0f} s, difference {100 * c.period_difference:+.2f} %; "
                   f"first {PLOT_SECONDS:g} s shown", fontsize=10)
    ax_u.legend(fontsize=9, loc="lower right")
    ax_d.plot(n.time, 1e3 * (n.tip_deflection - a.tip_deflection), color="tab:red", lw=1.0)
    ax_d.axhline(0.0, color="black", lw=0.8)
    ax_d.set_xlabel("time t (s)")
    ax_d.set_ylabel("network minus analytical (mm)")
    for axis in (ax_u, ax_d):
        axis.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _head(run: scene.Run, window: np.ndarray) -> scene.Run:
    """`run` cut to the samples of `window` (its metrics kept: they are of the whole run)."""
    return dataclasses.replace(run, time=run.time[window],
                               tip_deflection=run.tip_deflection[window])


def main(argv: list[str] | None = None) -> int:
    out = parser("stickslip-paper-authors", __doc__).parse_args(argv).out
    paths = find_fmus("paper_authors")
    if paths is None:
        return 2
    out.mkdir(parents=True, exist_ok=True)
    weights = str(convert(out / "paper_authors_network.onnx").resolve())
    print(f"converted {MAT.relative_to(REPO)} -> {weights}")
    fmus = Fmus(paths)
    try:
        points, truth = test_points()
        mse, r2 = sklearn_peer.metrics(fmi2_forces(fmus, weights, points), truth)
        print(f"NeuralFriction.fmu with it on their test file ({len(truth)} samples): MSE "
              f"{mse:.4f} N^2, R^2 {r2:.5f} (paper: 4.52, 0.9974)")
        print(f"== Paper scene, 0 .. {STOP:g} s: analytical law and the authors' network")
        comparisons = {}
        for fidelity in fidelities(fmus.models[BEAM]):
            progress(f"  {fidelity} ...")
            comparisons[fidelity] = compare(fmus, weights, fidelity)
            print("  " + line(comparisons[fidelity]))
    finally:
        fmus.close()
    path = out / "paper_authors_network.png"
    plot(comparisons[PLOT_FIDELITY], path)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
