"""`stickslip export-fmu` (docs/structures.md, "Exporting an FMU"): the CalculiX beam
(examples/calculix-beam) exported for FMI 2.0 and 3.0 from the packaged StickSlipBeam.fmu,
validated by fmpy, and run by fmpy to 0.5 s equal to `stickslip simulate` of the same
scene at every communication point, to the digits its CSV prints (11 significant).

With sensors (`[structure] sensors`): the export validated by fmpy and by
fmu-manipulation-toolbox's `fmutool -check` (the FMU Compliance Checker is on no package
registry here: docs/structures.md), its sensor outputs equal to the CLI's sensor columns,
and run alone in libcosim equal to fmpy's run bit for bit.

Coupled: the Gmsh beam exported with `friction.law = external` in place of
StickSlipBeam in the StickSlipCoupled SSP system with NeuralFriction.fmu, run by libcosim
equal to our Jacobi master bit for bit, and by our Gauss-Seidel master within the
coupling error of the run with the network embedded."""

from __future__ import annotations

import subprocess

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from stickslip_checks import other_masters
from stickslip_checks.artifacts import BEAM, FRICTION, REPO, Fmus, find_binary
from stickslip_checks.master import GAUSS_SEIDEL, JACOBI, run_alone, run_coupled

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


SENSORS = (("mid_y", 252, 2), ("contact_y", 502, 2), ("tip_x", 502, 1))
SENSOR_COLUMNS = tuple(c for name, _, _ in SENSORS for c in (name, f"{name}_velocity"))


@pytest.fixture(scope="module")
def sensor_scene(tmp_path_factory):
    """The example scene with three sensors (mid-span in y, the contact DOF in y and x),
    its structure named by absolute path."""
    path = tmp_path_factory.mktemp("sensors") / "scene.toml"
    sensors = ", ".join(
        f'{{ name = "{name}", node = {node}, direction = {direction} }}'
        for name, node, direction in SENSORS
    )
    path.write_text(
        "[structure]\n"
        'format = "calculix"\n'
        f'job = "{REPO / "examples" / "calculix-beam" / "beam"}"\n'
        "contact = { node = 502, direction = 2 }\n"
        f"sensors = [{sensors}]\n"
    )
    return path


