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

PyTorch is not installable here (PyPI's Linux torch wheels are CUDA builds that do not
import without the nvidia-* libraries, and the CPU-only build is not on PyPI; see
test_onnx_exporters.py), so the graph `torch.onnx.export` writes for an nn.Sequential of
Linear/Tanh layers (Gemm with transB = 1, the weights as [out, in]) is written with
`onnx.helper` from the same trained weights, in float32 and float64, and compared with
onnxruntime the same way. The Keras form (MatMul with the kernel as [in, out], Add of the
bias, Tanh, an Identity naming the output, opset 15, IR 8; the standardisation folded into
the first layer) is written the same way here, as a check that needs no TensorFlow; the
real Keras 3 exporters (SavedModel + tf2onnx, `model.export(format="onnx")`) run in
test_onnx_exporters.py.
NeuralFriction.fmu FMI 3.0 takes the .onnx file as its `weights` parameter and gives
the FMI 2.0 FMU's forces bit for bit (the same library behind both interfaces).

Tolerances, relative to the largest |force| over the points (a friction force passes
through 0 at v = 0, so a pointwise relative difference has no meaning there):
- float64: onnxruntime and we compute in f64 from the same f64 numbers and differ only
  in summation order and in tanh's last bits, a few ulps (1e-16) times the network's
  condition; 1e-12 leaves room for a condition of 1e3, a lost bit of any weight in the
  import would show far above it. Measured with onnxruntime 1.32 (the tests print it):
  9.7e-16 through the FMU, 1.7e-15 through import-network's batch evaluation, for the
  skl2onnx and PyTorch forms; 2.7e-15 and 2.5e-15 for the Keras form (its folded first
  layer).
- float32: onnxruntime evaluates every operation in f32 (rounding 6e-8 per operation,
  accumulated over 20-term sums in three layers, and its own f32 tanh), while we evaluate
  the same f32 weights in f64, so the difference is onnxruntime's f32 rounding: a few f32
  ulps of the accumulated sums. 1e-5 allows ~100 f32 ulps; measured 4.7e-7 (skl2onnx),
  3.9e-7 (PyTorch form) and 5.7e-7 (Keras form), i.e. about 4e-5 N on forces up to 73 N. The points are
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

from stickslip_checks.artifacts import BEAM, FRICTION, REPO, find_binary, fmu3_paths
from stickslip_checks.friction_points import fmi2_forces, fmi3_forces, relative

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
    return exported(graph, 17, ("pytorch", "2.5.0"), features)


def exported(graph, opset: int, producer: tuple[str, str], features) -> onnx.ModelProto:
    """`graph` as the model an exporter writes: IR 8, `opset`, its (name, version),
    checked by onnx and described."""
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", opset)],
                              producer_name=producer[0], producer_version=producer[1])
    model.ir_version = 8
    onnx.checker.check_model(model)
    return describe(model, features)


def keras_form_onnx(trained, dtype) -> onnx.ModelProto:
    """The graph tf2onnx writes for Sequential([Dense(20, tanh), Dense(20, tanh),
    Dense(1)]): MatMul with the kernel as [in, out], Add of the bias, Tanh, and an
    Identity to the output; opset 15, IR 8. The scaler is folded into the first layer:
    W' = diag(1/s) W, b' = b - (m/s) W, so the graph takes the raw inputs."""
    pipeline, features, _ = trained
    scaler, mlp = pipeline.named_steps["standardscaler"], pipeline.named_steps["mlpregressor"]
    elem = TensorProto.FLOAT if dtype == np.float32 else TensorProto.DOUBLE
    kernels, biases = list(mlp.coefs_), list(mlp.intercepts_)
    kernels[0] = kernels[0] / scaler.scale_[:, None]
    biases[0] = biases[0] - (scaler.mean_ / scaler.scale_) @ mlp.coefs_[0]
    inits, nodes, current = [], [], "dense_input"
    for k, (w, b) in enumerate(zip(kernels, biases)):
        layer = "dense" if k == 0 else f"dense_{k}"
        kernel, bias = f"sequential/{layer}/MatMul/ReadVariableOp:0", \
            f"sequential/{layer}/BiasAdd/ReadVariableOp:0"
        inits += [numpy_helper.from_array(np.asarray(w, dtype), kernel),
                  numpy_helper.from_array(np.asarray(b, dtype), bias)]
        nodes += [helper.make_node("MatMul", [current, kernel], [f"{layer}/MatMul:0"],
                                   name=f"sequential/{layer}/MatMul"),
                  helper.make_node("Add", [f"{layer}/MatMul:0", bias], [f"{layer}/BiasAdd:0"],
                                   name=f"sequential/{layer}/BiasAdd")]
        current = f"{layer}/BiasAdd:0"
        if k < len(kernels) - 1:
            nodes.append(helper.make_node("Tanh", [current], [f"{layer}/Tanh:0"],
                                          name=f"sequential/{layer}/Tanh"))
            current = f"{layer}/Tanh:0"
    output = f"dense_{len(kernels) - 1}"
    nodes.append(helper.make_node("Identity", [current], [output], name=f"Identity_{output}"))
    graph = helper.make_graph(
        nodes, "tf2onnx",
        [helper.make_tensor_value_info("dense_input", elem, ["unk__6", 2])],
        [helper.make_tensor_value_info(output, elem, ["unk__7", 1])],
        inits,
    )
    return exported(graph, 15, ("tf2onnx", "1.16.1 15c810"), features)


FORMS = {"sklearn": sklearn_onnx, "torch": torch_form_onnx, "keras": keras_form_onnx}


