"""Independent peer for the Rust neural friction law (issue 3).

Runs `stickslip train` on the paper's synthetic data, exports the exact train/test
split it used (--export-data), fits scikit-learn's MLPRegressor with the same
architecture (100, 100, 100), tanh, L-BFGS, standardised inputs and the same iteration
limit on that very split, and prints both fits side by side with their training times.

Regularisation: the Rust loss is MSE + lambda/2 ||W||^2 (raw target, standardised
inputs); scikit-learn minimises (1/2) MSE + alpha/(2 n) ||W||^2, so the same penalty is
alpha = n * lambda / 2 (alpha = 7 for lambda = 0.004, n = 3500).

Times: "ours" is the optimisation time the Rust report gives (`seconds`, data
generation and I/O excluded); scikit-learn's is the wall time of `fit` alone
(standardisation excluded). Both run in this one invocation on the same machine.

Usage: python -m stickslip_checks.sklearn_peer (or stickslip-sklearn-peer)
       [--iterations N] [--seed S] [--lambda L] [--binary PATH] [--json OUT.json]
The iteration limit, seed and lambda default to the settings the shipped network was
trained with (the `training` section of weights/paper-plain.json: max_iterations, seed,
lambda). The binary defaults to $STICKSLIP_BIN, else it is built with
`cargo build --release` (artifacts.find_binary).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from sklearn.neural_network import MLPRegressor
from sklearn.preprocessing import StandardScaler

from .artifacts import find_binary, shipped_training
from .tables import format_table


def shipped_settings() -> tuple[int, int, float]:
    """(iteration limit, seed, lambda) the shipped network was trained with: its weights
    file's `training` section (max_iterations, seed, lambda)."""
    training = shipped_training()
    return int(training["max_iterations"]), int(training["seed"]), float(training["lambda"])


def read_split(path: Path) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Features and target of one exported CSV (header `name[unit],...`)."""
    with path.open() as handle:
        header = handle.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return data[:, :-1], data[:, -1], header


def metrics(predicted: np.ndarray, truth: np.ndarray) -> tuple[float, float]:
    """MSE and R^2 (1 - SS_res / SS_tot), as the Rust report computes them."""
    residual = predicted - truth
    mse = float(np.mean(residual**2))
    r2 = float(1.0 - np.sum(residual**2) / np.sum((truth - truth.mean()) ** 2))
    return mse, r2


def shipped_generator() -> str:
    """The `stickslip train --generator` of the shipped network's data: `former` when its
    recorded settings have no relative noise (the generator before the authors' data were
    read added 0.02 N; see docs/decisions.md), else `authors`."""
    synthetic = shipped_training()["synthetic"]
    return "authors" if synthetic.get("relative_noise_std", 0.0) > 0 else "former"


def train_rust(iterations: int, seed: int, lam: float, binary: Path, workdir: Path) -> dict:
    """`stickslip train` on the shipped network's synthetic data (`shipped_generator`)
    into `workdir`: weights.json, report.json, history.csv and the split (split/train.csv,
    split/test.csv). Returns the report plus its wall time."""
    workdir.mkdir(parents=True, exist_ok=True)
    report_path = workdir / "report.json"
    command = [
        str(binary),
        "train",
        "--iterations",
        str(iterations),
        "--seed",
        str(seed),
        "--lambda",
        str(lam),
        "--generator",
        shipped_generator(),
        "--out",
        str(workdir / "weights.json"),
        "--report",
        str(report_path),
        "--history",
        str(workdir / "history.csv"),
        "--export-data",
        str(workdir / "split"),
        "--quiet",
    ]
    started = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True, text=True)
    report = json.loads(report_path.read_text())
    report["wall_seconds_with_io"] = time.perf_counter() - started
    return report


def fit_sklearn(split_dir: Path, iterations: int, seed: int, lam: float) -> dict:
    """MLPRegressor with our architecture and penalty on the exported split."""
    x_train, y_train, header = read_split(split_dir / "train.csv")
    x_test, y_test, _ = read_split(split_dir / "test.csv")
    scaler = StandardScaler().fit(x_train)
    alpha = len(y_train) * lam / 2.0
    model = MLPRegressor(
        hidden_layer_sizes=(100, 100, 100),
        activation="tanh",
        solver="lbfgs",
        alpha=alpha,
        max_iter=iterations,
        random_state=seed,
    )
    started = time.perf_counter()
    with np.errstate(all="ignore"):
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # "lbfgs failed to converge" at max_iter
            model.fit(scaler.transform(x_train), y_train)
    seconds = time.perf_counter() - started
    mse_train, r2_train = metrics(model.predict(scaler.transform(x_train)), y_train)
    mse_test, r2_test = metrics(model.predict(scaler.transform(x_test)), y_test)
    return {
        "columns": header,
        "train_samples": len(y_train),
        "test_samples": len(y_test),
        "alpha": alpha,
        "mse_train": mse_train,
        "mse_test": mse_test,
        "r2_train": r2_train,
        "r2_test": r2_test,
        "iterations": int(model.n_iter_),
        "seconds": seconds,
    }


def side_by_side(ours: dict, peer: dict, iterations: int, lam: float) -> dict:
    """Our training report and the peer's fit as one result (table, JSON)."""
    peer = dict(peer)
    return {
        "columns": peer.pop("columns"),
        "train_samples": peer.pop("train_samples"),
        "test_samples": peer.pop("test_samples"),
        "iterations_limit": iterations,
        "lambda": lam,
        "alpha": peer.pop("alpha"),
        "ours": {
            key: ours[key]
            for key in (
                "mse_train", "mse_test", "r2_train", "r2_test", "iterations", "seconds",
                "wall_seconds_with_io",
            )
        },
        "sklearn": peer,
        "time_ratio_sklearn_over_ours": peer["seconds"] / ours["seconds"],
    }