def export(scene, fmu, version, fmu_versions):
    subprocess.run(
        [
            find_binary(),
            "export-fmu",
            "--scene",
            scene,
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


@pytest.mark.parametrize("version", ["2.0", "3.0"])
def test_exported_sensors_pass_the_checkers_and_equal_the_cli(
    version, fmu_versions, sensor_scene, tmp_path
):
    fmu = tmp_path / "Sensors.fmu"
    export(sensor_scene, fmu, version, fmu_versions)
    assert validate_fmu(str(fmu)) == []
    check = subprocess.run(
        [other_masters.fmucontainer_command().parent / "fmutool", "-input", fmu, "-check"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    log = check.stdout + check.stderr
    assert f"This FMU seems to be compliant with FMI-{version}." in log, log
    assert f"No semantic error against the FMI-{version[0]} standard." in log, log

    csv = tmp_path / "sensors.csv"
    subprocess.run(
        [find_binary(), "simulate", "--scene", sensor_scene, "--t-end", str(STOP),
         "--out", csv, "--every", "10"],
        check=True,
        capture_output=True,
    )
    cli = np.genfromtxt(csv, delimiter=",", names=True)
    result = simulate_fmu(
        str(fmu),
        stop_time=STOP,
        output_interval=OUTPUT_INTERVAL,
        output=[*COLUMNS, *SENSOR_COLUMNS],
    )
    assert len(cli) == len(result) == 501
    for column in (*COLUMNS, *SENSOR_COLUMNS):
        fmu_values = printed(result[column])
        worst = np.max(np.abs(fmu_values - cli[column]))
        assert np.array_equal(fmu_values, cli[column]), f"{column}: largest difference {worst}"
    # The contact sensor is the tip, bit for bit.
    assert np.array_equal(result["contact_y"], result["tip_deflection"])
    assert np.array_equal(result["contact_y_velocity"], result["tip_velocity"])


def test_libcosim_runs_the_exported_fmu_as_fmpy(fmu_versions, sensor_scene, tmp_path):
    """libcosim (fixed-step, integer nanoseconds) on the exported FMI 2.0 FMU alone, to
    0.5 s at 1 ms: the tip, the friction force and every sensor equal fmpy's run bit for
    bit at all 501 points (libcosim hands the FMU the step size, which the FMU
    integrates over, so its clock does not move the bits)."""
    fmu = tmp_path / "SensorsCosim.fmu"
    export(sensor_scene, fmu, "2.0", fmu_versions)
    names = (*COLUMNS, *SENSOR_COLUMNS)
    cosim = other_masters.run_libcosim(
        fmu=fmu, record=tuple(("beam", n) for n in names), t_end=STOP
    )
    fmpy = other_masters.run_fmpy_fmu(fmu, names, t_end=STOP)
    n = round(STOP / other_masters.H)
    for name in names:
        got = cosim.at_grid(("beam", name), n)
        expected = fmpy.at_grid(("", name), n)
        assert not np.isnan(got).any() and not np.isnan(expected).any(), name
        assert np.array_equal(got, expected), (
            f"{name}: libcosim differs from fmpy by up to {np.max(np.abs(got - expected)):.3g}"
        )
    # Not a run that stays put: the tip slipped back (v < 0) before 0.5 s.
    assert np.min(cosim.at_grid(("beam", "tip_velocity"), n)) < 0


# ------------------------------------------------------------------ an export in a system

GMSH_SCENE = REPO / "examples" / "gmsh-beam" / "scene.toml"
# Past breakaway (0.40 s) into the first slip, where the coupling schemes part.
COUPLED_STOP = 0.7
# What the system sets on the exported beam; the rest is the export's (its scene's).
COUPLING = {"friction.law": "external", "external.coupling": "signed"}


@pytest.fixture(scope="module")
def coupled_export(fmu_versions, tmp_path_factory):
    """The Gmsh beam (examples/gmsh-beam: contact by its group "tip") with
    `friction.law = external` and a sensor by the same group in x, exported for FMI 2.0,
    and fmu-build's StickSlipCoupled.ssp with it in StickSlipBeam's place."""
    folder = tmp_path_factory.mktemp("coupled")
    text = GMSH_SCENE.read_text().replace(
        'mesh = "beam.msh"', f'mesh = "{GMSH_SCENE.parent / "beam.msh"}"'
    )
    assert 'contact = { group = "tip", direction = 2 }' in text
    scene = folder / "scene.toml"
    scene.write_text(
        '[friction]\nlaw = "external"\n\n'
        + text
        + 'sensors = [{ name = "corner_x", group = "tip", direction = 1 }]\n'
    )
    fmu = folder / "GmshBeam.fmu"
    export(scene, fmu, "2.0", fmu_versions)
    ssp = other_masters.ssp_with_beam(
        other_masters.COUPLED, fmu, folder / "GmshBeamCoupled.ssp", tuple(COUPLING)
    )
    return fmu, ssp


def test_an_exported_structure_coupled_to_neural_friction_runs_in_libcosim_as_in_our_master(
    fmu_versions, coupled_export
):
    """The export (friction.law = external, from its scene) coupled to NeuralFriction.fmu
    (the paper's plain network, external.coupling = signed) in an SSP system: libcosim
    (Jacobi, integer nanoseconds) equals our Jacobi master on the same clock bit for bit,
    in the tip, the friction force and the sensor. Our Gauss-Seidel master runs the same
    pair; both schemes are checked against the export with the network embedded
    (friction.law = neural, the monolithic run) within the coupling error measured on the
    built-in beam (docs/cosimulation.md: 45.6 um Gauss-Seidel, 130.5 um Jacobi over 0 to
    0.7 s at h = 1 ms), with a factor 2 of room for this structure (fully clamped, the
    corner node)."""
    fmu, ssp = coupled_export
    names = ("tip_deflection", "friction_force", "corner_x")
    n = round(COUPLED_STOP / other_masters.H)
    cosim = other_masters.run_libcosim(
        ssp=ssp, record=tuple(("beam", name) for name in names), t_end=COUPLED_STOP
    )
    fmus = Fmus({BEAM: fmu, FRICTION: fmu_versions["2.0"][FRICTION]})
    try:
        ours = {
            scheme: run_coupled(
                fmus,
                other_masters.H,
                COUPLED_STOP,
                beam={},
                friction={},
                record={BEAM: list(names)},
                scheme=scheme,
                coupling=COUPLING["external.coupling"],
                clock="nanoseconds" if scheme == JACOBI else "float",
            )
            for scheme in (JACOBI, GAUSS_SEIDEL)
        }
        monolithic = run_alone(
            fmus,
            BEAM,
            "monolithic",
            other_masters.H,
            COUPLED_STOP,
            record={BEAM: ["tip_deflection"]},
            parameters={BEAM: {"friction.law": "neural"}},
        )[BEAM, "tip_deflection"]
    finally:
        fmus.close()
    for name in names:
        got = cosim.at_grid(("beam", name), n)
        expected = ours[JACOBI][BEAM, name]
        assert not np.isnan(got).any(), name
        assert np.array_equal(got, expected), (
            f"{name}: libcosim differs from our Jacobi master by up to "
            f"{np.max(np.abs(got - expected)):.3g}"
        )
    # The corner moves along x as the beam bends (not a sensor that reads nothing).
    assert np.max(np.abs(ours[JACOBI][BEAM, "corner_x"])) > 0
    deviation = {
        scheme: float(np.max(np.abs(trace[BEAM, "tip_deflection"] - monolithic)))
        for scheme, trace in ours.items()
    }
    print(f"largest tip deviation from the monolithic run to {COUPLED_STOP} s: {deviation}")
    tip = monolithic
    assert tip.max() > 4e-3 and np.min(np.diff(tip)) < 0, "no breakaway: not a stick-slip run"
    assert 0 < deviation[GAUSS_SEIDEL] < 2 * 45.6e-6
    assert 0 < deviation[JACOBI] < 2 * 130.5e-6