def onnxruntime_forces(model: onnx.ModelProto, points, dtype) -> np.ndarray:
    session = onnxruntime.InferenceSession(model.SerializeToString(),
                                           providers=["CPUExecutionProvider"])
    name = session.get_inputs()[0].name
    return session.run(None, {name: points.astype(dtype)})[0][:, 0].astype(np.float64)


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
@pytest.mark.parametrize("form", sorted(FORMS))
def test_imported_network_matches_onnxruntime(built, trained, tmp_path, form, dtype):
    fmus = need(built)
    _, _, points = trained
    model = FORMS[form](trained, dtype)
    path = tmp_path / f"{form}.onnx"
    onnx.save(model, path)
    reference = onnxruntime_forces(model, points, dtype)

    direct = fmi2_forces(fmus, str(path.resolve()), points)
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
    np.testing.assert_array_equal(fmi2_forces(fmus, str(json_path.resolve()), points), direct)


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


def test_keras_form_has_what_tf2onnx_writes(trained):
    """The Keras form is tf2onnx's: MatMul + Add per layer, Tanh between, an Identity at
    the output, input `dense_input`, and no scaler node (folded into the first layer)."""
    model = keras_form_onnx(trained, np.float32)
    ops = [n.op_type for n in model.graph.node]
    assert ops == ["MatMul", "Add", "Tanh"] * 2 + ["MatMul", "Add", "Identity"], ops
    assert model.graph.input[0].name == "dense_input"
    assert model.producer_name == "tf2onnx"


@pytest.mark.parametrize("dtype", [np.float32, np.float64], ids=["float32", "float64"])
def test_fmi3_takes_the_onnx_file_with_the_bits_of_fmi2(built, trained, tmp_path, dtype):
    """NeuralFriction.fmu FMI 3.0 with `weights` = the .onnx file gives the FMI 2.0 FMU's
    forces bit for bit (the same library behind both interfaces), on 1,000 of the points,
    and they are onnxruntime's within the dtype's tolerance."""
    fmus = need(built)
    _, _, points = trained
    points = points[:1000]
    model = sklearn_onnx(trained, dtype)
    path = tmp_path / "fmi3.onnx"
    onnx.save(model, path)
    two = fmi2_forces(fmus, str(path.resolve()), points)
    three = fmi3_forces(fmu3_paths()[FRICTION], str(path.resolve()), points)
    np.testing.assert_array_equal(three, two)
    assert relative(three, onnxruntime_forces(model, points, dtype)) <= TOLERANCE[dtype]


@pytest.mark.parametrize("dtype", [np.float32, np.float64], ids=["float32", "float64"])
def test_what_onnx_writes_by_default_is_read(built, trained, tmp_path, dtype):
    """`onnx.helper.make_model` without a version writes the pinned onnx's newest IR and
    opset (onnx 1.23: IR 14, opset 28); our reader takes it, judging the Gemm and Tanh
    nodes by their versions (unchanged since 13), and gives onnxruntime's forces within
    the dtype's tolerance (onnxruntime 1.32 runs IR 14)."""
    fmus = need(built)
    _, _, points = trained
    points = points[:1000]
    written = torch_form_onnx(trained, dtype)
    fresh = helper.make_model(written.graph, producer_name="onnx.helper")
    fresh.metadata_props.extend(written.metadata_props)
    # The pins' defaults: a bump of onnx that writes newer versions must revisit the
    # reader's checked opsets (src/formats/src/onnx/convert/opset.rs).
    assert (fresh.ir_version, fresh.opset_import[0].version) == (14, 28)
    onnx.checker.check_model(fresh)
    path = tmp_path / "default.onnx"
    onnx.save(fresh, path)
    forces = fmi2_forces(fmus, str(path.resolve()), points)
    assert relative(forces, onnxruntime_forces(fresh, points, dtype)) <= TOLERANCE[dtype]


def test_reader_operator_table_is_the_pinned_onnx_schema_history():
    """The reader's per-operator versions (OPERATORS in src/formats/src/onnx/convert/
    opset.rs) are the since-versions of the pinned onnx's schema history, the source of
    truth for what each operator version is, and its checked opsets and newest IR version
    are that onnx's: a bump of onnx that adds an operator version makes this fail, so that
    the new version is judged before files using it are accepted."""
    from onnx import defs

    source = (REPO / "src/formats/src/onnx/convert/opset.rs").read_text()
    table = {
        (name, ml == "true"): [int(v) for v in since.split(",")]
        for name, ml, since in re.findall(
            r'op_type: "(\w+)",\s*ml: (true|false),\s*since: &\[([\d, ]+)\]', source)
    }
    assert len(table) == 15, sorted(table)
    opsets = re.search(r"CheckedOpsets \{\s*default: (\d+),\s*ml: (\d+)", source)
    checked = {False: int(opsets.group(1)), True: int(opsets.group(2))}
    # onnx's release table: (release, IR version, ai.onnx opset, ai.onnx.ml opset, ...).
    _, newest_ir, newest_default, newest_ml, *_ = helper.VERSION_TABLE[-1]
    assert (checked[False], checked[True]) == (newest_default, newest_ml)
    assert newest_default == defs.onnx_opset_version()
    reader_ir = int(re.search(r"IR_VERSIONS: \(i64, i64\) = \(3, (\d+)\)", source).group(1))
    assert reader_ir == newest_ir == onnx.IR_VERSION
    history: dict[tuple[str, bool], set[int]] = {}
    for schema in defs.get_all_schemas_with_history():
        ml = schema.domain == "ai.onnx.ml"
        if schema.domain in ("", "ai.onnx.ml") and (schema.name, ml) in table \
                and schema.since_version <= checked[ml]:
            history.setdefault((schema.name, ml), set()).add(schema.since_version)
    for key, since in table.items():
        assert since == sorted(history[key]), (key, since, sorted(history[key]))
