"""NeuralFriction's directional derivatives through fmpy's API, as a training tool that
wraps FMUs (FMIFlux-like) uses them: the capability flag, then the Jacobian of the outputs
with respect to the inputs that ModelStructure lists as their dependencies, column by
column with unit seeds, for both shipped networks and both FMI versions.

Checked against central differences of the outputs read through the same API, at random
points of the network's training domain. Tolerance (as in tests/fmu/directional.rs):
D_h = (y(x+h) - y(x-h)) / 2h is off by h^2 y'''/6 (truncation) plus 2 r / 2h (rounding of
outputs with error r). With h = 1e-4 standard deviations of the input, |D_2h - D_h|
(= 3 h^2 y'''/6 + O(h^4)) bounds three times the truncation, and r <= 1000 eps max(|y|, 1);
so |exact - D_h| <= |D_2h - D_h| + 1000 eps max(|y|, 1) / h. Stencils on which the force
changes sign (v = 0, the kink of |F|) are skipped.

StickSlipBeam does not provide directional derivatives: its flag is false and the call
raises fmpy's FMICallException (fmi2Error/fmi3Error), it does not crash.

Needs the FMUs built by `cargo run --release -p fmu-build`.
"""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

from stickslip_checks.artifacts import (
    BEAM,
    FRICTION,
    REPO,
    fmu3_paths,
    fmu_paths,
    model_description_xml,
)

EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def paths():
    try:
        return {"2.0": fmu_paths(), "3.0": fmu3_paths()}
    except FileNotFoundError as error:
        pytest.fail(str(error), pytrace=False)


class Friction:
    """An initialised NeuralFriction of one FMI version, driven through fmpy."""

    def __init__(self, path, version: str, weights: str, folder: str):
        self.description = read_model_description(str(path))
        self.version = version
        self.vr = {v.name: v.valueReference for v in self.description.modelVariables}
        two = version == "2.0"
        self.fmu = (FMU2Slave if two else FMU3Slave)(
            guid=self.description.guid if two else self.description.instantiationToken,
            unzipDirectory=folder,
            modelIdentifier=FRICTION,
            instanceName="jacobian",
        )
        self.fmu.instantiate()
        if two:
            self.fmu.setupExperiment(startTime=0.0)
            self.fmu.enterInitializationMode()
        else:
            self.fmu.enterInitializationMode(startTime=0.0)
        self.fmu.setString([self.vr["weights"]], [weights])
        self.fmu.exitInitializationMode()
        # The user's view: each output and the inputs ModelStructure says it depends on.
        self.outputs = [u.variable.valueReference for u in self.description.outputs]
        self.knowns = sorted(
            {
                d.valueReference
                for u in self.description.outputs
                for d in (u.dependencies or [])
                if d.name in ("sliding_velocity", "normal_force")
            }
        )

    def set(self, values: dict[int, float]) -> None:
        if self.version == "2.0":
            self.fmu.setReal(list(values), list(values.values()))
        else:
            self.fmu.setFloat64(list(values), list(values.values()))

    def read(self) -> np.ndarray:
        if self.version == "2.0":
            return np.array(self.fmu.getReal(self.outputs))
        return np.array(self.fmu.getFloat64(self.outputs))

    def column(self, known: int) -> np.ndarray:
        return np.array(self.fmu.getDirectionalDerivative(self.outputs, [known], [1.0]))

    def close(self) -> None:
        self.fmu.terminate()
        self.fmu.freeInstance()


def training_box(weights: str) -> dict[str, tuple[float, float, float]]:
    """(min, max, std) of the velocity and normal-force features of a shipped network."""
    model = json.loads((REPO / "weights" / weights).read_text())
    return {f["role"]: (f["min"], f["max"], f["input_std"]) for f in model["features"]}


@pytest.mark.parametrize("version", ["2.0", "3.0"])
@pytest.mark.parametrize("weights", ["paper-plain.json", "paper-signed.json"])
def test_jacobian_matches_central_differences(paths, version, weights):
    path = paths[version][FRICTION]
    xml = model_description_xml(path).decode()
    flag = "providesDirectionalDerivative" + ("s" if version == "3.0" else "")
    assert f'{flag}="true"' in xml
    folder = extract(str(path))
    friction = Friction(path, version, weights, folder)
    try:
        box = training_box(weights)
        inputs = {
            friction.vr["sliding_velocity"]: box["sliding_velocity"],
            friction.vr["normal_force"]: box["normal_force"],
        }
        assert friction.knowns == sorted(inputs)
        rng = np.random.default_rng(23)
        compared = 0
        for _ in range(25):
            x = {vr: lo + (hi - lo) * rng.uniform(0.01, 0.99) for vr, (lo, hi, _) in inputs.items()}
            for known, (_, _, std) in inputs.items():
                friction.set(x)
                exact = friction.column(known)
                h = 1e-4 * std
                stencil = []
                for t in (-2, -1, 1, 2):
                    friction.set({**x, known: x[known] + t * h})
                    stencil.append(friction.read())
                force = friction.outputs.index(friction.vr["friction_force"])
                forces = [y[force] for y in stencil]
                if min(forces) <= 0.0 <= max(forces):
                    continue
                d_h = (stencil[2] - stencil[1]) / (2 * h)
                d_2h = (stencil[3] - stencil[0]) / (4 * h)
                scale = np.maximum(np.max(np.abs(stencil), axis=0), 1.0)
                tolerance = np.abs(d_2h - d_h) + 1000 * EPS * scale / h
                assert np.all(np.abs(exact - d_h) <= tolerance), (x, known, exact, d_h, tolerance)
                compared += len(exact)
        assert compared >= 200, compared
    finally:
        friction.close()
        shutil.rmtree(folder, ignore_errors=True)


def test_both_versions_give_the_same_jacobian(paths):
    folders = {version: extract(str(paths[version][FRICTION])) for version in ("2.0", "3.0")}
    fmus = {
        version: Friction(paths[version][FRICTION], version, "paper-signed.json", folder)
        for version, folder in folders.items()
    }
    try:
        for fmu in fmus.values():
            fmu.set({fmu.vr["sliding_velocity"]: -0.07, fmu.vr["normal_force"]: 103.0})
        columns = {v: [list(f.column(k)) for k in f.knowns] for v, f in fmus.items()}
        assert columns["2.0"] == columns["3.0"]
    finally:
        for fmu in fmus.values():
            fmu.close()
        for folder in folders.values():
            shutil.rmtree(folder, ignore_errors=True)


@pytest.mark.parametrize("version", ["2.0", "3.0"])
def test_the_beam_refuses(paths, version):
    path = paths[version][BEAM]
    flag = "providesDirectionalDerivative" + ("s" if version == "3.0" else "")
    assert f'{flag}="false"' in model_description_xml(path).decode()
    description = read_model_description(str(path))
    folder = extract(str(path))
    try:
        kind = FMU2Slave if version == "2.0" else FMU3Slave
        token = description.guid if version == "2.0" else description.instantiationToken
        beam = kind(guid=token, unzipDirectory=folder, modelIdentifier=BEAM, instanceName="b")
        beam.instantiate()
        output = description.outputs[0].variable.valueReference
        known = next(v.valueReference for v in description.modelVariables if v.causality == "input")
        with pytest.raises(FMICallException):
            beam.getDirectionalDerivative([output], [known], [1.0])
        beam.freeInstance()
    finally:
        shutil.rmtree(folder, ignore_errors=True)
