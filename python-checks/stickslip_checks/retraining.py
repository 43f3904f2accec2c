"""The network's training, its accuracy through NeuralFriction.fmu, and its peer (the
library of the training entry point).

1. Trains the paper's network with `stickslip train` into OUT/training/ (weights,
   report, history and the exact split), with the iteration limit, seed and lambda that
   the `training` section of weights/paper-plain.json records (the paper's: synthetic
   data N = 5000, 70/30 split, 3 x 100 tanh, lambda = 0.004, 200 L-BFGS iterations,
   seed 2; the rest are `stickslip train`'s defaults).
2. Compares the weights with the shipped weights/paper-plain.json byte for byte
   (the network inside the FMUs is the one trained here).
3. Evaluates NeuralFriction.fmu (law neural, `weights` = the trained file; natively the
   shipped paper-plain.json's bytes) on every test sample through fmi2DoStep and
   compares its MSE with the trainer's report: the FMU and the trainer must agree to
   FMU_AGREEMENT relative (same network, inputs inside the training range, so the FMU's
   clamping never acts).
4. Fits scikit-learn's MLPRegressor (100, 100, 100), tanh, lbfgs on the very same split
   (sklearn_peer) and prints both fits side by side, with the training-time ratio.
5. Plots: OUT/training_history.png (paper Fig. 3d), OUT/predicted_vs_true.png (Fig. 5a)
   and OUT/friction_curves.png (Fig. 5b: data, analytical law and the FMU's network).

The checks of 2. and 3. are tests/test_training.py's.
"""

from __future__ import annotations

import csv
import json
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from . import plots, sklearn_peer
from .artifacts import SHIPPED_WEIGHTS, Fmus
from .scene import drive_friction, friction_sweep

FMU_AGREEMENT = 1e-9  # relative MSE difference FMU vs trainer

# The trainer is CPU-dependent on purpose (docs/decisions.md, "The same bits on every
# CPU"): its synthetic data and batch activation call the C library's exp, and
# matrixmultiply picks its kernel by CPU. The shipped weights were trained with glibc's
# x86_64 FMA kernel of exp, which glibc selects exactly when the CPU has FMA and AVX2 -
# the condition under which matrixmultiply selects its FMA/AVX2 kernel too. Arguments at
# which that exp and glibc's SSE2 kernel differ in the last bit (145 of 200,000 random
# points in [-10, 10], found with GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA), with the
# FMA kernel's result: where exp gives these bits, the trainer runs the shipped
# weights' kernels.
SHIPPED_EXP_KERNEL = {
    "0x1.5636c7a7e7930p+2": "0x1.a3fe7dcef9fc5p+7",
    "0x1.d83e6da6ef7c0p-1": "0x1.41f1fd0c5f00fp+1",
    "0x1.245b7159f5a7cp+2": "0x1.816fa86a4c6c9p+6",
    "-0x1.d7b5930c752f0p+1": "0x1.9b191b96001cbp-6",
}


def trainer_kernels_differ() -> str | None:
    """None when `stickslip train` runs here with the kernels the shipped weights were
    trained with (SHIPPED_EXP_KERNEL), else why not. exp is evaluated in a child
    process, as the trainer runs: under qemu-user only this process is emulated, and
    both inherit the environment (GLIBC_TUNABLES)."""
    probe = ("import math, sys\n"
             "for x in sys.argv[1:]: print(math.exp(float.fromhex(x)).hex())")
    run = subprocess.run([sys.executable, "-c", probe, *SHIPPED_EXP_KERNEL],
                         capture_output=True, text=True, check=True)
    got = run.stdout.split()
    want = list(SHIPPED_EXP_KERNEL.values())
    if got == want:
        return None
    return ("the C library's exp here is not the x86_64 glibc FMA kernel the shipped "
            f"weights were trained with (exp at {list(SHIPPED_EXP_KERNEL)} gives {got}, "
            f"that kernel {want}); the trainer is CPU-dependent by design "
            "(docs/decisions.md), so its weights are not the shipped bytes here")


