"""Exports one friction network with the real exporters (issue 33), in the exporter venv
(scripts/exporters-env.sh, pinned in python-checks/requirements-exporters.txt).

    .venv-exporters/bin/python python-checks/exporters/export_networks.py OUT_DIR

A Keras model of the friction law F(v, F_n) (Normalization, Dense(16, tanh),
Dense(16, tanh), Dense(1)) is trained briefly on the paper's exponential law; a second
model is the same network with the normalisation folded into the first layer (a user who
standardises outside Keras). Both, in float32 and float64 (the float32 weights, widened),
go through each documented route:

- `savedmodel-tf2onnx`: `model.export(dir)` then `python -m tf2onnx.convert --saved-model`,
- `keras-export-onnx`: Keras 3's `model.export(path, format="onnx")`,
- `tf2onnx-from-keras`: `tf2onnx.convert.from_keras(model)`.

Each file gets the stickslip metadata keys with onnx's API, and onnxruntime (the version
pinned here) evaluates it on a grid of (v, F_n) points: v down to 1e-7 in magnitude and 0,
both signs, at several normal forces, rounded to float32 so that every reader sees the
same inputs. OUT_DIR/manifest.json records per export the versions, the route's outcome
(the file, or the exception the exporter or onnxruntime raised) and onnxruntime's
predictions; the comparison with our reader runs in the main suite
(python-checks/tests/test_onnx_exporters.py), which has the FMUs.

Nothing here asserts: an exporter that fails is a row of the table, not a crash.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import traceback
from importlib.metadata import version
from pathlib import Path

os.environ.setdefault("TF_CPP_MIN_LOG_LEVEL", "3")

import numpy as np  # noqa: E402

V_MAX, FN_RANGE = 0.4, (50.0, 150.0)


def exponential_law(v, normal_force):
    """The paper's law (Eq. 6): sign(v) F_n (mu_k + (mu_s - mu_k) exp(-alpha |v|))."""
    return np.sign(v) * normal_force * (0.2 + 0.3 * np.exp(-5.0 * np.abs(v)))


def grid() -> np.ndarray:
    """(v, F_n) rows: v = 0, +-1e-7 ... +-1e-1 by decades and a uniform sweep of the
    range, at five normal forces across the training range; float32-exact."""
    decades = 10.0 ** np.arange(-7, 0)
    speeds = np.concatenate([[0.0], decades, -decades, np.linspace(-V_MAX, V_MAX, 41)])
    forces = np.linspace(*FN_RANGE, 5)
    points = np.array([[v, f] for v in speeds for f in forces])
    return points.astype(np.float32).astype(np.float64)


def features() -> list[dict]:
    """The metadata's training range: the grid's, whose ends are float32 roundings (the law
    clamps its inputs to the range; a range of exactly +-0.4 would clamp f32(-0.4), which
    is 6e-9 beyond, and the clamp would show as a difference from onnxruntime)."""
    v_max = float(np.float32(V_MAX))
    return [
        {"name": "sliding_velocity", "unit": "m/s", "role": "sliding_velocity",
         "min": -v_max, "max": v_max},
        {"name": "normal_force", "unit": "N", "role": "normal_force",
         "min": FN_RANGE[0], "max": FN_RANGE[1]},
    ]


def trained_keras():
    """The trained float32 model with its Normalization layer, and its weights."""
    import keras

    keras.utils.set_random_seed(33)
    rng = np.random.default_rng(33)
    x = np.column_stack([rng.uniform(-V_MAX, V_MAX, 2000),
                         rng.uniform(*FN_RANGE, 2000)]).astype(np.float32)
    y = exponential_law(x[:, 0], x[:, 1]).astype(np.float32)
    normalization = keras.layers.Normalization()
    normalization.adapt(x)
    model = keras.Sequential([
        keras.Input((2,), name="features"),
        normalization,
        keras.layers.Dense(16, activation="tanh"),
        keras.layers.Dense(16, activation="tanh"),
        keras.layers.Dense(1),
    ])
    model.compile(optimizer=keras.optimizers.Adam(1e-2), loss="mse")
    model.fit(x, y, epochs=30, batch_size=64, verbose=0)
    mean = np.asarray(normalization.mean, dtype=np.float64).ravel()
    std = np.sqrt(np.asarray(normalization.variance, dtype=np.float64).ravel())
    dense = [layer.get_weights() for layer in model.layers[1:]]
    return mean, std, dense


