"""The README's per-framework routes to an .onnx file, run with the real exporters
(issue 33), and each file read by NeuralFriction.fmu against onnxruntime.

Keras 3 (TensorFlow's CPU build) exports run in their own venv, .venv-exporters
(scripts/exporters-env.sh, pinned in requirements-exporters.txt; scripts/test.sh always
creates it): python-checks/exporters/export_networks.py writes the .onnx files of each
route and onnxruntime's predictions to a temporary folder, and this module compares. Where
that venv is absent, the Keras part skips, saying so. scikit-learn goes through skl2onnx
in this venv. Every outcome, export failures included, is a row of the table written to
target/onnx-exporters.md (printed by scripts/test.sh).

PyTorch is not among the exporters: PyPI's Linux x86_64 torch wheels are CUDA builds
whose import loads libcudart and cuBLAS from the nvidia-* packages (torch 2.15.0 with
--no-deps: "libcudart.so.13: cannot open shared object file"); the CPU-only build is on
download.pytorch.org only, which the tests may not reach (docs/command-line.md).

The points: v = 0 and |v| from 1e-7 to 0.1 by decades, both signs, and a sweep of the
training range, at five normal forces, rounded to float32 so that every reader sees the
same inputs.

The bound, per point, from the computation (forward error analysis of the network as our
weights file holds it, the f32 or f64 unit roundoff u of the graph's data type): the
normalised input carries 2u (|x| + |mean|) / std (the subtraction and the division); a
dense layer of fan-in n adds gamma(n + 1) = (n + 1) u / (1 - (n + 1) u) times the sum of
|terms| |W| |a| + |b| (the dot product and the bias, in any summation order, vectorised or
not) and passes the incoming error through |W|; tanh passes it with slope at most 1 and
adds 4u |tanh| (onnxruntime's vectorised tanh is an approximation of a few ulps); the
output scaling multiplies by its std and adds u |F|. onnxruntime rounds with the graph's
u, we evaluate in f64 with u = 2^-53, so the two evaluations differ by at most the bound
with the graph's u plus the bound with 2^-53. Measured ratios (difference / bound) are in
the table; exact equality is never asked (onnxruntime's kernels differ by CPU).
"""

from __future__ import annotations

import json
import subprocess
import warnings
from pathlib import Path

import numpy as np
import onnx
import onnxruntime
import pytest
import skl2onnx
import sklearn
from conftest import need
from onnx import helper
from sklearn.exceptions import ConvergenceWarning
from sklearn.neural_network import MLPRegressor
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler
from skl2onnx import to_onnx

from stickslip_checks.artifacts import REPO, find_binary
from stickslip_checks.friction_points import fmi2_forces

EXPORTERS_PYTHON = REPO / ".venv-exporters" / "bin" / "python"
EXPORT_SCRIPT = REPO / "python-checks" / "exporters" / "export_networks.py"
TABLE = REPO / "target" / "onnx-exporters.md"
UNIT_ROUNDOFF = {"float32": 2.0**-24, "float64": 2.0**-53}

# The Keras routes the README documents: each must export, run in onnxruntime and import.
# A route outside this set that starts working is reported by the test below, so that
# the README can name it; tf2onnx.convert.from_keras fails with these pins.
DOCUMENTED_KERAS = {(route, dtype, normalise)
                    for dtype in ("float32", "float64")
                    for route, normalise in [("savedmodel-tf2onnx", False),
                                             ("savedmodel-tf2onnx", True),
                                             ("keras-export-onnx", False)]}


def exponential_law(v, normal_force):
    return np.sign(v) * normal_force * (0.2 + 0.3 * np.exp(-5.0 * np.abs(v)))


