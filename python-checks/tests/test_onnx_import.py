"""Bringing your own network as ONNX (issue 23): the same numbers as onnxruntime.

A scikit-learn Pipeline (StandardScaler + MLPRegressor, tanh, 20 x 20) is trained on
synthetic data of the paper's exponential law and exported with skl2onnx in float32 and
float64. skl2onnx writes the scaler as an ai.onnx.ml `Scaler` node in float32 and as
`Sub`/`Div` in float64 (test_skl2onnx_writes_what_the_reader_expects checks that, so a
new skl2onnx that changes it is noticed). The features are described with onnx's own
API (`onnx.helper.set_model_props`, keys `stickslip.features`, `stickslip.target`,
`stickslip.variant`). Each file is then evaluated on 10,000 points inside the training
range
  (a) by onnxruntime (the reference),
  (b) by NeuralFriction.fmu (FMI 2.0, fmpy) with the `weights` parameter set to the
      absolute path of the .onnx file, and
  (c) by `stickslip import-network` (its --check-data prints the largest difference
      from a column of onnxruntime's predictions) and the weights JSON it writes,
      evaluated by the FMU again, which must give the bits of (b).

PyTorch is not installable here (its CPU-only build is not on the package registry this
environment uses, the default build pulls gigabytes of CUDA libraries), so the graph
`torch.onnx.export` writes for an nn.Sequential of Linear/Tanh layers (Gemm with
transB = 1, the weights as [out, in]) is written with `onnx.helper` from the same
trained weights, in float32 and float64, and compared with onnxruntime the same way.

Tolerances, relative to the largest |force| over the points (a friction force passes
through 0 at v = 0, so a pointwise relative difference has no meaning there):
- float64: onnxruntime and we compute in f64 from the same f64 numbers and differ only
  in summation order and in tanh's last bits, a few ulps (1e-16) times the network's
  condition; 1e-12 leaves room for a condition of 1e3, a lost bit of any weight in the
  import would show far above it. Measured (the tests print it): 1.5e-15 through the
  FMU, 1.7e-15 through import-network's batch evaluation, for both graph forms.
- float32: onnxruntime evaluates every operation in f32 (rounding 6e-8 per operation,
  accumulated over 20-term sums in three layers, and its own f32 tanh), while we evaluate
  the same f32 weights in f64, so the difference is onnxruntime's f32 rounding: a few f32
  ulps of the accumulated sums. 1e-5 allows ~100 f32 ulps; measured 4.5e-7 (skl2onnx)
  and 4.6e-7 (PyTorch form), i.e. about 3.4e-5 N on forces up to 73 N. The points are
  rounded to f32 first, so both sides see the same inputs.
"""

from __future__ import annotations

import json
import re
import subprocess
import warnings

import numpy as np
import onnx
import onnxruntime
import pytest
from conftest import need
from fmpy import simulate_fmu
from onnx import TensorProto, helper, numpy_helper
from sklearn.exceptions import ConvergenceWarning
from sklearn.neural_network import MLPRegressor
from sklearn.pipeline import make_pipeline
from sklearn.preprocessing import StandardScaler
from skl2onnx import to_onnx

from stickslip_checks.artifacts import BEAM, FRICTION, find_binary

POINTS = 10_000
# Largest difference from onnxruntime relative to the largest |force|, per dtype (see the
# module docstring).
TOLERANCE = {np.float64: 1e-12, np.float32: 1e-5}


def exponential_law(v, normal_force):
    """The paper's law (Eq. 6): sign(v) F_n (mu_k + (mu_s - mu_k) exp(-alpha |v|))."""
    return np.sign(v) * normal_force * (0.2 + 0.3 * np.exp(-5.0 * np.abs(v)))


