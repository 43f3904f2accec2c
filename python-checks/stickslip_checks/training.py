"""The network's training, its accuracy through NeuralFriction.fmu, and its peer.

1. Trains the paper's network with `stickslip train` at the paper's settings (synthetic
   data N = 5000, 70/30 split, 3 x 100 tanh, lambda = 0.004, 200 L-BFGS iterations,
   seed 2) into OUT/training/: weights, report, history and the exact split.
2. Checks that the weights equal the shipped weights/paper-plain.json byte for byte
   (the network inside the FMUs is the one trained here).
3. Evaluates NeuralFriction.fmu (law neural, its default paper-plain.json) on every
   test sample through fmi2DoStep and compares its MSE with the trainer's report: the FMU
   and the trainer must agree to 1e-9 relative (same network, inputs inside the
   training range, so the FMU's clamping never acts).
4. Fits scikit-learn's MLPRegressor (100, 100, 100), tanh, lbfgs on the very same split
   (sklearn_peer.py) and prints both fits side by side, with the training-time ratio.
5. Plots: OUT/training_history.png (paper Fig. 3d), OUT/predicted_vs_true.png (Fig. 5a)
   and OUT/friction_curves.png (Fig. 5b: data, analytical law and the FMU's network).

Exits with status 1 if a check fails.

Usage: python training.py [OUT_DIR]   (default: <repo>/out)
"""

from __future__ import annotations

import csv
import json
import sys
import time
from pathlib import Path

import numpy as np

import fmu_scene
import sklearn_peer
from fmu_scene import DT, FRICTION, LAW, REPO, exponential_law

ITERATIONS, SEED, LAMBDA = 200, 2, 0.004  # the paper's settings (src/neural/train.rs)
SHIPPED = REPO / "weights" / "paper-plain.json"
FMU_AGREEMENT = 1e-9  # relative MSE difference FMU vs trainer


def predict_with_fmu(fmus: fmu_scene.Fmus, features: np.ndarray) -> np.ndarray:
    """Signed friction force (N) of NeuralFriction.fmu for each (v, F_n) row, one
    communication step per sample (the FMU has no state, so the order does not matter)."""
    vf = fmus.vr[FRICTION]
    slave = fmus.slave(FRICTION, "test-set")
    slave.instantiate()
    forces = np.empty(len(features))
    try:
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
        slave.setInteger([vf["law"]], [LAW["neural"]])
        slave.exitInitializationMode()
        inputs = [vf["sliding_velocity"], vf["normal_force"]]
        output = [vf["friction_force"]]
        t = 0.0
        for k, (v, fn) in enumerate(features):
            slave.setReal(inputs, [float(v), float(fn)])
            slave.doStep(currentCommunicationPoint=t, communicationStepSize=DT)
            t += DT
            forces[k] = slave.getReal(output)[0]
        slave.terminate()
    finally:
        slave.freeInstance()
    return forces


def read_history(path: Path) -> dict[str, np.ndarray]:
    with path.open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    return {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}


def plot_history(history: dict[str, np.ndarray], report: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 5))
    it = history["iteration"]
    ax.semilogy(it, history["mse_train"], label="MSE, training set (3500 samples)", lw=1.4)
    ax.semilogy(it, history["mse_test"], label="MSE, test set (1500 samples)", lw=1.4, ls="--")
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


def plot_predicted_vs_true(truth: np.ndarray, predicted: np.ndarray, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    mse, r2 = sklearn_peer.metrics(predicted, truth)
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
        f"Test set (1500 samples) through NeuralFriction.fmu (cf. paper Fig. 5a)\n"
        f"MSE {mse:.2f} N^2, R2 {r2:.5f} (paper: 4.52 N^2, 0.9974)",
        fontsize=10,
    )
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_curves(
    x_train: np.ndarray, y_train: np.ndarray, curve: tuple[np.ndarray, np.ndarray], path: Path
) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    v, f_network = curve
    fig, ax = plt.subplots(figsize=(9, 5.5))
    ax.scatter(x_train[:, 0], y_train, s=3, color="lightgrey",
               label="training data (F_n 90 .. 110 N, noise 0.02 N)")
    ax.plot(v, exponential_law(v), color="black", lw=1.4, ls="--",
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


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    out = Path(argv[0]) if argv else REPO / "out"
    workdir = out / "training"
    failures: list[str] = []
    try:
        paths = fmu_scene.fmu_paths()
    except FileNotFoundError as error:
        print(f"training: {error}", file=sys.stderr)
        return 2
    binary = sklearn_peer.find_binary()

    print(f"== stickslip train, the paper's settings -> {workdir}")
    report = sklearn_peer.train_rust(ITERATIONS, SEED, LAMBDA, binary, workdir)
    print(
        f"  {report['iterations']} iterations in {report['seconds']:.2f} s: MSE test "
        f"{report['mse_test']:.4f} N^2, R2 test {report['r2_test']:.5f} (paper: 4.52, 0.9974)"
    )
    same = (workdir / "weights.json").read_bytes() == SHIPPED.read_bytes()
    print(f"  weights equal the shipped {SHIPPED.relative_to(REPO)} byte for byte: {same}")
    if not same:
        failures.append(f"retrained weights differ from {SHIPPED}")

    x_train, y_train, _ = sklearn_peer.read_split(workdir / "split" / "train.csv")
    x_test, y_test, _ = sklearn_peer.read_split(workdir / "split" / "test.csv")
    fmus = fmu_scene.Fmus(paths)
    try:
        began = time.perf_counter()
        predicted = predict_with_fmu(fmus, x_test)
        fmu_seconds = time.perf_counter() - began
        curve = fmu_scene.friction_sweep(fmus, "neural")
    finally:
        fmus.close()
    mse, r2 = sklearn_peer.metrics(predicted, y_test)
    relative = abs(mse - report["mse_test"]) / report["mse_test"]
    print(
        f"\n== NeuralFriction.fmu on the {len(y_test)} test samples ({fmu_seconds:.2f} s): "
        f"MSE {mse:.4f} N^2, R2 {r2:.5f}; relative difference to the trainer's MSE "
        f"{relative:.1e} (must be < {FMU_AGREEMENT:g})"
    )
    if not relative < FMU_AGREEMENT:
        failures.append(f"FMU MSE {mse} differs from the trainer's {report['mse_test']}")

    print("\n== scikit-learn peer on the same split")
    peer = sklearn_peer.fit_sklearn(workdir / "split", ITERATIONS, SEED, LAMBDA)
    result = sklearn_peer.side_by_side(report, peer, ITERATIONS, LAMBDA)
    sklearn_peer.print_table(result)
    (out / "sklearn_peer.json").write_text(json.dumps(result, indent=2) + "\n")

    written = [out / "training_history.png", out / "predicted_vs_true.png",
               out / "friction_curves.png", out / "sklearn_peer.json"]
    plot_history(read_history(workdir / "history.csv"), report, written[0])
    plot_predicted_vs_true(y_test, predicted, written[1])
    plot_curves(x_train, y_train, curve, written[2])
    print()
    for p in written:
        print(f"wrote {p}")
    return fmu_scene.report_failures(failures)


if __name__ == "__main__":
    sys.exit(main())
