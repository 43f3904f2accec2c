"""The FMI 3.0 FMUs (<fmu root>/3.0/*.fmu) under fmpy: validation, the same results as the
FMI 2.0 FMUs bit for bit, the FMI 3.0 state machine refusing illegal calls, FMU state
round trips, and resourcePath as a path.

Both versions are the same library (fmi2* and fmi3* exports) over the same tables, so
at the same settings every output must be equal, not only close: a difference would
mean that the FMI 3.0 glue does something to the model that the FMI 2.0 glue does not.

Needs the FMUs built by `cargo run --release -p fmu-build`; without them every test
here FAILS and says how to build them.
"""

from __future__ import annotations

import ctypes
import shutil
import tempfile

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import (
    FMU3Slave,
    fmi3Boolean,
    fmi3InstanceEnvironment,
    fmi3IntermediateUpdateCallback,
    fmi3LogMessageCallback,
    fmi3ValueReference,
)
from fmpy.validation import validate_fmu

from stickslip_checks.artifacts import BEAM, FRICTION, Model, fmu3_paths, fmu_paths

FMI3_ERROR = 3
STOP = 0.6  # s: past the breakaway at about 0.4 s, so both stick and slip are compared


@pytest.fixture(scope="module")
def paths():
    try:
        return {"2.0": fmu_paths(), "3.0": fmu3_paths()}
    except FileNotFoundError as error:
        pytest.fail(str(error), pytrace=False)


@pytest.fixture(scope="module")
def unzipped(paths):
    folders = {name: extract(str(path)) for name, path in paths["3.0"].items()}
    yield folders
    for folder in folders.values():
        shutil.rmtree(folder, ignore_errors=True)


def test_validate_fmu_is_empty(paths):
    for name, path in paths["3.0"].items():
        assert validate_fmu(str(path)) == [], name
        description = read_model_description(str(path))
        assert description.fmiVersion == "3.0"
        assert description.coSimulation is not None and description.modelExchange is None


def test_fmi3_layout(paths):
    import zipfile

    for name, path in paths["3.0"].items():
        names = zipfile.ZipFile(path).namelist()
        assert f"binaries/x86_64-linux/{name}.so" in names, names


@pytest.mark.parametrize("law", ["exponential", "neural"])
@pytest.mark.parametrize("level", ["modal", "beam"])
def test_beam_outputs_equal_fmi2_bit_for_bit(paths, law, level):
    model = Model.read(paths["2.0"][BEAM])
    start = {
        "fidelity.level": model.code("fidelity.level", level),
        "friction.law": model.code("friction.law", law),
    }
    results = {
        version: simulate_fmu(
            str(paths[version][BEAM]),
            stop_time=STOP,
            output_interval=1e-3,
            start_values=start,
        )
        for version in ("2.0", "3.0")
    }
    r2, r3 = results["2.0"], results["3.0"]
    assert r2.dtype.names == r3.dtype.names
    # The scene must actually stick and slip in the compared window.
    assert r2["transitions"][-1] >= 1
    for column in r2.dtype.names:
        assert np.array_equal(r2[column], r3[column]), column


@pytest.mark.parametrize("law", ["neural", "exponential"])
def test_friction_outputs_equal_fmi2_bit_for_bit(paths, law):
    model = Model.read(paths["2.0"][FRICTION])
    t = np.linspace(0.0, 0.1, 101)
    inputs = np.array(
        list(zip(t, 0.05 * np.sin(60.0 * t), 100.0 + 10.0 * t)),
        dtype=[("time", float), ("sliding_velocity", float), ("normal_force", float)],
    )
    results = [
        simulate_fmu(
            str(paths[version][FRICTION]),
            stop_time=0.1,
            output_interval=1e-3,
            input=inputs,
            start_values={"law": model.code("law", law)},
        )
        for version in ("2.0", "3.0")
    ]
    assert np.ptp(results[0]["friction_force"]) > 1.0
    for column in results[0].dtype.names:
        assert np.array_equal(results[0][column], results[1][column]), column