@pytest.fixture(scope="module")
def trained():
    """The pipeline, its training box and 10,000 evaluation points inside it."""
    rng = np.random.default_rng(23)
    x = np.column_stack([rng.uniform(-0.4, 0.4, 1500), rng.uniform(50.0, 150.0, 1500)])
    y = exponential_law(x[:, 0], x[:, 1])
    pipeline = make_pipeline(
        StandardScaler(),
        # L-BFGS fits the law closely (R^2 0.9998 on 3000 samples, forces up to 72 N of
        # the law's 75), so the network has the steep weights a real one has at v = 0.
        MLPRegressor((20, 20), activation="tanh", solver="lbfgs", max_iter=400,
                     random_state=0),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        # scikit-learn 1.6 passes L-BFGS-B options that SciPy deprecates; not ours to fix.
        warnings.simplefilter("ignore", DeprecationWarning)
        pipeline.fit(x, y)
    low, high = x.min(axis=0), x.max(axis=0)
    # Inside the box, rounded to f32 so that a float32 graph sees the same inputs as we do.
    points = rng.uniform(low, high, (POINTS, 2)).astype(np.float32).astype(np.float64)
    points = np.clip(points, low, high)
    features = [
        {"name": "sliding_velocity", "unit": "m/s", "role": "sliding_velocity",
         "min": float(low[0]), "max": float(high[0])},
        {"name": "normal_force", "unit": "N", "role": "normal_force",
         "min": float(low[1]), "max": float(high[1])},
    ]
    return pipeline, features, points


def describe(model: onnx.ModelProto, features) -> onnx.ModelProto:
    helper.set_model_props(model, {
        "stickslip.features": json.dumps(features),
        "stickslip.target": json.dumps({"name": "friction_force", "unit": "N"}),
        "stickslip.variant": "plain",
    })
    return model


def sklearn_onnx(trained, dtype) -> onnx.ModelProto:
    pipeline, features, points = trained
    return describe(to_onnx(pipeline, points[:1].astype(dtype)), features)


def torch_form_onnx(trained, dtype) -> onnx.ModelProto:
    """The graph torch.onnx.export writes for Sequential(Normalise, Linear, Tanh, Linear,
    Tanh, Linear): Sub/Div, Gemm(transB = 1) with W as [out, in], opset 17, IR 8."""
    pipeline, features, _ = trained
    scaler, mlp = pipeline.named_steps["standardscaler"], pipeline.named_steps["mlpregressor"]
    elem = TensorProto.FLOAT if dtype == np.float32 else TensorProto.DOUBLE

    def tensor(name, value):
        return numpy_helper.from_array(np.asarray(value, dtype=dtype), name)

    inits = [tensor("mean", scaler.mean_), tensor("std", scaler.scale_)]
    nodes = [helper.make_node("Sub", ["input", "mean"], ["centred"], name="/Sub"),
             helper.make_node("Div", ["centred", "std"], ["x0"], name="/Div")]
    current = "x0"
    for k, (w, b) in enumerate(zip(mlp.coefs_, mlp.intercepts_)):
        inits += [tensor(f"linear{k}.weight", w.T), tensor(f"linear{k}.bias", b)]
        out = f"z{k}"
        nodes.append(helper.make_node(
            "Gemm", [current, f"linear{k}.weight", f"linear{k}.bias"], [out],
            name=f"/linear{k}/Gemm", alpha=1.0, beta=1.0, transB=1))
        current = out
        if k < len(mlp.coefs_) - 1:
            nodes.append(helper.make_node("Tanh", [out], [f"a{k}"], name=f"/act{k}/Tanh"))
            current = f"a{k}"
    nodes.append(helper.make_node("Identity", [current], ["output"], name="/Identity"))
    graph = helper.make_graph(
        nodes, "main_graph",
        [helper.make_tensor_value_info("input", elem, ["batch", 2])],
        [helper.make_tensor_value_info("output", elem, ["batch", 1])],
        inits,
    )
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 17)],
                              producer_name="pytorch", producer_version="2.5.0")
    model.ir_version = 8
    onnx.checker.check_model(model)
    return describe(model, features)


def onnxruntime_forces(model: onnx.ModelProto, points, dtype) -> np.ndarray:
    session = onnxruntime.InferenceSession(model.SerializeToString(),
                                           providers=["CPUExecutionProvider"])
    name = session.get_inputs()[0].name
    return session.run(None, {name: points.astype(dtype)})[0][:, 0].astype(np.float64)


def fmu_forces(fmus, weights: str, points) -> np.ndarray:
    """friction_force of NeuralFriction.fmu with `weights` at every point (outputs are
    evaluated when read, see src/fmi/src/friction.rs)."""
    vr = fmus.vr[FRICTION]
    slave = fmus.slave(FRICTION, "onnx")
    slave.instantiate()
    slave.setString([vr["weights"]], [weights])
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    inputs, output = [vr["sliding_velocity"], vr["normal_force"]], [vr["friction_force"]]
    forces = np.empty(len(points))
    for k, (v, f_n) in enumerate(points):
        slave.setReal(inputs, [float(v), float(f_n)])
        forces[k] = slave.getReal(output)[0]
    slave.terminate()
    slave.freeInstance()
    return forces


def relative(ours, reference) -> float:
    return float(np.max(np.abs(ours - reference)) / np.max(np.abs(reference)))