def forward_bound(weights: dict, points: np.ndarray, u: float) -> np.ndarray:
    """Per point, the largest difference rounding with unit roundoff u can make in the
    network of our weights file `weights` (see the module docstring)."""
    mean = np.array([f["input_mean"] for f in weights["features"]])
    std = np.array([f["input_std"] for f in weights["features"]])
    activation = {"tanh": np.tanh, "relu": lambda z: np.maximum(z, 0.0),
                  "sigmoid": lambda z: 1.0 / (1.0 + np.exp(-z))}[weights["activation"]]
    a = (points - mean) / std
    error = 2.0 * u * (np.abs(points) + np.abs(mean)) / std
    layers = weights["layers"]
    for k, layer in enumerate(layers):
        w, b = np.array(layer["weights"]), np.array(layer["biases"])
        n = w.shape[1] + 1
        gamma = n * u / (1.0 - n * u)
        terms = np.abs(a) @ np.abs(w).T + np.abs(b)
        z = a @ w.T + b
        error = error @ np.abs(w).T + gamma * terms
        if k < len(layers) - 1:
            a = activation(z)
            error = error + 4.0 * u * np.abs(a)
        else:
            a = z
    scale = weights["target"]["output_std"]
    force = a[:, 0] * scale + weights["target"]["output_mean"]
    return error[:, 0] * abs(scale) + u * np.abs(force)


def import_network(path: Path, out: Path) -> tuple[bool, str]:
    run = subprocess.run([str(find_binary()), "import-network", str(path), "--out", str(out)],
                         capture_output=True, text=True, check=False)
    return run.returncode == 0, run.stderr.strip()


