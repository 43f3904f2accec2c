"""The FMUs under fmpy: validation, the stick-slip curve (against the command line),
missing resources, refused inputs and parameters, and the FMI call order.

Needs the FMUs built by `cargo run --release -p fmu-build`; they are read from the 2.0/
folder of $STICKSLIP_FMU_DIR, else of $CARGO_TARGET_DIR/fmu, else of <repo>/target/fmu.
Without them every
test here FAILS (it is not skipped) and says how to build them. The command-line binary
is $STICKSLIP_BIN, else the release binary built (if needed) by cargo.

Runs in a few seconds once the FMUs and the binary exist.
"""

from __future__ import annotations

import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from conftest import need
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.validation import validate_fmu

from stickslip_checks.artifacts import BEAM, FRICTION, Fmus, find_binary, fmu_paths
from stickslip_checks import scene
from stickslip_checks.scene import exponential_law, friction_sweep

FMI2_ERROR = 3
BELT_SPEED = 0.02  # m/s
BREAKAWAY = 0.400  # s


_beam_result = {}


def beam_curve(fmus: Fmus):
    """The paper scene at beam fidelity through simulate_fmu, 1 ms output (cached)."""
    if "beam" not in _beam_result:
        _beam_result["beam"] = simulate_fmu(
            str(fmus.paths[BEAM]),
            start_time=0.0,
            stop_time=1.2,
            output_interval=1e-3,
            start_values={"fidelity.level": fmus.models[BEAM].code("fidelity.level", "beam")},
        )
    return _beam_result["beam"]


def initialised(fmus: Fmus, name: str, instance: str, **integers):
    """An instantiated slave in step mode (integer parameters by name set first)."""
    slave = fmus.slave(name, instance)
    slave.instantiate()
    slave.setupExperiment(startTime=0.0, stopTime=1.2)
    slave.enterInitializationMode()
    if integers:
        vr = fmus.vr[name]
        slave.setInteger([vr[k.replace("__", ".")] for k in integers], list(integers.values()))
    slave.exitInitializationMode()
    return slave


def still_usable(fmus: Fmus, slave, name: str) -> None:
    """After an fmi2Error: fmi2Reset brings the instance back and it steps again."""
    slave.reset()
    slave.setupExperiment(startTime=0.0, stopTime=1.2)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    for k in range(3):
        slave.doStep(currentCommunicationPoint=k * 1e-3, communicationStepSize=1e-3)
    output = "tip_deflection" if name == BEAM else "friction_force"
    (value,) = slave.getReal([fmus.vr[name][output]])
    assert np.isfinite(value)
    slave.terminate()
    slave.freeInstance()


# ----------------------------------------------------------------------------- tests


def test_fmu_dir_missing_fails_with_the_build_command(tmp_path, monkeypatch):
    monkeypatch.setenv("STICKSLIP_FMU_DIR", str(tmp_path / "no-such-dir"))
    with pytest.raises(FileNotFoundError, match="cargo run --release -p fmu-build"):
        fmu_paths()


def test_fmus_left_at_the_old_top_level_paths_are_not_used(tmp_path, monkeypatch):
    """An older fmu-build wrote the FMI 2.0 FMUs at <fmu root>/*.fmu; they now live in
    <fmu root>/2.0/. A stale copy at the old place must not be run in their stead."""
    for name in (BEAM, FRICTION):
        (tmp_path / f"{name}.fmu").write_bytes(b"stale")
    monkeypatch.setenv("STICKSLIP_FMU_DIR", str(tmp_path))
    with pytest.raises(FileNotFoundError, match="2.0"):
        fmu_paths()


@pytest.mark.parametrize("name", [BEAM, FRICTION])
def test_validate_fmu_finds_no_problem(built, name):
    fmus = need(built)
    assert validate_fmu(str(fmus.paths[name])) == []


@pytest.fixture(scope="module")
def scene_runs(built):
    """fmu_scene's runs, or the error that says how to build the FMUs."""
    return built if isinstance(built, Exception) else scene.run_all(built)