def import_network(onnx_path, points, reference, tmp_path, tag):
    """`stickslip import-network --check-data` with onnxruntime's predictions as a
    column: the JSON path and the printed largest difference (target units)."""
    out = tmp_path / f"{tag}.json"
    data = tmp_path / f"{tag}.csv"
    truth = exponential_law(points[:, 0], points[:, 1])
    rows = np.column_stack([points, truth, reference])
    header = "sliding_velocity[m/s],normal_force[N],friction_force[N],onnxruntime"
    np.savetxt(data, rows, delimiter=",", header=header, comments="", fmt="%.17g")
    run = subprocess.run(
        [str(find_binary()), "import-network", str(onnx_path), "--out", str(out),
         "--check-data", str(data), "--prediction-column", "onnxruntime"],
        capture_output=True, text=True, check=False,
    )
    assert run.returncode == 0, run.stderr
    largest = re.search(r"largest \|difference\| = (\S+) N", run.stdout)
    r2 = re.search(r"R\^2 = (\S+)", run.stdout)
    assert largest and r2, run.stdout
    return out, float(largest.group(1)), float(r2.group(1))


def test_skl2onnx_writes_what_the_reader_expects(trained):
    """What skl2onnx 1.19 writes: the Scaler in f32, Sub/Div in f64, then MatMul + Add."""
    ops = {dtype: [n.op_type for n in sklearn_onnx(trained, dtype).graph.node]
           for dtype in (np.float32, np.float64)}
    assert ops[np.float32][0] == "Scaler", ops
    assert ops[np.float64][:2] == ["Sub", "Div"], ops
    for names in ops.values():
        assert names.count("MatMul") == 3 and names.count("Tanh") == 2, names


@pytest.mark.parametrize("dtype", [np.float32, np.float64], ids=["float32", "float64"])
@pytest.mark.parametrize("form", ["sklearn", "torch"])
def test_imported_network_matches_onnxruntime(built, trained, tmp_path, form, dtype):
    fmus = need(built)
    _, _, points = trained
    model = (sklearn_onnx if form == "sklearn" else torch_form_onnx)(trained, dtype)
    path = tmp_path / f"{form}.onnx"
    onnx.save(model, path)
    reference = onnxruntime_forces(model, points, dtype)

    direct = fmu_forces(fmus, str(path.resolve()), points)
    difference = relative(direct, reference)
    print(f"{form} {np.dtype(dtype).name}: FMU with the .onnx vs onnxruntime: "
          f"largest difference {difference:.3e} of max |F| = {np.max(np.abs(reference)):.2f} N")
    assert difference <= TOLERANCE[dtype]

    json_path, printed, r2 = import_network(path, points, reference, tmp_path, form)
    # The CLI's own evaluation (in batch, by matrix products: the same numbers up to
    # summation order) is within the same tolerance.
    scale = float(np.max(np.abs(reference)))
    print(f"  import-network --check-data: largest difference {printed / scale:.3e} of max |F|,"
          f" R^2 {r2:.6f}")
    assert printed <= TOLERANCE[dtype] * scale
    # The network has learned the law (not a parity criterion; less than 1 because the law
    # jumps by 2 mu_s F_n at v = 0, which a smooth network cannot follow); a broken import
    # or CSV reading would give R^2 near or below 0.
    assert r2 > 0.95
    # The JSON written is the network read from the .onnx: the same bits through the FMU.
    np.testing.assert_array_equal(fmu_forces(fmus, str(json_path.resolve()), points), direct)


@pytest.mark.parametrize("dtype", [np.float32, np.float64], ids=["float32", "float64"])
def test_beam_runs_an_onnx_network_as_its_json(built, trained, tmp_path, dtype):
    """StickSlipBeam.fmu with friction.weights = the .onnx file runs as with the JSON that
    import-network writes from it: bit for bit, and the law is the network (a different
    run from the shipped network's)."""
    fmus = need(built)
    _, _, points = trained
    model = sklearn_onnx(trained, dtype)
    path = tmp_path / "beam.onnx"
    onnx.save(model, path)
    reference = onnxruntime_forces(model, points[:10], dtype)
    json_path, _, _ = import_network(path, points[:10], reference, tmp_path, "beam")

    def run(weights):
        # Past the first breakaway (about 0.4 s), so that the kinetic law acts.
        return simulate_fmu(str(fmus.paths[BEAM]), stop_time=1.0, output_interval=1e-3,
                            start_values={"friction.law": 3, "friction.weights": weights})

    onnx_run, json_run, shipped = (run(str(path.resolve())), run(str(json_path.resolve())),
                                   run("paper-plain.json"))
    for column in onnx_run.dtype.names:
        np.testing.assert_array_equal(onnx_run[column], json_run[column], err_msg=column)
    assert not np.array_equal(onnx_run["tip_deflection"], shipped["tip_deflection"])
    assert np.all(np.isfinite(onnx_run["tip_deflection"]))
