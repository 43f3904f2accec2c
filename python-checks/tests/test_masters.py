"""Our FMUs and SSP systems in the co-simulation masters users run them in: libcosim,
Ecos, fmucontainer (its container run by fmpy) and fmpy's SSP runner, each driven as its
users drive it (stickslip_checks.other_masters). For each master:

- it loads the systems, with every variable of the FMUs (choices included: they are
  Integers, which every master here supports, unlike FMI Enumerations);
- StickSlipBeam with no parameter given equals our master (fmpy) bit for bit;
- parameters set through the master (non-default choices) give what fmpy gives with
  the same settings, bit for bit, and differ from the defaults;
- the coupled systems (StickSlipCoupled, and NeuralFriction with the learned law with
  memory, rate-and-state and LuGre) equal our Jacobi or Gauss-Seidel master bit for bit,
  whichever scheme the master runs, in the tip deflection and the law's state;
- an FMU error at initialisation (a negative Young's modulus) reaches the user, or we
  record exactly what the user sees (docs/cosimulation.md, "Masters tested").

Runs at h = 1e-3 s to 0.7 s (breakaway at 0.4 s, then the first slip, where the schemes
part). Needs the FMUs and system files of `cargo run --release -p fmu-build`, and the
masters of python-checks/requirements-other_masters.txt (scripts/python-env.sh installs them).
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from conftest import need
from fmpy.ssp.ssd import read_ssd
from fmpy.validation import validate_fmu

from stickslip_checks import other_masters
from stickslip_checks.artifacts import BEAM, FRICTION, fmu_paths
from stickslip_checks.master import COUPLINGS, GAUSS_SEIDEL, JACOBI, run_coupled
from stickslip_checks.other_masters import (
    COUPLED,
    COUPLED_LUGRE,
    COUPLED_MEMORY,
    COUPLED_RATE_STATE,
    MONOLITHIC,
    STATE_OF,
    H,
    T_END,
)

N = round(T_END / H)
TIP = ("beam", "tip_deflection")
# A non-default choice of each kind the scripts set: the modal model and Coulomb friction.
NON_DEFAULT = {"fidelity.level": "modal", "friction.law": "coulomb"}

_references: dict = {}


def reference(fmus, key):
    """Our master's tip deflection (fmpy), cached per module run: "defaults",
    "non-default" (NON_DEFAULT), "monolithic" (friction.law = neural, as in
    StickSlipMonolithic.ssp), or a coupling scheme."""
    if key not in _references:
        if key in (JACOBI, GAUSS_SEIDEL):
            _references[key] = other_masters.reference_coupled(fmus, key)
        else:
            parameters = {
                "defaults": {},
                "non-default": NON_DEFAULT,
                "monolithic": {"friction.law": "neural"},
            }[key]
            _references[key] = other_masters.reference_beam(fmus, parameters)
    return _references[key]


def state_law_reference(fmus, system: str, scheme: str, clock: str = "float") -> dict:
    """Our master's tip deflection and law state (STATE_OF) on the coupled system
    `system`, cached per module run."""
    key = (system, scheme, clock)
    if key not in _references:
        outputs = (TIP, STATE_OF[system])
        _references[key] = other_masters.reference_outputs(
            fmus, scheme, outputs, system=system, clock=clock
        )
    return _references[key]


def first_drop(tip: np.ndarray, level: float) -> float:
    """The first time (s) `tip` (on the grid k H) falls through `level` (m), linearly
    interpolated."""
    k = np.nonzero((tip[:-1] >= level) & (tip[1:] < level))[0][0]
    return float((k + (tip[k] - level) / (tip[k] - tip[k + 1])) * H)


def codes(fmus, values: dict) -> dict:
    """`values` with choices as their integer codes (as masters other than ours take them)."""
    model = fmus.models[BEAM]
    return {
        name: model.code(name, value) if name in model.choices else value
        for name, value in values.items()
    }


def assert_bit_identical(series: other_masters.Series, name, expected: np.ndarray, what: str):
    got = series.at_grid(name, N)
    recorded = ~np.isnan(got)
    # Every master records the whole grid, fmpy's SSP runner all but t = 0.
    assert recorded[1:].all(), f"{what}: points missing"
    same = got[recorded] == expected[recorded]
    assert same.all(), (
        f"{what}: differs from our master from t = {np.argmin(same) * H:.3f} s on, by up to "
        f"{other_masters.deviation(got, expected):.3g} (SI units)"
    )


def single_beam_csv(start: dict) -> str:
    """fmucontainer's link list for StickSlipBeam alone: its inputs and tip deflection
    exposed, and `start` as START rules (choices as codes)."""
    lines = ["rule;from_fmu;from_port;to_fmu;to_port", "FMU;StickSlipBeam.fmu;;;"]
    for line in other_masters.csv_path(MONOLITHIC).read_text().splitlines():
        if line.startswith("INPUT;"):
            lines.append(line)
    lines.append("OUTPUT;StickSlipBeam.fmu;tip_deflection;;beam.tip_deflection")
    lines += [f"START;StickSlipBeam.fmu;{name};{value};" for name, value in start.items()]
    return "\n".join(lines) + "\n"


def container_run(csv_text: str, tmp_path: Path, name: str, *, sequential=False):
    container, _ = other_masters.build_container(csv_text, tmp_path / name, name, sequential=sequential)
    return other_masters.run_fmpy_fmu(container, ("beam.tip_deflection",))


# ----------------------------------------------------------------------------- loads


def test_the_system_files_are_valid_ssp(built):
    """fmpy reads both SSD files against the SSP 1.0 schema (read_ssd validates), with
    the components and connections fmu-build wrote."""
    need(built)
    coupled = read_ssd(str(other_masters.ssp_path(COUPLED)))
    assert [c.name for c in coupled.system.elements] == ["beam", "friction"]
    links = {
        (c.startElement, c.startConnector, c.endElement, c.endConnector)
        for c in coupled.system.connections
    }
    # The step coupling's links (the signed coupling's and the step-consistent
    # tangent), wired in every coupled system: the ones our master runs it with.
    element = {BEAM: "beam", FRICTION: "friction"}
    assert links == {
        (element[link.source], link.output, element[link.target], link.input)
        for link in COUPLINGS["step"]
    }
    assert ("friction", "friction_force_slope", "beam", "external.friction_slope") in links
    monolithic = read_ssd(str(other_masters.ssp_path(MONOLITHIC)))
    assert [c.name for c in monolithic.system.elements] == ["beam"]


def test_libcosim_loads_every_variable_of_both_fmus(built):
    """libcosim dropped every FMI Enumeration ("Enumeration variable type not
    supported"); with Integer choices it sees every variable of both FMUs."""
    fmus = need(built)
    from libcosimpy.CosimEnums import CosimVariableType

    seen = other_masters.libcosim_variables(other_masters.ssp_path(COUPLED))
    for fmu, instance in other_masters.INSTANCES.items():
        model = fmus.models[fmu]
        assert set(seen[instance]) == set(model.variables), instance
        for name in model.choices:
            assert seen[instance][name] == CosimVariableType.INTEGER.value, name


def test_ecos_reads_every_choice_as_an_integer(built):
    """Ecos reported "No variable named 'fidelity.level' of type int" for Enumerations;
    now every choice reads as an Integer with the value the SSD's parameter set gives."""
    fmus = need(built)
    names = {other_masters.INSTANCES[f]: list(fmus.models[f].choices) for f in (BEAM, FRICTION)}
    values = other_masters.ecos_integers(other_masters.ssp_path(COUPLED), names)
    beam = fmus.models[BEAM]
    assert values["beam", "friction.law"] == beam.code("friction.law", "external")
    assert values["beam", "fidelity.level"] == int(beam.variables["fidelity.level"].start)
    assert values["friction", "law"] == fmus.models[FRICTION].code("law", "neural")
    assert len(values) == sum(len(v) for v in names.values())


def test_fmucontainer_builds_a_valid_container_of_the_coupled_system(built, tmp_path):
    need(built)
    container, log = other_masters.build_container(
        other_masters.csv_path(COUPLED).read_text(), tmp_path, COUPLED, sequential=False
    )
    assert "ERROR" not in log, log
    assert validate_fmu(str(container)) == []


# ----------------------------------------------------------------------------- defaults


def test_defaults_equal_our_master_in_every_master(built, tmp_path):
    """StickSlipBeam with no parameter given: libcosim and Ecos on the bare FMU, a
    container of it, and fmpy's SSP runner (which applies no parameter of the SSD unless
    passed them) all equal our master bit for bit."""
    fmus = need(built)
    expected = reference(fmus, "defaults")
    beam = fmu_paths()[BEAM]
    assert_bit_identical(other_masters.run_libcosim(fmu=beam), TIP, expected, "libcosim")
    assert_bit_identical(other_masters.run_ecos(fmu=beam), TIP, expected, "Ecos")
    container = container_run(single_beam_csv({}), tmp_path, "defaults")
    assert_bit_identical(container, ("", "beam.tip_deflection"), expected, "fmucontainer")
    fmpy_ssp = other_masters.run_fmpy_ssp(other_masters.ssp_path(MONOLITHIC))
    assert_bit_identical(fmpy_ssp, TIP, expected, "fmpy.ssp")


# ----------------------------------------------------------------------------- parameters


def test_non_default_choices_set_in_every_master_act_as_in_fmpy(built, tmp_path):
    """fidelity.level = modal and friction.law = coulomb, set through each master's own
    way of setting parameters, give fmpy's run with the same settings bit for bit, and
    not the defaults."""
    fmus = need(built)
    expected = reference(fmus, "non-default")
    defaults = reference(fmus, "defaults")
    assert other_masters.deviation(expected, defaults) > 1e-4, "the settings change nothing"
    beam = fmu_paths()[BEAM]
    settings = codes(fmus, NON_DEFAULT)
    runs = {
        "libcosim": other_masters.run_libcosim(fmu=beam, parameters={"beam": settings}),
        "Ecos": other_masters.run_ecos(fmu=beam, parameters={"beam": settings}),
        "fmpy.ssp": other_masters.run_fmpy_ssp(
            other_masters.ssp_path(MONOLITHIC),
            parameters=other_masters.ssd_parameter_set(other_masters.ssp_path(MONOLITHIC), {"beam": settings}),
        ),
    }
    for label, series in runs.items():
        assert_bit_identical(series, TIP, expected, label)
    container = container_run(single_beam_csv(settings), tmp_path, "nondefault")
    assert_bit_identical(container, ("", "beam.tip_deflection"), expected, "fmucontainer")


def test_the_monolithic_system_runs_its_parameter_set_in_every_master(built, tmp_path):
    """StickSlipMonolithic.ssp sets friction.law = neural (and every other parameter to
    its default) in its parameter set: libcosim and Ecos apply it from the SSD, fmpy's
    runner when given the SSD's values, fmucontainer from the START rules of the link
    list. All equal fmpy with friction.law = neural, which is not the default."""
    fmus = need(built)
    expected = reference(fmus, "monolithic")
    assert other_masters.deviation(expected, reference(fmus, "defaults")) > 1e-4
    ssp = other_masters.ssp_path(MONOLITHIC)
    assert_bit_identical(other_masters.run_libcosim(ssp=ssp), TIP, expected, "libcosim")
    assert_bit_identical(other_masters.run_ecos(ssp=ssp), TIP, expected, "Ecos")
    fmpy_ssp = other_masters.run_fmpy_ssp(ssp, parameters=other_masters.ssd_parameter_set(ssp))
    assert_bit_identical(fmpy_ssp, TIP, expected, "fmpy.ssp")
    container = container_run(other_masters.csv_path(MONOLITHIC).read_text(), tmp_path, MONOLITHIC)
    assert_bit_identical(container, ("", "beam.tip_deflection"), expected, "fmucontainer")


def test_ecos_applies_no_parameter_set_unless_it_is_named(built):
    """What an Ecos user must know: without init(parameter_set="initialValues") Ecos
    silently runs the FMU's defaults, not the SSD's values."""
    fmus = need(built)
    unnamed = other_masters.run_ecos(ssp=other_masters.ssp_path(MONOLITHIC), parameter_set=None)
    assert_bit_identical(unnamed, TIP, reference(fmus, "defaults"), "Ecos without a set")


# ----------------------------------------------------------------------------- coupled system


def test_the_coupled_system_equals_our_masters_scheme_for_scheme(built, tmp_path):
    """libcosim's fixed-step algorithm, Ecos and a parallel container step every FMU from
    the outputs of the last communication point: our Jacobi master, bit for bit. A
    -sequential container steps the beam, then the friction law with the beam's new
    outputs: our Gauss-Seidel master (beam first), bit for bit."""
    fmus = need(built)
    jacobi, gauss_seidel = reference(fmus, JACOBI), reference(fmus, GAUSS_SEIDEL)
    # The schemes part after breakaway, so matching one is not matching both.
    assert other_masters.deviation(jacobi, gauss_seidel) > 1e-5
    ssp = other_masters.ssp_path(COUPLED)
    assert_bit_identical(other_masters.run_libcosim(ssp=ssp), TIP, jacobi, "libcosim")
    assert_bit_identical(other_masters.run_ecos(ssp=ssp), TIP, jacobi, "Ecos")
    csv = other_masters.csv_path(COUPLED).read_text()
    parallel = container_run(csv, tmp_path, "parallel")
    assert_bit_identical(parallel, ("", "beam.tip_deflection"), jacobi, "fmucontainer")
    sequential = container_run(csv, tmp_path, "sequential", sequential=True)
    assert_bit_identical(sequential, ("", "beam.tip_deflection"), gauss_seidel, "-sequential")


def test_the_coupled_system_with_a_law_with_state_equals_our_masters(built, tmp_path):
    """StickSlipCoupledMemory.ssp: NeuralFriction runs the learned law with memory
    (weights = rate-and-state-learned.json, set in the SSD's parameter set), whose state
    it integrates over each communication step of the size the master gives. Ecos and a
    parallel container give our Jacobi master, a sequential container our Gauss-Seidel
    master, bit for bit; libcosim gives our Jacobi master bit for bit when that counts
    time as libcosim does (integer nanoseconds: steps of h to rounding), and not when it
    steps by h exactly (the law's state sees the last bits of the step size; measured
    1e-6 m apart by t = 0.7 s). The run is not the plain network's: the parameter set
    reached NeuralFriction."""
    fmus = need(built)
    jacobi, gauss_seidel = (
        other_masters.reference_coupled(fmus, scheme, system=COUPLED_MEMORY)
        for scheme in (JACOBI, GAUSS_SEIDEL)
    )
    jacobi_ns = other_masters.reference_coupled(
        fmus, JACOBI, system=COUPLED_MEMORY, clock="nanoseconds"
    )
    assert other_masters.deviation(jacobi, jacobi_ns) > 0, "the clock changes nothing"
    # The learned law's corridor (6.3 to 9.1 mm) is not the plain network's: measured
    # 2.4 mm apart over the run.
    assert other_masters.deviation(jacobi, reference(fmus, JACOBI)) > 1e-3
    assert other_masters.deviation(jacobi, gauss_seidel) > 1e-6
    ssp = other_masters.ssp_path(COUPLED_MEMORY)
    assert_bit_identical(other_masters.run_libcosim(ssp=ssp), TIP, jacobi_ns, "libcosim")
    assert_bit_identical(other_masters.run_ecos(ssp=ssp), TIP, jacobi, "Ecos")
    csv = other_masters.csv_path(COUPLED_MEMORY).read_text()
    parallel = container_run(csv, tmp_path, "memory-parallel")
    assert_bit_identical(parallel, ("", "beam.tip_deflection"), jacobi, "fmucontainer")
    sequential = container_run(csv, tmp_path, "memory-sequential", sequential=True)
    assert_bit_identical(sequential, ("", "beam.tip_deflection"), gauss_seidel, "-sequential")


@pytest.mark.parametrize("system", [COUPLED_RATE_STATE, COUPLED_LUGRE])
def test_the_coupled_system_with_each_state_law_equals_our_masters(built, tmp_path, system):
    """StickSlipCoupledRateState.ssp and StickSlipCoupledLuGre.ssp: NeuralFriction runs
    law = rate-and-state or law = lugre (set in the SSD's parameter set), integrating
    the law's state over each communication step. The tip deflection and the law's
    state output (state_theta, bristle_deflection) equal our masters bit for bit:
    libcosim our Jacobi master counting time in nanoseconds as it does, Ecos and a
    parallel container our Jacobi master, a sequential container our Gauss-Seidel
    master. The run is not the plain network's (the parameter set reached
    NeuralFriction) and the state moves (so comparing it is not comparing constants).
    fmpy's SSP runner runs the law too, equal to neither scheme (its first step)."""
    fmus = need(built)
    state = STATE_OF[system]
    outputs = (TIP, state)
    jacobi, gauss_seidel, jacobi_ns = (
        state_law_reference(fmus, system, scheme, clock)
        for scheme, clock in ((JACOBI, "float"), (GAUSS_SEIDEL, "float"), (JACOBI, "nanoseconds"))
    )
    # Measured over 0.7 s: 2.4 mm (rate-and-state) and 1.2 mm (LuGre) from the plain
    # network's run; 1e-4 m is far above any rounding and far below either.
    assert other_masters.deviation(jacobi[TIP], reference(fmus, JACOBI)) > 1e-4
    assert np.ptp(jacobi[state]) > 0, f"{state[1]} never moves"
    # libcosim's clock moves the bits (measured 9.5e-6 m and 2.3e-5 m of tip by 0.7 s):
    # matching the nanosecond run is not matching the float one.
    assert other_masters.deviation(jacobi[TIP], jacobi_ns[TIP]) > 0, "the clock changes nothing"
    assert other_masters.deviation(jacobi[TIP], gauss_seidel[TIP]) > 0
    ssp = other_masters.ssp_path(system)
    runs = {
        "libcosim": (other_masters.run_libcosim(ssp=ssp, record=outputs), jacobi_ns),
        "Ecos": (other_masters.run_ecos(ssp=ssp, record=outputs), jacobi),
    }
    csv = other_masters.csv_path(system).read_text()
    containers = (("parallel", False, jacobi), ("sequential", True, gauss_seidel))
    for label, sequential, expected in containers:
        # The label names the container too: no leading "-" (fmucontainer's arguments).
        container, _ = other_masters.build_container(csv, tmp_path / label, label, sequential=sequential)
        runs[label] = (other_masters.run_container(container, outputs), expected)
    for label, (series, expected) in runs.items():
        for output in outputs:
            assert_bit_identical(series, output, expected[output], f"{system} {label} {output[1]}")
    # fmpy's SSP runner goes as far as its first step allows (note 5 of
    # docs/cosimulation.md: every connected input starts at 0, so it equals neither
    # scheme): it sets `law` from the SSD's values (an Integer, which it can set), so
    # the law's state moves in its run, and nothing turns NaN.
    fmpy_ssp = other_masters.run_fmpy_ssp(ssp, parameters=other_masters.ssd_parameter_set(ssp), record=outputs)
    theirs = fmpy_ssp.at_grid(state, N)[1:]
    assert np.isfinite(theirs).all() and np.ptp(theirs) > 0, f"fmpy.ssp: {state[1]} never moves"


def test_the_coupled_rate_and_state_system_follows_the_embedded_law(built):
    """The physics of StickSlipCoupledRateState at its step h = 1e-3 s: the tip leaves
    stick where StickSlipBeam with friction.law = rate-and-state embedded does.
    Measured to 1.2 s (docs/cosimulation.md, "Step-consistent coupling"), first drop
    through the embedded run's mid-corridor 0.70 ms early in Gauss-Seidel and 1.28 ms late
    in Jacobi with the step coupling (0.44 ms late and 2.6 ms late with the signed one),
    the coupling's error; asserted here within twice those over the masters' 0.7 s.
    (The periods need 1.2 s: tests/fmu/friction_laws_coupled.rs.)"""
    fmus = need(built)
    embedded = other_masters.reference_beam(fmus, {"friction.law": "rate-and-state"})
    # The embedded run's corridor over 0.35 to 0.7 s: stick at the top, first slip.
    late = embedded[len(embedded) // 2 :]
    level = 0.5 * (late.min() + late.max())
    t_embedded = first_drop(embedded, level)
    tolerance = {GAUSS_SEIDEL: 2 * 0.70e-3, JACOBI: 2 * 1.28e-3}
    for scheme, allowed in tolerance.items():
        tip = state_law_reference(fmus, COUPLED_RATE_STATE, scheme)[TIP]
        t = first_drop(tip, level)
        assert abs(t - t_embedded) < allowed, f"{scheme}: first drop {t} s, embedded {t_embedded} s"


def test_fmpy_ssp_starts_the_connected_inputs_at_zero(built):
    """fmpy's SSP runner steps every FMU, then copies outputs to inputs: Jacobi, but
    without an exchange before the first step. Every connector starts at 0, so over the
    first step the beam's static limit is 0 N: it slips at once (one transition), where
    our masters keep it stuck until breakaway at 0.4 s. Its coupled run therefore leaves
    ours from the first step on (docs/cosimulation.md, note 5)."""
    fmus = need(built)
    ssp = other_masters.ssp_path(COUPLED)
    transitions = ("beam", "transitions")
    series = other_masters.run_fmpy_ssp(
        ssp, parameters=other_masters.ssd_parameter_set(ssp), record=(TIP, transitions), t_end=0.01
    )
    assert series.at_grid(transitions, 10)[1] == 1
    jacobi = reference(fmus, JACOBI)
    assert series.at_grid(TIP, 10)[1] != jacobi[1]
    # Ours: no transition before breakaway.
    ours = run_coupled(
        fmus,
        H,
        0.01,
        beam={},
        friction={},
        record={BEAM: ["transitions"]},
        scheme=JACOBI,
        coupling="signed",
    )
    assert (ours[BEAM, "transitions"] == 0).all()


# ----------------------------------------------------------------------------- FMU errors


def run_script(code: str, tmp: Path | None = None) -> subprocess.CompletedProcess:
    """`code` in a fresh Python process (libcosim aborts the whole process on an FMU
    error), with stdout and stderr together; `tmp` as its TMPDIR (an aborted libcosim
    leaves its unpacked FMUs there)."""
    env = dict(os.environ)
    if tmp is not None:
        env["TMPDIR"] = str(tmp)
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        timeout=120,
        check=False,
        env=env,
    )


REASON = "invalid scene: material.youngs_modulus = -1e0; it must be finite and > 0 (Pa)"


def test_libcosim_shows_the_reason_then_aborts_the_process(built, tmp_path):
    """libcosim logs the FMU's reason at error level, then ends the whole process with
    SIGABRT from an uncaught C++ exception: no Python exception, nothing after it runs,
    and its unpacked FMU is left in the temporary folder."""
    need(built)
    done = run_script(
        f"""
        from stickslip_checks import other_masters
        other_masters.run_libcosim(fmu={str(fmu_paths()[BEAM])!r},
                             parameters={{"beam": {{"material.youngs_modulus": -1.0}}}})
        print("still running")
        """,
        tmp_path,
    )
    assert done.returncode == -6, done.stdout  # SIGABRT
    assert list(tmp_path.glob("libcosim_*")), "libcosim cleaned up after all"
    logged = f"[error]   [FMI status=error, category=logStatusError] fmi2GetReal: {REASON}"
    assert logged in done.stdout
    assert f"what():  Model error: fmi2GetReal: {REASON}" in done.stdout
    assert "still running" not in done.stdout


def test_ecos_hides_the_error_unless_its_log_level_is_debug(built):
    """Ecos logs an FMU's fmi2Error at debug level only; init() returns True and the
    steps go on, reading 0 from the failed FMU. At log level "debug" the reason shows."""
    need(built)
    script = """
        import numpy as np
        from stickslip_checks import other_masters
        bad = {{"beam": {{"material.youngs_modulus": -1.0}}}}
        series = other_masters.run_ecos(fmu={fmu!r}, parameters=bad, t_end=0.01, log_level={level!r})
        print("outputs", np.unique(series.values[("beam", "tip_deflection")]))
        """
    fmu = str(fmu_paths()[BEAM])
    quiet = run_script(script.format(fmu=fmu, level="warn"))
    assert quiet.returncode == 0, quiet.stdout
    assert "youngs_modulus" not in quiet.stdout
    assert "outputs [0.]" in quiet.stdout
    debug = run_script(script.format(fmu=fmu, level="debug"))
    assert debug.returncode == 0, debug.stdout
    assert f"fmi2Error fmi2ExitInitializationMode: {REASON}" in debug.stdout


def test_fmucontainer_passes_the_error_and_the_reason_on(built, tmp_path):
    """The container returns the embedded FMU's fmi2Error from
    fmi2ExitInitializationMode and logs its reason with the FMU's name; fmpy shows both."""
    need(built)
    container, _ = other_masters.build_container(
        single_beam_csv({"material.youngs_modulus": -1.0}), tmp_path, "error", sequential=False
    )
    done = run_script(
        f"""
        from stickslip_checks import other_masters
        try:
            other_masters.run_fmpy_fmu({str(container)!r}, ("beam.tip_deflection",), t_end=0.01)
        except Exception as error:
            print("raised", type(error).__name__, error)
        """
    )
    assert f"[ERROR] StickSlipBeam.fmu: fmi2ExitInitializationMode: {REASON}" in done.stdout
    assert "raised FMICallException fmi2ExitInitializationMode failed with status 3" in done.stdout


def test_fmpy_ssp_shows_the_reason_and_raises(built):
    need(built)
    ssp = str(other_masters.ssp_path(MONOLITHIC))
    done = run_script(
        f"""
        from stickslip_checks import other_masters
        p = other_masters.ssd_parameter_set({ssp!r}, {{"beam": {{"material.youngs_modulus": -1.0}}}})
        try:
            other_masters.run_fmpy_ssp({ssp!r}, parameters=p, t_end=0.01)
        except Exception as error:
            print("raised", type(error).__name__, error)
        """
    )
    assert f"fmi2ExitInitializationMode: {REASON}" in done.stdout, done.stdout
    assert "raised FMICallException fmi2ExitInitializationMode failed with status 3" in done.stdout