def test_every_run_of_the_scene_breaks_away_at_0_4_s_and_agrees_before(scene_runs):
    """fmu_scene's runs (every structural model; exponential law, both networks embedded,
    both couplings): breakaway within 1 ms of 0.400 s, and in stick the kinetic law is
    never evaluated, so every law gives the exponential run's curve up to its breakaway
    (1e-12 m leaves room for rounding only)."""
    runs = need(scene_runs)
    assert len(runs) == 15
    for r in runs:
        b = r.metrics["breakaway"]
        assert b is not None, r.name
        assert abs(b - scene.BREAKAWAY_EXPECTED) <= scene.BREAKAWAY_TOLERANCE + 1e-12, (r.name, b)
        pre = r.metrics["dev_before_breakaway"]
        assert pre is not None and pre <= scene.PRE_SLIP_TOLERANCE, (r.name, pre)


def test_the_frames_hold_the_csv_files_rows(scene_runs):
    runs = need(scene_runs)
    table, slips = scene.to_frames(runs)
    assert table["run"].tolist() == [r.name for r in runs]
    assert table["breakaway [s]"].astype(float).tolist() == [r.metrics["breakaway"] for r in runs]
    assert len(slips) == sum(r.metrics["major_slips"] for r in runs)


def test_beam_fidelity_reproduces_the_stick_slip_curve(built):
    result = beam_curve(need(built))
    t, u, stick = result["time"], result["tip_deflection"], result["stick"].astype(bool)
    assert len(t) == 1201
    np.testing.assert_allclose(t, np.arange(1201) * 1e-3, rtol=0, atol=1e-12)
    # Stick phase: the tip rides on the belt from u = 0.
    before = t < BREAKAWAY - 1e-9
    assert stick[before].all()
    np.testing.assert_allclose(u[before], BELT_SPEED * t[before], rtol=0, atol=1e-9)
    # Breakaway: the first sample in slip is t = 0.400 s, at u = v_b * 0.4 s = 8 mm.
    first_slip = np.flatnonzero(~stick)[0]
    assert t[first_slip] == pytest.approx(BREAKAWAY, abs=1e-9)
    assert u[first_slip] == pytest.approx(BELT_SPEED * BREAKAWAY, abs=1e-6)
    # Then stick-slip: several transitions, the deflection inside the paper's corridor.
    after = t >= BREAKAWAY
    assert result["transitions"][-1] >= 10
    assert 4e-3 < u[after].min() < u[after].max() < 9e-3


def test_beam_fidelity_equals_the_command_line(built, tmp_path):
    result = beam_curve(need(built))
    csv_path = tmp_path / "beam.csv"
    command = [
        str(find_binary()),
        "simulate",
        "--fidelity",
        "beam",
        "--every",
        "10",
        "--out",
        str(csv_path),
    ]
    subprocess.run(command, check=True, capture_output=True, text=True)
    cli = np.genfromtxt(csv_path, delimiter=",", names=True)
    # Common times: the CLI writes every 10th step of 0.1 ms, the FMU every 1 ms.
    fmu_index = {round(t * 1e3): k for k, t in enumerate(result["time"])}
    pairs = [(fmu_index[round(t * 1e3)], j) for j, t in enumerate(cli["t"])]
    assert len(pairs) == len(result["time"]) == 1201
    k, j = map(np.array, zip(*pairs))
    np.testing.assert_allclose(result["time"][k], cli["t"][j], rtol=0, atol=1e-12)
    np.testing.assert_allclose(
        result["tip_deflection"][k], cli["tip_deflection"][j], rtol=0, atol=1e-12
    )
    np.testing.assert_array_equal(result["stick"][k].astype(int), cli["stick"][j].astype(int))


@pytest.mark.parametrize("name", [BEAM, FRICTION])
def test_missing_weights_resource_fails_instantiation(built, tmp_path, name):
    fmus = need(built)
    source = fmus.paths[name]

    def copy(target: Path, leave_out: str | None) -> Path:
        with zipfile.ZipFile(source) as zin, zipfile.ZipFile(target, "w") as zout:
            for item in zin.infolist():
                if item.filename != leave_out:
                    zout.writestr(item, zin.read(item.filename))
        return target

    # Control: a full copy instantiates (so the copying is not what breaks it).
    full = copy(tmp_path / f"{name}-full.fmu", None)
    assert len(simulate_fmu(str(full), stop_time=0.01, output_interval=1e-3)) == 11

    broken = copy(tmp_path / f"{name}.fmu", "resources/paper-plain.json")
    with zipfile.ZipFile(broken) as z:
        assert "resources/paper-plain.json" not in z.namelist()
        assert "resources/paper-signed.json" in z.namelist()
    with pytest.raises(Exception, match="[Ii]nstantiate"):
        simulate_fmu(str(broken), stop_time=0.01, output_interval=1e-3)


