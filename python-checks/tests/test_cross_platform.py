"""The FMUs' Windows and aarch64 Linux binaries, and the x86_64 one on a CPU without AVX2
and FMA, give the x86_64 Linux outputs bit for bit (stickslip_checks.cross_platform):
every output at every communication step of the paper scene's breakaway and first slip,
each fidelity, both laws, FMI 2.0 and 3.0, and NeuralFriction over an input grid.

Bit for bit, not within a tolerance: the FMUs promise reproducible results, and the
physics and the network use one implementation of every transcendental and one
operation order on every platform and CPU; a last-bit difference on one step is a
broken promise, whatever it grows to later.

The table is written to <target>/cross-platform.md and printed (pytest -s). Needs the
FMUs built by fmu-build with all platforms (not STICKSLIP_HOST_ONLY) and the packages of
scripts/cross-deps.sh (Wine, qemu, the cross compilers); without them the tests FAIL.
"""

from __future__ import annotations

import zipfile

import pytest

from stickslip_checks import cross_platform
from stickslip_checks.artifacts import BEAM, FRICTION, Model, fidelities, fmu3_paths, fmu_paths


@pytest.fixture(scope="module")
def run():
    try:
        fmu_paths(), fmu3_paths()
    except FileNotFoundError as error:
        pytest.fail(str(error), pytrace=False)
    result = cross_platform.run_all()
    path = cross_platform.write_table(result)
    print("\n" + cross_platform.table(result) + f"(written to {path})")
    return result


def test_every_case_ran_on_every_platform(run):
    beam, friction = (Model.read(fmu_paths()[name]) for name in (BEAM, FRICTION))
    expected = len(cross_platform.cases(beam, friction))
    # 3 fidelities x 5 laws of the beam + 2 laws of NeuralFriction.
    assert expected == len(cross_platform.BEAM_LAWS) * len(fidelities(beam)) + 2
    assert len(cross_platform.BEAM_LAWS) == 5
    for platform in cross_platform.FOREIGN:
        for version in ("2.0", "3.0"):
            ran = [r for r in run.results if r.platform == platform.name and r.version == version]
            assert len(ran) == expected, (platform.name, version)


def test_foreign_binaries_give_the_x86_64_linux_bits(run):
    differing = [
        f"{r.platform}, FMI {r.version}, {r.case.model} {r.case.setting}: {r.detail}"
        for r in run.results
        if not r.identical
    ]
    assert not differing, "\n".join(differing)


def test_the_runs_cover_stick_and_slip(run):
    """The compared horizon holds the breakaway: the beam's transitions output (its one
    Integer output) is nonzero at the end of every run, else the comparison never saw
    slip; and every run has all its steps."""
    beam_runs = [r for r in run.results if r.case.model == BEAM and r.lines]
    assert beam_runs
    for r in beam_runs:
        assert r.lines == round(cross_platform.STOP / cross_platform.STEP), r
        # The driver prints the outputs in the plan's order, the last ones last.
        outputs = [line.split() for line in r.case.plan.splitlines() if line.startswith("output ")]
        (counter,) = [k for k, line in enumerate(outputs) if line[1] == "int"]
        assert int(r.last_line.split()[counter - len(outputs)]) > 0, r


@pytest.mark.parametrize("version", ["2.0", "3.0"])
def test_fmus_carry_every_platform(version):
    paths = fmu_paths() if version == "2.0" else fmu3_paths()
    for name, path in paths.items():
        names = set(zipfile.ZipFile(path).namelist())
        for platform in (cross_platform.NATIVE, cross_platform.WINDOWS, cross_platform.AARCH64):
            binary = platform.binary(cross_platform.Path(""), version, name).as_posix()
            assert binary in names, (path, sorted(names))


def test_ssp_files_embed_the_multi_platform_fmus():
    """The SSP systems embed the FMI 2.0 FMUs as they are: each embedded FMU holds the
    three binaries."""
    import io

    ssps = sorted(fmu_paths()[BEAM].parent.glob("*.ssp"))
    assert ssps, "no SSP file next to the FMI 2.0 FMUs"
    for ssp in ssps:
        with zipfile.ZipFile(ssp) as archive:
            embedded = [n for n in archive.namelist() if n.endswith(".fmu")]
            assert embedded, ssp
            for name in embedded:
                inner = zipfile.ZipFile(io.BytesIO(archive.read(name))).namelist()
                model = name.rsplit("/", 1)[-1].removesuffix(".fmu")
                for platform in (cross_platform.NATIVE, cross_platform.WINDOWS, cross_platform.AARCH64):
                    binary = platform.binary(cross_platform.Path(""), "2.0", model).as_posix()
                    assert binary in inner, (ssp.name, name, inner)
