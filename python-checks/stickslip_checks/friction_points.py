"""NeuralFriction.fmu evaluated point by point, in FMI 2.0 and FMI 3.0 (fmpy): the
friction force of a weights file (our JSON or an .onnx) at given (sliding velocity,
normal force) pairs. NeuralFriction has no state and evaluates its outputs when they are
read (src/fmi/src/friction.rs), so setting the inputs and reading friction_force is
the law at that point; no step is needed. Used by the ONNX and fitrnet import checks.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi3 import FMU3Slave

from .artifacts import FRICTION, Fmus

INPUTS = ("sliding_velocity", "normal_force")


def _evaluate(set_real, get_real, vr: dict, points: np.ndarray) -> np.ndarray:
    """friction_force at each (v, F_n) row, with the FMI version's Real setter and getter."""
    inputs, output = [vr[name] for name in INPUTS], [vr["friction_force"]]
    forces = np.empty(len(points))
    for k, (v, f_n) in enumerate(points):
        set_real(inputs, [float(v), float(f_n)])
        forces[k] = get_real(output)[0]
    return forces


def fmi2_forces(fmus: Fmus, weights: str, points: np.ndarray) -> np.ndarray:
    """friction_force of the FMI 2.0 NeuralFriction.fmu with `weights` at every row
    (v [m/s], F_n [N]) of `points`."""
    vr = fmus.vr[FRICTION]
    slave = fmus.slave(FRICTION, "points")
    slave.instantiate()
    slave.setString([vr["weights"]], [weights])
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    forces = _evaluate(slave.setReal, slave.getReal, vr, points)
    slave.terminate()
    slave.freeInstance()
    return forces


def fmi3_forces(fmu: Path, weights: str, points: np.ndarray) -> np.ndarray:
    """The same through the FMI 3.0 NeuralFriction.fmu at `fmu` (fmi3SetFloat64 /
    fmi3GetFloat64; the weights set in Initialization Mode)."""
    description = read_model_description(str(fmu))
    vr = {v.name: v.valueReference for v in description.modelVariables}
    folder = extract(str(fmu))
    try:
        slave = FMU3Slave(guid=description.instantiationToken, unzipDirectory=folder,
                          modelIdentifier=description.coSimulation.modelIdentifier,
                          instanceName="points")
        slave.instantiate()
        slave.enterInitializationMode(startTime=0.0)
        slave.setString([vr["weights"]], [weights])
        slave.exitInitializationMode()
        forces = _evaluate(slave.setFloat64, slave.getFloat64, vr, points)
        slave.terminate()
        slave.freeInstance()
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    return forces


def relative(ours: np.ndarray, reference: np.ndarray) -> float:
    """max |ours - reference| / max |reference|: relative to the largest force, because a
    friction force passes through 0 at v = 0, where a pointwise ratio means nothing."""
    return float(np.max(np.abs(ours - reference)) / np.max(np.abs(reference)))

