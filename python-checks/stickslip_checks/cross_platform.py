"""The FMUs' foreign binaries run here: the Windows DLL under Wine, the aarch64 Linux
binary under qemu, and the x86_64 Linux binary on a CPU without AVX2 and FMA (qemu's
Nehalem model), each driven by the small C importer `fmu-build/cross-driver/fmi_driver.c`
cross-compiled for its platform, and compared bit for bit with the x86_64 Linux binary
run natively by the same driver (docs/cross-platform.md).

Cases (stickslip_checks.cross_cases): platform x FMI version x (StickSlipBeam at each
structural fidelity with each law over the paper scene's breakaway and first slip;
NeuralFriction with either memoryless law over a grid of inputs, and with each law with
state over a stepped velocity history). The driver prints every output after every
communication step as the hex bits of its value, so "identical" means every bit of every
output at every step.

`python -m stickslip_checks.cross_platform` prints the table and writes it to
<target>/cross-platform.md; python-checks/tests/test_cross_platform.py fails on every
case that differs.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
import zipfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

from .artifacts import BEAM, FRICTION, REPO, Model, fmu3_paths, fmu_paths, fmu_root
from .cross_cases import Case, cases, write_slip_weights

DRIVER_SOURCES = REPO / "fmu-build" / "cross-driver"
SYSROOT_AARCH64 = "/usr/aarch64-linux-gnu"


@dataclass(frozen=True)
class Platform:
    """A platform the test runs a packaged binary on: its folders in the FMUs, and how its
    driver is compiled and started."""

    name: str
    fmi2_folder: str
    fmi3_folder: str
    extension: str
    compiler: str

    def binary(self, unzipped: Path, version: str, identifier: str) -> Path:
        folder = self.fmi2_folder if version == "2.0" else self.fmi3_folder
        return unzipped / "binaries" / folder / f"{identifier}.{self.extension}"


NATIVE = Platform("x86_64-linux", "linux64", "x86_64-linux", "so", "gcc")
WINDOWS = Platform(
    "x86_64-windows (Wine)", "win64", "x86_64-windows", "dll", "x86_64-w64-mingw32-gcc"
)
AARCH64 = Platform(
    "aarch64-linux (qemu)", "aarch64-linux", "aarch64-linux", "so", "aarch64-linux-gnu-gcc"
)
# The same x86_64 binary on an emulated CPU without AVX2 and FMA (glibc and the network's
# kernel dispatch on those at run time).
NO_FMA = Platform(
    "x86_64-linux, no AVX2/FMA (qemu Nehalem)", "linux64", "x86_64-linux", "so", "gcc"
)
FOREIGN = (WINDOWS, AARCH64, NO_FMA)


def work_dir() -> Path:
    """Where the drivers, the Wine prefix and the table go: <target>/cross-driver."""
    return fmu_root().parent / "cross-driver"


def build_drivers(out: Path) -> dict[str, list[str]]:
    """Compiles the driver for each platform (and the Wine shim); returns the command
    prefix that runs each platform's driver."""
    out.mkdir(parents=True, exist_ok=True)
    source = str(DRIVER_SOURCES / "fmi_driver.c")
    # -ffp-contract=off: the driver's one sum (t += h) rounds alike everywhere.
    flags = ["-O2", "-ffp-contract=off", "-Wall", "-Wextra", "-Werror"]
    native = out / "fmi_driver"
    subprocess.run(["gcc", *flags, "-o", str(native), source, "-ldl"], check=True)
    arm = out / "fmi_driver-aarch64"
    subprocess.run([AARCH64.compiler, *flags, "-o", str(arm), source, "-ldl"], check=True)
    exe = out / "windows" / "fmi_driver.exe"
    exe.parent.mkdir(exist_ok=True)
    subprocess.run([WINDOWS.compiler, *flags, "-o", str(exe), source], check=True)
    # Wine 8.0 lacks bcryptprimitives.dll (Rust's std imports ProcessPrng from it); the
    # test's own stand-in goes next to the driver, where Windows looks for DLLs first.
    shim = exe.parent / "bcryptprimitives.dll"
    shim_source = str(DRIVER_SOURCES / "process_prng.c")
    subprocess.run(
        [WINDOWS.compiler, "-O2", "-Wall", "-shared", "-o", str(shim), shim_source, "-ladvapi32"],
        check=True,
    )
    return {
        NATIVE.name: [str(native)],
        WINDOWS.name: ["/usr/lib/wine/wine64", str(exe)],
        AARCH64.name: ["qemu-aarch64-static", "-L", SYSROOT_AARCH64, str(arm)],
        NO_FMA.name: ["qemu-x86_64-static", "-cpu", "Nehalem", str(native)],
    }


def environment(out: Path) -> dict[str, str]:
    """A Wine prefix under <target>, made before the first run, no Wine debug output."""
    env = dict(os.environ)
    env["WINEPREFIX"] = str(out / "wineprefix")
    env["WINEDEBUG"] = "-all"
    prepare_wine_prefix(env)
    return env


def prepare_wine_prefix(env: dict[str, str]) -> None:
    """Creates the Wine prefix and waits until its server has finished. The first run in
    a new prefix otherwise creates it on the way and, on a fresh machine, failed once in
    two tries ("chdir to /tmp/wine-.../server-...: No such file or directory")."""
    if Path(env["WINEPREFIX"], "system.reg").exists():
        return
    subprocess.run(["/usr/lib/wine/wine64", "wineboot", "--init"], env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=600)
    subprocess.run(["/usr/lib/wine/wineserver", "--wait"], env=env, check=True, timeout=600)


