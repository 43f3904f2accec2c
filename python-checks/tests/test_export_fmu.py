"""`stickslip export-fmu` (docs/structures.md, "Exporting an FMU"): the CalculiX beam
(examples/calculix-beam) exported for FMI 2.0 and 3.0 from the packaged StickSlipBeam.fmu,
validated by fmpy, and run by fmpy to 0.5 s equal to `stickslip simulate` of the same
scene at every communication point, to the digits its CSV prints (11 significant)."""

from __future__ import annotations

import subprocess

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from stickslip_checks.artifacts import REPO, find_binary

SCENE = REPO / "examples" / "calculix-beam" / "scene.toml"
STOP = 0.5
OUTPUT_INTERVAL = 1e-3
COLUMNS = ("tip_deflection", "tip_velocity", "friction_force")


def printed(values: np.ndarray) -> np.ndarray:
    """The values as the CSV prints them (`{:.10e}`: 11 significant digits)."""
    return np.array([float(f"{v:.10e}") for v in values])


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    """`stickslip simulate` of the scene to STOP: its CSV, every internal step (1e-4 s)."""
    out = tmp_path_factory.mktemp("cli") / "calculix.csv"
    subprocess.run(
        [find_binary(), "simulate", "--scene", SCENE, "--t-end", str(STOP), "--out", out],
        check=True,
        capture_output=True,
    )
    return np.genfromtxt(out, delimiter=",", names=True)


@pytest.mark.parametrize("version", ["2.0", "3.0"])
def test_exported_calculix_beam_validates_and_equals_the_cli(
    version, fmu_versions, cli_run, tmp_path
):
    fmu = tmp_path / "CalculixBeam.fmu"
    subprocess.run(
        [
            find_binary(),
            "export-fmu",
            "--scene",
            SCENE,
            "--out",
            fmu,
            "--fmi",
            version,
            "--from",
            fmu_versions[version]["StickSlipBeam"],
        ],
        check=True,
        capture_output=True,
    )
    assert validate_fmu(str(fmu)) == []
    result = simulate_fmu(
        str(fmu),
        stop_time=STOP,
        output_interval=OUTPUT_INTERVAL,
        output=[*COLUMNS, "stick"],
    )
    # The CSV has every internal step of 1e-4 s; the communication points are every 10th.
    cli = cli_run[::10]
    assert len(cli) == len(result) == 501
    for column in COLUMNS:
        fmu_values = printed(result[column])
        worst = np.max(np.abs(fmu_values - cli[column]))
        assert np.array_equal(fmu_values, cli[column]), f"{column}: largest difference {worst}"
    assert np.array_equal(result["stick"].astype(int), cli["stick"].astype(int))