def run(iterations: int, seed: int, lam: float, binary: Path, workdir: Path) -> dict:
    """Both fits on one split, side by side."""
    ours = train_rust(iterations, seed, lam, binary, workdir)
    peer = fit_sklearn(workdir / "split", iterations, seed, lam)
    return side_by_side(ours, peer, iterations, lam)


def table(result: dict) -> str:
    """Both fits side by side, under the set-up and over the training-time ratio."""
    ours, peer = result["ours"], result["sklearn"]
    rows = [
        [label, fmt.format(ours[key]), fmt.format(peer[key])]
        for key, label, fmt in [
            ("mse_train", "MSE train [N^2]", "{:.4f}"),
            ("mse_test", "MSE test [N^2]", "{:.4f}"),
            ("r2_train", "R2 train", "{:.5f}"),
            ("r2_test", "R2 test", "{:.5f}"),
            ("iterations", "iterations", "{}"),
            ("seconds", "training [s]", "{:.2f}"),
        ]
    ]
    return "\n".join([
        f"paper data, {result['train_samples']}/{result['test_samples']} split, "
        f"(100,100,100) tanh L-BFGS, max {result['iterations_limit']} iterations, "
        f"lambda {result['lambda']} = sklearn alpha {result['alpha']:g}",
        format_table(["", "stickslip (Rust)", "scikit-learn"], rows),
        f"scikit-learn / stickslip training time: {result['time_ratio_sklearn_over_ours']:.1f}x",
    ])


def main(argv: list[str] | None = None) -> int:
    """Entry point: parses the options, runs both fits in a temporary folder, prints
    the table."""
    iterations, seed, lam = shipped_settings()
    parser = argparse.ArgumentParser(
        prog="stickslip-sklearn-peer", description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--iterations", type=int, default=iterations)
    parser.add_argument("--seed", type=int, default=seed)
    parser.add_argument("--lambda", dest="lam", type=float, default=lam)
    parser.add_argument("--binary", type=Path, default=None)
    parser.add_argument("--json", type=Path, default=None, help="also write the result here")
    args = parser.parse_args(argv)
    binary = args.binary or find_binary()
    with tempfile.TemporaryDirectory(prefix="sklearn-peer-") as workdir:
        result = run(args.iterations, args.seed, args.lam, binary, Path(workdir))
    print(table(result))
    if args.json:
        args.json.write_text(json.dumps(result, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