def slave(paths, unzipped, name, instance="a", messages=None):
    description = read_model_description(str(paths["3.0"][name]))
    fmu = FMU3Slave(
        guid=description.instantiationToken,
        unzipDirectory=unzipped[name],
        modelIdentifier=description.coSimulation.modelIdentifier,
        instanceName=instance,
    )

    def log(environment, status, category, message):
        if messages is not None:
            messages.append((status, category.decode(), message.decode()))

    fmu.instantiate(logMessage=log)
    return fmu, description


def vr(description, name):
    return next(v.valueReference for v in description.modelVariables if v.name == name)


def test_illegal_calls_are_refused(paths, unzipped):
    """FMI 3.0's co-simulation state table (section 4.2.4): a step before initialisation,
    a fixed parameter set in Step Mode, event mode in an instance instantiated without
    it, and a call after the error."""
    messages = []
    fmu, description = slave(paths, unzipped, BEAM, messages=messages)
    with pytest.raises(FMICallException) as error:
        fmu.doStep(0.0, 1e-3)
    assert error.value.status == FMI3_ERROR
    assert any("fmi3DoStep: illegal call sequence" in m for _, _, m in messages), messages
    fmu.reset()

    fmu.enterInitializationMode(startTime=0.0, stopTime=1.0)
    fmu.exitInitializationMode()
    fmu.doStep(0.0, 1e-3)
    with pytest.raises(FMICallException):
        fmu.setFloat64([vr(description, "geometry.length")], [2.5])
    assert any("fmi3SetFloat64" in m and "fixed parameter" in m for _, _, m in messages), messages
    fmu.reset()

    fmu.enterInitializationMode(startTime=0.0, stopTime=1.0)
    fmu.exitInitializationMode()
    for call in (fmu.enterEventMode, fmu.enterStepMode):
        with pytest.raises(FMICallException):
            call()
    # Instantiated without eventModeUsed: no Event Mode, and no Step Mode to re-enter.
    assert any("instantiated with eventModeUsed = false" in m for _, _, m in messages), messages
    # In the error state only reset, free, and the FMU-state functions are accepted.
    with pytest.raises(FMICallException):
        fmu.doStep(1e-3, 1e-3)
    # Value types without variables: an empty request is fine, a value reference not.
    fmu.reset()
    with pytest.raises(FMICallException):
        fmu.getFloat32([])  # Instantiated: no gets before Initialization Mode
    fmu.reset()
    fmu.enterInitializationMode(startTime=0.0, stopTime=1.0)
    fmu.getFloat32([])
    with pytest.raises(FMICallException):
        fmu.getInt64([vr(description, "friction.law")])
    fmu.freeInstance()


def outputs(fmu, description):
    refs = [v.valueReference for v in description.modelVariables if v.causality == "output"]
    kinds = {v.valueReference: v.type for v in description.modelVariables}
    return [
        fmu.getFloat64([r])[0]
        if kinds[r] == "Float64"
        else (fmu.getInt32([r])[0] if kinds[r] == "Int32" else fmu.getBoolean([r])[0])
        for r in refs
    ]


def test_state_round_trips_are_bit_identical(paths, unzipped):
    """Get, set, serialize and deserialize: from a saved state the next steps give the
    same outputs as the uninterrupted run, in the same instance and in a fresh one."""
    fmu, description = slave(paths, unzipped, BEAM, "first")
    fmu.enterInitializationMode(startTime=0.0, stopTime=1.0)
    fmu.setInt32([vr(description, "fidelity.level")], [1])
    fmu.exitInitializationMode()
    h, t = 1e-3, 0.0
    for _ in range(380):
        fmu.doStep(t, h)
        t += h
    state = fmu.getFMUState()
    saved_t = t
    serialized = fmu.serializeFMUState(state)
    reference = []
    for _ in range(100):  # across the breakaway
        fmu.doStep(t, h)
        t += h
        reference.append(outputs(fmu, description))
    fmu.setFMUState(state)
    t = saved_t
    again = []
    for _ in range(100):
        fmu.doStep(t, h)
        t += h
        again.append(outputs(fmu, description))
    assert again == reference

    other, _ = slave(paths, unzipped, BEAM, "second")
    restored = other.deserializeFMUState(serialized)
    other.setFMUState(restored)
    assert other.serializeFMUState(other.getFMUState()) == serialized
    t = saved_t
    fresh = []
    for _ in range(100):
        other.doStep(t, h)
        t += h
        fresh.append(outputs(other, description))
    assert fresh == reference
    fmu.freeFMUState(state)
    other.freeFMUState(restored)
    fmu.terminate()
    fmu.freeInstance()
    other.freeInstance()


