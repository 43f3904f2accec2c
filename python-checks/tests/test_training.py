"""The training entry point's checks: `stickslip train` with the settings the shipped
network records reproduces weights/paper-plain.json byte for byte (the network inside
the FMUs is the one trained here), and NeuralFriction.fmu on every test sample gives
the trainer's test MSE to FMU_AGREEMENT (1e-9) relative (same network, inputs inside
the training range, so the FMU's clamping never acts).

Needs the FMUs and the binary ($STICKSLIP_BIN, else cargo builds it). About 15 s.
"""

from __future__ import annotations

from conftest import need

from stickslip_checks import retraining, sklearn_peer
from stickslip_checks.artifacts import find_binary


def test_retrained_network_is_the_shipped_one_and_the_fmu_agrees_with_the_trainer(
    built, tmp_path
):
    fmus = need(built)
    report = retraining.train(find_binary(), tmp_path)
    result = retraining.evaluate(fmus, tmp_path, report)
    assert result.weights_equal
    assert len(result.predicted) == sklearn_peer.shipped_training()["test_samples"]
    assert result.relative < retraining.FMU_AGREEMENT, (result.mse, report["mse_test"])