def predict_with_fmu(fmus: Fmus, features: np.ndarray, weights: Path) -> np.ndarray:
    """Signed friction force (N) of NeuralFriction.fmu with the weights file `weights` for
    each (v, F_n) row, one communication step per sample (the FMU has no state, so the
    order does not matter)."""
    inputs = {
        "sliding_velocity": features[:, 0].astype(float),
        "normal_force": features[:, 1].astype(float),
    }
    return drive_friction(fmus, "neural", str(weights.resolve()), inputs, "test-set")


def read_history(path: Path) -> dict[str, np.ndarray]:
    with path.open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    return {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}


@dataclass
class Retraining:
    """What training measures: the trainer's report, whether its weights equal the
    shipped ones byte for byte, NeuralFriction.fmu on the test set (MSE in N^2, R^2,
    its relative difference to the trainer's MSE, wall time)."""

    workdir: Path
    report: dict
    weights_equal: bool
    predicted: np.ndarray
    mse: float
    r2: float
    relative: float
    fmu_seconds: float


def train(binary: Path, workdir: Path) -> dict:
    """`stickslip train` with the shipped settings into `workdir`; its report."""
    return sklearn_peer.train_rust(*sklearn_peer.shipped_settings(), binary, workdir)


def evaluate(fmus: Fmus, workdir: Path, report: dict) -> Retraining:
    """The trained weights against the shipped ones, and NeuralFriction.fmu with the
    trained weights on the test set of `workdir`'s split (the trained weights, not the
    FMU's packaged ones: on a CPU whose trainer kernels differ they are another network,
    trainer_kernels_differ)."""
    x_test, y_test, _ = sklearn_peer.read_split(workdir / "split" / "test.csv")
    began = time.perf_counter()
    predicted = predict_with_fmu(fmus, x_test, workdir / "weights.json")
    fmu_seconds = time.perf_counter() - began
    mse, r2 = sklearn_peer.metrics(predicted, y_test)
    return Retraining(
        workdir=workdir,
        report=report,
        weights_equal=(workdir / "weights.json").read_bytes() == SHIPPED_WEIGHTS.read_bytes(),
        predicted=predicted,
        mse=mse,
        r2=r2,
        relative=abs(mse - report["mse_test"]) / report["mse_test"],
        fmu_seconds=fmu_seconds,
    )


def fit_peer(workdir: Path, report: dict) -> dict:
    """scikit-learn's fit on `workdir`'s split beside the trainer's report
    (sklearn_peer.side_by_side)."""
    iterations, seed, lam = sklearn_peer.shipped_settings()
    peer = sklearn_peer.fit_sklearn(workdir / "split", iterations, seed, lam)
    return sklearn_peer.side_by_side(report, peer, iterations, lam)


def write_outputs(fmus: Fmus, result: Retraining, peer: dict, out: Path) -> list[Path]:
    """sklearn_peer.json and the three figures in `out`."""
    x_train, y_train, _ = sklearn_peer.read_split(result.workdir / "split" / "train.csv")
    _, y_test, _ = sklearn_peer.read_split(result.workdir / "split" / "test.csv")
    curve = friction_sweep(fmus, "neural")
    # The analytical law of the plot: the FMU's exponential law (paper Eq. 6).
    _, analytical = friction_sweep(fmus, "exponential")
    written = [out / "training_history.png", out / "predicted_vs_true.png",
               out / "friction_curves.png", out / "sklearn_peer.json"]
    (out / "sklearn_peer.json").write_text(json.dumps(peer, indent=2) + "\n")
    history = read_history(result.workdir / "history.csv")
    plots.training_history(history, result.report, written[0])
    plots.predicted_vs_true(y_test, result.predicted, result.mse, result.r2, written[1])
    plots.friction_curves(x_train, y_train, curve, analytical, written[2])
    return written