@pytest.mark.parametrize(
    ("name", "variable"),
    [
        (BEAM, "belt_speed"),
        (BEAM, "normal_force"),
        (BEAM, "external.kinetic_force"),
        (FRICTION, "sliding_velocity"),
        (FRICTION, "normal_force"),
    ],
)
def test_nan_input_is_an_fmi2_error(built, name, variable):
    fmus = need(built)
    slave = initialised(fmus, name, "nan")
    slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=1e-3)
    with pytest.raises(FMICallException) as error:
        slave.setReal([fmus.vr[name][variable]], [float("nan")])
    assert error.value.status == FMI2_ERROR
    still_usable(fmus, slave, name)


def test_negative_youngs_modulus_is_an_fmi2_error(built):
    fmus = need(built)
    # Through simulate_fmu, as a user would set it.
    with pytest.raises(FMICallException) as error:
        simulate_fmu(
            str(fmus.paths[BEAM]),
            stop_time=0.01,
            output_interval=1e-3,
            start_values={
                "material.youngs_modulus": -2.1e11,
                "fidelity.level": fmus.models[BEAM].code("fidelity.level", "beam"),
            },
        )
    assert error.value.status == FMI2_ERROR
    # Step by step: refused when initialisation ends; the instance survives a reset.
    slave = fmus.slave(BEAM, "negative-E")
    slave.instantiate()
    slave.setupExperiment(startTime=0.0, stopTime=1.2)
    slave.enterInitializationMode()
    slave.setReal([fmus.vr[BEAM]["material.youngs_modulus"]], [-2.1e11])
    with pytest.raises(FMICallException) as error:
        slave.exitInitializationMode()
    assert error.value.status == FMI2_ERROR
    still_usable(fmus, slave, BEAM)


@pytest.mark.parametrize("name", [BEAM, FRICTION])
def test_do_step_before_initialisation_raises(built, name):
    fmus = need(built)
    slave = fmus.slave(name, "order")
    slave.instantiate()
    with pytest.raises(FMICallException) as error:
        slave.doStep(currentCommunicationPoint=0.0, communicationStepSize=1e-3)
    assert error.value.status == FMI2_ERROR
    still_usable(fmus, slave, name)


def test_fixed_parameter_after_initialisation_raises(built):
    fmus = need(built)
    beam = fmus.models[BEAM].code("fidelity.level", "beam")
    slave = initialised(fmus, BEAM, "fixed", fidelity__level=beam)
    with pytest.raises(FMICallException) as error:
        slave.setReal([fmus.vr[BEAM]["material.youngs_modulus"]], [2.0e11])
    assert error.value.status == FMI2_ERROR
    still_usable(fmus, slave, BEAM)


def test_exponential_law_is_paper_eq6_at_the_start_values(built):
    """NeuralFriction's exponential law against the oracle scene.exponential_law
    (Eq. 6 written out in Python, coefficients from the model description's start
    values): the same formula, so only rounding may differ. Also on both sides of the
    jump at v = 0, where the sign of v decides."""
    fmus = need(built)
    friction = fmus.models[FRICTION]
    velocities = np.concatenate([np.linspace(-0.35, 0.35, 701), [-1e-9, 1e-9, 2.0]])
    v, force = friction_sweep(fmus, "exponential", velocities=velocities)
    expected = exponential_law(v, friction)
    np.testing.assert_allclose(force, expected, rtol=1e-12, atol=1e-12)
    # Eq. 6 at its ends: mu_s F_n at v -> 0+, and toward mu_k F_n at large |v|.
    names = ("static_coefficient", "kinetic_coefficient", "normal_force")
    mu_s, mu_k, f_n = (friction.real_start(name) for name in names)
    assert expected[-2] == pytest.approx(mu_s * f_n, rel=1e-7)
    assert expected[-3] == pytest.approx(-mu_s * f_n, rel=1e-7)
    assert expected[-1] == pytest.approx(mu_k * f_n, rel=1e-4)