def sklearn_exports(points: np.ndarray, features: list[dict], folder: Path) -> list[dict]:
    """skl2onnx exports of a StandardScaler + MLPRegressor(16, 16, tanh) pipeline fitted
    to the same law, in float32 and float64, with onnxruntime's predictions; `features`
    the metadata (the exporter script's, whose range holds the points)."""
    rng = np.random.default_rng(33)
    x = np.column_stack([rng.uniform(-0.4, 0.4, 2000), rng.uniform(50.0, 150.0, 2000)])
    pipeline = make_pipeline(StandardScaler(), MLPRegressor(
        (16, 16), activation="tanh", solver="lbfgs", max_iter=300, random_state=0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        warnings.simplefilter("ignore", DeprecationWarning)
        pipeline.fit(x, exponential_law(x[:, 0], x[:, 1]))
    entries = []
    for dtype in ("float32", "float64"):
        model = to_onnx(pipeline, points[:1].astype(dtype))
        helper.set_model_props(model, {"stickslip.features": json.dumps(features),
                                       "stickslip.variant": "plain"})
        name = f"sklearn-skl2onnx-{dtype}"
        path = folder / f"{name}.onnx"
        onnx.save(model, path)
        session = onnxruntime.InferenceSession(str(path), providers=["CPUExecutionProvider"])
        feed = {session.get_inputs()[0].name: points.astype(dtype)}
        entries.append({
            "name": name, "framework": "scikit-learn", "route": "skl2onnx.to_onnx",
            "dtype": dtype, "normalization_layer": True, "file": path.name,
            "export_error": None, "onnxruntime_error": None,
            "onnxruntime": session.run(None, feed)[0][:, 0].tolist(),
            "ir_version": model.ir_version,
            "opsets": {o.domain or "ai.onnx": o.version for o in model.opset_import},
            "producer": f"{model.producer_name} {model.producer_version}",
        })
    return entries


@pytest.fixture(scope="module")
def keras_exports(tmp_path_factory):
    """The exporter script's manifest and folder, or the reason it could not run."""
    if not EXPORTERS_PYTHON.exists():
        return f"the exporter venv {EXPORTERS_PYTHON.parent.parent} is absent " \
               "(bash scripts/exporters-env.sh creates it; scripts/test.sh always does)"
    folder = tmp_path_factory.mktemp("exporters")
    run = subprocess.run([str(EXPORTERS_PYTHON), str(EXPORT_SCRIPT), str(folder)],
                         capture_output=True, text=True, check=False)
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads((folder / "manifest.json").read_text()), folder


def judge(entry: dict, folder: Path, points: np.ndarray, fmus) -> dict:
    """Import result, largest difference from onnxruntime and its ratio to the bound."""
    row = dict(entry, imported=None, refusal=None, largest=None, relative=None, ratio=None)
    if not entry["file"]:
        return row
    path = folder / entry["file"]
    ok, message = import_network(path, folder / f"{entry['name']}.json")
    row["imported"] = ok
    if not ok:
        row["refusal"] = message
        return row
    if entry["onnxruntime"] is None:
        return row
    weights = json.loads((folder / f"{entry['name']}.json").read_text())
    reference = np.array(entry["onnxruntime"])
    ours = fmi2_forces(fmus, str(path.resolve()), points)
    bound = forward_bound(weights, points, UNIT_ROUNDOFF[entry["dtype"]]) \
        + forward_bound(weights, points, UNIT_ROUNDOFF["float64"])
    difference = np.abs(ours - reference)
    row.update(largest=float(difference.max()),
               relative=float(difference.max() / np.abs(reference).max()),
               ratio=float(np.max(difference / bound)))
    return row


def write_table(rows: list[dict], versions: str) -> None:
    lines = [f"ONNX exporters against NeuralFriction.fmu ({versions})", "",
             "| framework | route | dtype | normalisation | file (IR, opsets) | onnxruntime "
             "| import | largest \\|F - F_ort\\| | of max \\|F\\| | / bound |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        file = "export failed: " + r["export_error"] if r["export_error"] else \
            f"IR {r['ir_version']}, " + ", ".join(f"{d} {v}" for d, v in r["opsets"].items())
        ort = "runs" if r["onnxruntime"] is not None else \
            ("-" if r["export_error"] else "fails: " + r["onnxruntime_error"])
        imported = "-" if r["imported"] is None else \
            ("accepted" if r["imported"] else "refused: " + r["refusal"])
        numbers = ["-", "-", "-"] if r["largest"] is None else \
            [f"{r['largest']:.2e} N", f"{r['relative']:.1e}", f"{r['ratio']:.3f}"]
        norm = "layer" if r["normalization_layer"] else "folded"
        cells = [r["framework"], r["route"], r["dtype"], norm, file, ort, imported, *numbers]
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    TABLE.parent.mkdir(exist_ok=True)
    TABLE.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


def test_every_exporter_route_imports_within_the_rounding_bound(built, keras_exports):
    fmus = need(built)
    if isinstance(keras_exports, str):
        pytest.skip(keras_exports)
    manifest, folder = keras_exports
    points = np.array(manifest["points"])
    assert np.count_nonzero(points[:, 0] == 0.0) > 0
    assert np.min(np.abs(points[points[:, 0] != 0.0, 0])) <= 1.0001e-7
    # Inside the range the law clamps to, so that the comparison sees only rounding.
    for k, feature in enumerate(manifest["features"]):
        assert feature["min"] <= points[:, k].min() and points[:, k].max() <= feature["max"]
    entries = manifest["exports"] + sklearn_exports(points, manifest["features"], folder)
    rows = [judge(entry, folder, points, fmus) for entry in entries]
    versions = ", ".join(f"{k} {v}" for k, v in manifest["versions"].items()
                         if k not in ("numpy", "protobuf"))
    versions += f"; scikit-learn {sklearn.__version__}, skl2onnx {skl2onnx.__version__}, " \
                f"main venv onnxruntime {onnxruntime.__version__}"
    write_table(rows, versions)

    for r in rows:
        if r["onnxruntime"] is not None:
            # Every file onnxruntime runs is a network the reader claims to read.
            assert r["imported"], f"{r['name']}: {r['refusal']}"
            assert r["ratio"] <= 1.0, f"{r['name']}: {r['ratio']} of the bound"
        elif r["imported"] is False:
            # A file onnxruntime cannot run either: refused, naming the cause.
            assert r["file"] in r["refusal"], r["refusal"]
    working = {(r["route"], r["dtype"], r["normalization_layer"]) for r in rows
               if r["framework"] == "keras" and r["imported"] and r["onnxruntime"]}
    assert working == DOCUMENTED_KERAS, \
        f"Keras routes that export, run and import: {sorted(working)}; the README " \
        f"documents {sorted(DOCUMENTED_KERAS)}"
    assert all(r["imported"] and r["onnxruntime"] for r in rows
               if r["framework"] == "scikit-learn")