def keras_model(mean, std, dense, normalise: bool, dtype: str):
    """The network as a Keras model in `dtype`: with a Normalization layer holding the
    mean and variance, or with them folded into the first layer (W' = W / s,
    b' = b - (m / s) W)."""
    import keras

    kernels = [np.asarray(w, np.float64) for w, _ in dense]
    biases = [np.asarray(b, np.float64) for _, b in dense]
    if not normalise:
        biases[0] = biases[0] - (mean / std) @ kernels[0]
        kernels[0] = kernels[0] / std[:, None]
    layers = [keras.Input((2,), name="features", dtype=dtype)]
    if normalise:
        layers.append(keras.layers.Normalization(mean=mean, variance=std**2, dtype=dtype))
    for k in range(len(kernels)):
        activation = "tanh" if k < len(kernels) - 1 else None
        layers.append(keras.layers.Dense(kernels[k].shape[1], activation=activation,
                                         dtype=dtype))
    model = keras.Sequential(layers)
    for layer, w, b in zip(model.layers[-len(kernels):], kernels, biases):
        layer.set_weights([w.astype(dtype), b.astype(dtype)])
    return model


def export_route(model, route: str, path: Path, work: Path) -> None:
    if route == "savedmodel-tf2onnx":
        saved = work / (path.stem + "-savedmodel")
        model.export(str(saved), format="tf_saved_model", verbose=False)
        run = subprocess.run(
            [sys.executable, "-m", "tf2onnx.convert", "--saved-model", str(saved),
             "--output", str(path)],
            capture_output=True, text=True, check=False,
        )
        if run.returncode != 0:
            lines = [ln for ln in run.stderr.splitlines() if ln.strip()]
            raise RuntimeError(" | ".join(lines[-3:]))
    elif route == "keras-export-onnx":
        model.export(str(path), format="onnx", verbose=False)
    elif route == "tf2onnx-from-keras":
        import tf2onnx

        tf2onnx.convert.from_keras(model, output_path=str(path))
    else:
        raise ValueError(route)


def one_line(error: BaseException) -> str:
    text = f"{type(error).__name__}: {error}".replace("\n", " ")
    return text[:600]


def main(out: Path) -> None:
    import onnx
    import onnxruntime
    from onnx import helper

    out.mkdir(parents=True, exist_ok=True)
    points = grid()
    mean, std, dense = trained_keras()
    exports = []
    for dtype in ("float32", "float64"):
        for normalise in (False, True):
            model = keras_model(mean, std, dense, normalise, dtype)
            keras_forces = model.predict(points.astype(dtype), verbose=0)[:, 0]
            for route in ("savedmodel-tf2onnx", "keras-export-onnx", "tf2onnx-from-keras"):
                name = f"keras-{route}-{dtype}-{'normalization' if normalise else 'folded'}"
                path = out / f"{name}.onnx"
                entry = {"name": name, "framework": "keras", "route": route, "dtype": dtype,
                         "normalization_layer": normalise, "file": None,
                         "export_error": None, "onnxruntime_error": None,
                         "onnxruntime": None,
                         "framework_forces": [float(f) for f in keras_forces]}
                try:
                    export_route(model, route, path, out)
                    written = onnx.load(str(path))
                    helper.set_model_props(written, {
                        "stickslip.features": json.dumps(features()),
                        "stickslip.target": json.dumps({"name": "friction_force",
                                                        "unit": "N"}),
                        "stickslip.variant": "plain",
                    })
                    onnx.save(written, str(path))
                    entry.update(file=path.name, ir_version=written.ir_version,
                                 opsets={o.domain or "ai.onnx": o.version
                                         for o in written.opset_import},
                                 producer=f"{written.producer_name} "
                                          f"{written.producer_version}".strip(),
                                 operators=[n.op_type for n in written.graph.node])
                except Exception as error:  # an exporter's failure is a result
                    entry["export_error"] = one_line(error)
                    traceback.print_exc(limit=2)
                if entry["file"]:
                    try:
                        session = onnxruntime.InferenceSession(
                            str(path), providers=["CPUExecutionProvider"])
                        feed = {session.get_inputs()[0].name: points.astype(dtype)}
                        entry["onnxruntime"] = [float(f) for f in session.run(None, feed)[0][:, 0]]
                    except Exception as error:
                        entry["onnxruntime_error"] = one_line(error)
                exports.append(entry)
                print(name, "exported" if entry["file"] else entry["export_error"][:120],
                      "" if entry["onnxruntime"] else entry["onnxruntime_error"], flush=True)
    packages = ["tensorflow-cpu", "keras", "tf2onnx", "onnx", "onnxruntime", "numpy",
                "protobuf"]
    manifest = {
        "versions": {p: version(p) for p in packages},
        "points": points.tolist(),
        "features": features(),
        "exports": exports,
    }
    (out / "manifest.json").write_text(json.dumps(manifest, indent=1))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(Path(sys.argv[1]))