def test_resource_path_is_a_path_not_a_uri(paths, unzipped):
    """FMI 3.0 passes the resources directory as an absolute path with a trailing
    separator (fmpy does so); FMI 2.0's file URI is refused with the reason."""
    description = read_model_description(str(paths["3.0"][FRICTION]))
    library = ctypes.CDLL(f"{unzipped[FRICTION]}/binaries/x86_64-linux/{FRICTION}.so")
    function = library.fmi3InstantiateCoSimulation
    function.restype = ctypes.c_void_p
    messages = []

    def log(environment, status, category, message):
        messages.append(message.decode())

    callback = fmi3LogMessageCallback(log)
    no_update = fmi3IntermediateUpdateCallback()

    def instantiate(resources: str):
        return function(
            b"r",
            description.instantiationToken.encode(),
            resources.encode(),
            fmi3Boolean(False),
            fmi3Boolean(False),
            fmi3Boolean(False),
            fmi3Boolean(False),
            (fmi3ValueReference * 0)(),
            ctypes.c_size_t(0),
            fmi3InstanceEnvironment(),
            callback,
            no_update,
        )

    uri = f"file://{unzipped[FRICTION]}/resources/"
    assert not instantiate(uri)
    assert any("is a URI" in m for m in messages), messages
    good = instantiate(f"{unzipped[FRICTION]}/resources/")
    assert good
    library.fmi3FreeInstance.argtypes = [ctypes.c_void_p]
    library.fmi3FreeInstance(good)
    # The network is read from there: an empty folder does not have it.
    empty = tempfile.mkdtemp()
    try:
        assert not instantiate(empty + "/")
    finally:
        shutil.rmtree(empty)


def six_feature_network(path):
    """The shipped plain network with four more inputs (role other, trained range [-1, 1])
    that every first-layer unit reads, written to `path`: a network that uses all of
    NeuralFriction's inputs (the Rust tests build the same one)."""
    import json

    from stickslip_checks.artifacts import SHIPPED_WEIGHTS

    network = json.loads(SHIPPED_WEIGHTS.read_text())
    for k in range(1, 5):
        network["features"].append(
            {
                "name": f"extra{k}",
                "unit": "",
                "role": "other",
                "input_mean": 0.0,
                "input_std": 1.0,
                "min": -1.0,
                "max": 1.0,
            }
        )
    network["layer_sizes"][0] = 6
    for o, row in enumerate(network["layers"][0]["weights"]):
        row.extend(0.2 + 0.05 * ((o + k) % 5) for k in range(4))
    path.write_text(json.dumps(network))
    return path


