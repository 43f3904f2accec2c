"""The network's training, its accuracy through NeuralFriction.fmu, and its peer.

1. Trains the paper's network with `stickslip train` into OUT/training/ (weights,
   report, history and the exact split), with the iteration limit, seed and lambda that
   the `training` section of weights/paper-plain.json records (the paper's: synthetic
   data N = 5000, 70/30 split, 3 x 100 tanh, lambda = 0.004, 200 L-BFGS iterations,
   seed 2; the rest are `stickslip train`'s defaults).
2. Checks that the weights equal the shipped weights/paper-plain.json byte for byte
   (the network inside the FMUs is the one trained here).
3. Evaluates NeuralFriction.fmu (law neural, its default paper-plain.json) on every
   test sample through fmi2DoStep and compares its MSE with the trainer's report: the FMU
   and the trainer must agree to 1e-9 relative (same network, inputs inside the
   training range, so the FMU's clamping never acts).
4. Fits scikit-learn's MLPRegressor (100, 100, 100), tanh, lbfgs on the very same split
   (sklearn_peer) and prints both fits side by side, with the training-time ratio.
5. Plots: OUT/training_history.png (paper Fig. 3d), OUT/predicted_vs_true.png (Fig. 5a)
   and OUT/friction_curves.png (Fig. 5b: data, analytical law and the FMU's network).

Exits with status 1 if a check fails.

Usage: python -m stickslip_checks.training [OUT_DIR]   (or stickslip-training;
default: <repo>/out)
"""

from __future__ import annotations

import csv
import json
import sys
import time
from pathlib import Path

import numpy as np

from . import plots, sklearn_peer
from .artifacts import REPO, SHIPPED_WEIGHTS, Fmus, find_binary
from .fmu_scene import drive_friction, friction_sweep
from .runner import find_fmus, out_dir, report_failures

FMU_AGREEMENT = 1e-9  # relative MSE difference FMU vs trainer


def predict_with_fmu(fmus: Fmus, features: np.ndarray) -> np.ndarray:
    """Signed friction force (N) of NeuralFriction.fmu for each (v, F_n) row, one
    communication step per sample (the FMU has no state, so the order does not matter)."""
    inputs = {
        "sliding_velocity": features[:, 0].astype(float),
        "normal_force": features[:, 1].astype(float),
    }
    return drive_friction(fmus, "neural", None, inputs, "test-set")


def read_history(path: Path) -> dict[str, np.ndarray]:
    with path.open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    return {key: np.array([float(r[key]) for r in rows]) for key in rows[0]}


def main(argv: list[str] | None = None) -> int:
    out = out_dir(argv, create=False)  # made with its training/ folder below
    workdir = out / "training"
    failures: list[str] = []
    paths = find_fmus("training")
    if paths is None:
        return 2
    binary = find_binary()

    iterations, seed, lam = sklearn_peer.shipped_settings()
    print(f"== stickslip train, the paper's settings -> {workdir}")
    report = sklearn_peer.train_rust(iterations, seed, lam, binary, workdir)
    print(
        f"  {report['iterations']} iterations in {report['seconds']:.2f} s: MSE test "
        f"{report['mse_test']:.4f} N^2, R2 test {report['r2_test']:.5f} (paper: 4.52, 0.9974)"
    )
    same = (workdir / "weights.json").read_bytes() == SHIPPED_WEIGHTS.read_bytes()
    print(f"  weights equal the shipped {SHIPPED_WEIGHTS.relative_to(REPO)} byte for byte: {same}")
    if not same:
        failures.append(f"retrained weights differ from {SHIPPED_WEIGHTS}")

    x_train, y_train, _ = sklearn_peer.read_split(workdir / "split" / "train.csv")
    x_test, y_test, _ = sklearn_peer.read_split(workdir / "split" / "test.csv")
    fmus = Fmus(paths)
    try:
        began = time.perf_counter()
        predicted = predict_with_fmu(fmus, x_test)
        fmu_seconds = time.perf_counter() - began
        curve = friction_sweep(fmus, "neural")
        # The analytical law of the plot: the FMU's exponential law (paper Eq. 6).
        _, analytical = friction_sweep(fmus, "exponential")
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
    peer = sklearn_peer.fit_sklearn(workdir / "split", iterations, seed, lam)
    result = sklearn_peer.side_by_side(report, peer, iterations, lam)
    sklearn_peer.print_table(result)
    (out / "sklearn_peer.json").write_text(json.dumps(result, indent=2) + "\n")

    written = [out / "training_history.png", out / "predicted_vs_true.png",
               out / "friction_curves.png", out / "sklearn_peer.json"]
    plots.training_history(read_history(workdir / "history.csv"), report, written[0])
    plots.predicted_vs_true(y_test, predicted, mse, r2, written[1])
    plots.friction_curves(x_train, y_train, curve, analytical, written[2])
    print()
    for p in written:
        print(f"wrote {p}")
    return report_failures(failures)


if __name__ == "__main__":
    sys.exit(main())