@dataclass
class Result:
    platform: str
    version: str
    case: Case
    identical: bool
    detail: str
    seconds: float = 0.0
    lines: int = 0
    first_line: str = ""
    last_line: str = ""


@dataclass
class Run:
    results: list[Result] = field(default_factory=list)
    native_seconds: float = 0.0
    foreign_seconds: dict[str, float] = field(default_factory=dict)


def _run(command: list[str], args: list[str], plan: str, env: dict[str, str]) -> tuple[str, float]:
    start = time.perf_counter()
    done = subprocess.run([*command, *args], input=plan, capture_output=True, text=True, env=env,
                          timeout=600)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} exited {done.returncode}: {done.stderr[-2000:]}")
    return done.stdout, seconds


def _windows_path(path: Path) -> str:
    """Wine maps the Unix root to drive Z:."""
    return "Z:" + str(path.resolve())


def _compare(native: str, foreign: str) -> tuple[bool, str]:
    a, b = native.splitlines(), foreign.splitlines()
    if a == b:
        return True, f"{len(a)} steps"
    differing = [k for k, (x, y) in enumerate(zip(a, b)) if x != y]
    first = differing[0] if differing else min(len(a), len(b))
    return False, (f"{len(differing)} of {len(a)} steps differ (lengths {len(a)}/{len(b)}), "
                   f"first at step {first + 1}")


def run_all(platforms=FOREIGN, out: Path | None = None) -> Run:
    """Runs every case natively and on each platform; compares the outputs."""
    out = out or work_dir()
    commands = build_drivers(out)
    env = environment(out)
    unzip_root = Path(tempfile.mkdtemp(prefix="stickslip-cross-"))
    run = Run()
    try:
        paths = {"2.0": fmu_paths(), "3.0": fmu3_paths()}
        beam, friction = Model.read(paths["2.0"][BEAM]), Model.read(paths["2.0"][FRICTION])
        jobs = []
        for version, fmus in paths.items():
            for name, archive in fmus.items():
                folder = unzip_root / version / name
                zipfile.ZipFile(archive).extractall(folder)
                if name == FRICTION:
                    write_slip_weights(folder / "resources")
                token = Model.read(archive).guid
                for case in (c for c in cases(beam, friction) if c.model == name):
                    jobs.append((version, folder, token, case))

        def native(job):
            version, folder, token, case = job
            binary = NATIVE.binary(folder, version, case.model)
            args = [version[0], str(binary), str(folder / "resources"), token]
            return _run(commands[NATIVE.name], args, case.plan, env)

        def foreign(item):
            platform, (version, folder, token, case), reference = item
            binary = platform.binary(folder, version, case.model)
            resources = folder / "resources"
            if platform is WINDOWS:
                binary_arg, resources_arg = _windows_path(binary), _windows_path(resources)
            else:
                binary_arg, resources_arg = str(binary), str(resources)
            if not binary.is_file():
                missing = f"{binary.relative_to(folder)} is not in the FMU"
                return Result(platform.name, version, case, False, missing)
            args = [version[0], binary_arg, resources_arg, token]
            try:
                output, seconds = _run(commands[platform.name], args, case.plan, env)
            except (RuntimeError, subprocess.TimeoutExpired) as error:
                return Result(platform.name, version, case, False, f"run failed: {error}")
            same, detail = _compare(reference, output)
            rows = output.splitlines()
            return Result(platform.name, version, case, same, detail, seconds, len(rows),
                          rows[0] if rows else "", rows[-1] if rows else "")

        with ThreadPoolExecutor(max_workers=2) as pool:
            natives = list(pool.map(native, jobs))
            run.native_seconds = sum(s for _, s in natives)
            items = [(p, job, ref) for p in platforms for job, (ref, _) in zip(jobs, natives)]
            run.results = list(pool.map(foreign, items))
        for platform in platforms:
            run.foreign_seconds[platform.name] = sum(
                r.seconds for r in run.results if r.platform == platform.name
            )
    finally:
        shutil.rmtree(unzip_root, ignore_errors=True)
    return run


def table(run: Run) -> str:
    """The markdown table: platform x FMI version x model and setting -> identical."""
    lines = [
        "| platform | FMI | model | setting | identical to x86_64 Linux | detail | run time (s) |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in run.results:
        lines.append(f"| {r.platform} | {r.version} | {r.case.model} | {r.case.setting} | "
                     f"{'yes' if r.identical else 'NO'} | {r.detail} | {r.seconds:.1f} |")
    lines.append("")
    lines.append(f"Native x86_64 runs (the reference): {run.native_seconds:.1f} s in all; "
                 + ", ".join(f"{name}: {s:.1f} s" for name, s in run.foreign_seconds.items()) + ".")
    return "\n".join(lines) + "\n"


def write_table(run: Run, out: Path | None = None) -> Path:
    path = (out or work_dir()).parent / "cross-platform.md"
    path.write_text("# Foreign binaries against x86_64 Linux, bit for bit\n\n" + table(run))
    return path


def main() -> int:
    run = run_all()
    print(table(run))
    print(f"written to {write_table(run)}")
    return 0 if all(r.identical for r in run.results) else 1


if __name__ == "__main__":
    sys.exit(main())