def test_extra_features_are_one_array_that_reaches_the_network(paths, unzipped, tmp_path):
    """NeuralFriction's FMI 3.0 input `extra_feature` is one Float64 array of four
    (value reference 16); set with fmi3SetFloat64 in a request that also holds scalars,
    it gives the network the same four values as FMI 2.0's `extra_feature[1..4]`: every
    output equal bit for bit, and other values give another force."""
    from fmpy.fmi2 import FMU2Slave

    description3 = read_model_description(str(paths["3.0"][FRICTION]))
    array = next(v for v in description3.modelVariables if v.name == "extra_feature")
    assert (array.type, array.causality, array.valueReference) == ("Float64", "input", 16)
    assert [int(d.start) for d in array.dimensions] == [4]
    assert not any(v.name.startswith("extra_feature[") for v in description3.modelVariables)

    weights = str(six_feature_network(tmp_path / "six-features.json"))
    features, velocity, normal = [0.3, -0.6, 0.8, -0.1], 0.05, 100.0
    model = Model.read(paths["2.0"][FRICTION])
    neural = model.code("law", "neural")
    law_outputs = ["friction_force", "friction_force_magnitude", "friction_coefficient"]

    description2 = read_model_description(str(paths["2.0"][FRICTION]))
    folder2 = extract(str(paths["2.0"][FRICTION]))
    try:
        two = FMU2Slave(
            guid=description2.guid,
            unzipDirectory=folder2,
            modelIdentifier=FRICTION,
            instanceName="scalars",
        )
        two.instantiate()
        two.setupExperiment(startTime=0.0)
        two.enterInitializationMode()
        two.setInteger([vr(description2, "law")], [neural])
        two.setString([vr(description2, "weights")], [weights])
        two.exitInitializationMode()
        elements = [vr(description2, f"extra_feature[{k}]") for k in range(1, 5)]
        inputs = [vr(description2, "sliding_velocity"), vr(description2, "normal_force")]
        two.setReal(elements + inputs, features + [velocity, normal])
        out2 = two.getReal([vr(description2, name) for name in law_outputs])
        two.setReal(elements, [0.0] * 4)
        zeros = two.getReal([vr(description2, "friction_force")])[0]
        two.terminate()
        two.freeInstance()
    finally:
        shutil.rmtree(folder2, ignore_errors=True)

    three, _ = slave(paths, unzipped, FRICTION, "array")
    three.enterInitializationMode(startTime=0.0)
    three.setInt32([vr(description3, "law")], [neural])
    three.setString([vr(description3, "weights")], [weights])
    three.exitInitializationMode()
    three.setFloat64(
        [vr(description3, "sliding_velocity"), 16, vr(description3, "normal_force")],
        [velocity, *features, normal],
    )
    out3 = three.getFloat64([vr(description3, name) for name in law_outputs])
    assert three.getFloat64([16], nValues=4) == features
    assert out3 == out2
    assert abs(out3[0] - zeros) > 1e-3 * abs(zeros), (out3[0], zeros)
    # A request whose nValues does not count the array's four values is refused.
    with pytest.raises(FMICallException):
        three.getFloat64([16])
    three.freeInstance()


def test_time_reads_as_the_instance_clock(paths, unzipped):
    """`time` (value reference 0, the independent variable) reads as the instance's
    current time, as in Reference-FMUs; setting it is refused with the reason."""
    messages = []
    fmu, _ = slave(paths, unzipped, BEAM, "time", messages=messages)
    fmu.enterInitializationMode(startTime=0.1, stopTime=1.0)
    assert fmu.getFloat64([0]) == [0.1]
    fmu.exitInitializationMode()
    t = 0.1
    for _ in range(5):
        fmu.doStep(t, 1e-3)
        t += 1e-3
    assert fmu.getFloat64([0]) == [t]
    with pytest.raises(FMICallException):
        fmu.setFloat64([0], [0.0])
    assert any("independent variable" in m for _, _, m in messages), messages
    fmu.freeInstance()


def test_the_side_by_side_table_sees_equal_runs(paths):
    """stickslip_checks.versions (the main job's table) on a short run: both
    versions' columns filled, equal bit for bit, the breakaway at 0.4 s in each."""
    from stickslip_checks import versions

    row = versions.beam_row(paths, "modal", "exponential", t_end=0.5)
    assert row.identical and row.max_difference == 0.0
    assert row.breakaway[0] == row.breakaway[1] == pytest.approx(0.4, abs=1e-3)
    assert row.transitions[0] == row.transitions[1] >= 1


def test_every_run_of_the_main_jobs_table_is_equal_bit_for_bit(paths):
    """The whole fmi_versions table (every structural model with both laws over the
    paper scene, NeuralFriction with both laws): every output of every sample equal."""
    from stickslip_checks import versions

    rows = versions.compare_all(paths)
    assert len(rows) >= 8
    for row in rows:
        assert row.identical and row.max_difference == 0.0, (row.name, row.max_difference)
    frame = versions.to_frame(rows)
    assert frame["identical"].all() and frame["run"].tolist() == [r.name for r in rows]
