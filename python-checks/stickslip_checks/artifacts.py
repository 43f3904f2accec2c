"""The built artifacts and what their model descriptions say: the one place that knows
where the FMUs and the `stickslip` binary are, and how a variable's name, type and
choices map to FMI value references and integer codes.

- FMUs: under $STICKSLIP_FMU_DIR, else $CARGO_TARGET_DIR/fmu (relative to the
  repository root, as fmu-build resolves it), else <repo>/target/fmu, where
  `cargo run --release -p fmu-build` writes them: the FMI 2.0 FMUs, the SSP systems and
  fmucontainer's link lists in its `2.0/` folder, the FMI 3.0 FMUs in `3.0/`. Nothing is
  read from the top of that folder, where an older fmu-build wrote the FMI 2.0 files.
- Binary: $STICKSLIP_BIN, else the release binary, built (if needed) by cargo.
- Value references, types, start values and the choices of every variable are read from
  each FMU's modelDescription.xml; nothing here is hard-coded. A choice variable is an
  FMI Integer set to the code of one of its words; the codes and words are listed in the
  `stickslip` tool's vendor annotation, and `choices` is the only function that reads
  them. The structural models are fidelity.level's items without `auto` (`fidelities`).
- The shipped network: <repo>/weights/paper-plain.json; its `training` section records
  the settings it was trained with (`shipped_training`).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import tempfile
import zipfile
from pathlib import Path
from xml.etree import ElementTree

from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

BEAM = "StickSlipBeam"
FRICTION = "NeuralFriction"
# The item of StickSlipBeam's fidelity.level that is not a structural model: it picks one
# of the others (and a time step and integrator) by itself. See `fidelities`.
AUTO = "auto"
BUILD_HINT = (
    "run `cargo run --release -p fmu-build` first "
    "(it writes <target dir>/fmu/2.0/*.fmu and <target dir>/fmu/3.0/*.fmu)"
)


def _repo_root() -> Path:
    """The repository this package belongs to: <repo>/python-checks/stickslip_checks is
    where it lives (an editable install, as scripts/python-env.sh makes); otherwise the
    nearest folder above the working directory that holds python-checks/pyproject.toml."""
    source = Path(__file__).resolve().parents[2]
    if (source / "python-checks" / "pyproject.toml").is_file():
        return source
    here = Path.cwd().resolve()
    for folder in (here, *here.parents):
        if (folder / "python-checks" / "pyproject.toml").is_file():
            return folder
    return here


REPO = _repo_root()
DEFAULT_OUT = REPO / "out"
SHIPPED_WEIGHTS = REPO / "weights" / "paper-plain.json"


def shipped_training() -> dict:
    """The `training` section of the shipped weights file: the settings `stickslip train`
    ran with (`max_iterations`, `seed`, `lambda`, the data set, ...)."""
    return json.loads(SHIPPED_WEIGHTS.read_text())["training"]


def fmu_root() -> Path:
    """$STICKSLIP_FMU_DIR, else $CARGO_TARGET_DIR/fmu, else <repo>/target/fmu: the folder
    that holds one folder per FMI version (`2.0/`, `3.0/`)."""
    if os.environ.get("STICKSLIP_FMU_DIR"):
        return Path(os.environ["STICKSLIP_FMU_DIR"])
    if os.environ.get("CARGO_TARGET_DIR"):
        # Relative to the workspace root, as fmu-build resolves it.
        return REPO / os.environ["CARGO_TARGET_DIR"] / "fmu"
    return REPO / "target" / "fmu"


def fmu_dir() -> Path:
    """<fmu root>/2.0: the FMI 2.0 FMUs, the SSP systems that embed them and
    fmucontainer's link lists (which name FMUs in their own folder)."""
    return fmu_root() / "2.0"


def fmu_paths() -> dict[str, Path]:
    """Paths of both FMI 2.0 FMUs; FileNotFoundError (with the build command) if one is
    missing."""
    directory = fmu_dir()
    paths = {name: directory / f"{name}.fmu" for name in (BEAM, FRICTION)}
    missing = [str(p) for p in paths.values() if not p.is_file()]
    if missing:
        raise FileNotFoundError(f"missing FMU(s) {', '.join(missing)}: {BUILD_HINT}")
    return paths


def fmu3_paths() -> dict[str, Path]:
    """Paths of both FMI 3.0 FMUs (<fmu root>/3.0/, the same library as the FMI 2.0 ones);
    FileNotFoundError (with the build command) if one is missing."""
    directory = fmu_root() / "3.0"
    paths = {name: directory / f"{name}.fmu" for name in (BEAM, FRICTION)}
    missing = [str(p) for p in paths.values() if not p.is_file()]
    if missing:
        raise FileNotFoundError(f"missing FMU(s) {', '.join(missing)}: {BUILD_HINT}")
    return paths


def find_binary() -> Path:
    """$STICKSLIP_BIN, or the release binary built (if needed) by cargo."""
    if os.environ.get("STICKSLIP_BIN"):
        return Path(os.environ["STICKSLIP_BIN"])
    subprocess.run(
        ["cargo", "build", "--release", "--quiet", "--bin", "stickslip"],
        cwd=REPO,
        check=True,
    )
    metadata = subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--no-deps"],
        cwd=REPO,
        check=True,
        capture_output=True,
        text=True,
    )
    return Path(json.loads(metadata.stdout)["target_directory"]) / "release" / "stickslip"


# ----------------------------------------------------------------------------- model description


# The <Tool name="..."> under <VendorAnnotations> that lists the choices
# (stickslip_fmi::model_description::CHOICES_TOOL).
CHOICES_TOOL = "stickslip"


def choices(xml: str | bytes) -> dict[str, dict[str, int]]:
    """Variable name -> {word: integer code} of every choice variable of the model
    description `xml`, as its `stickslip` tool annotation lists them:

        <VendorAnnotations><Tool name="stickslip"><Choices>
          <Choice variable="friction.law" type="FrictionModel" description="...">
            <Item code="1" name="exponential" description="..."/> ...

    The variables themselves are FMI Integers with min 1 and max the number of codes."""
    root = ElementTree.fromstring(xml)
    path = f"VendorAnnotations/Tool[@name='{CHOICES_TOOL}']/Choices/Choice"
    return {
        choice.get("variable"): {item.get("name"): int(item.get("code")) for item in choice}
        for choice in root.findall(path)
    }


def model_description_xml(fmu: Path) -> bytes:
    """The modelDescription.xml of the FMU archive `fmu`."""
    with zipfile.ZipFile(fmu) as archive:
        return archive.read("modelDescription.xml")


class Model:
    """One model description: variables by name, their value references, types and choices."""

    def __init__(self, description, choices: dict[str, dict[str, int]]):
        self.description = description
        self.guid = description.guid
        self.identifier = description.coSimulation.modelIdentifier
        self.variables = {v.name: v for v in description.modelVariables}
        self.vr = {name: v.valueReference for name, v in self.variables.items()}
        unknown = set(choices) - set(self.variables)
        if unknown:
            raise ValueError(f"choices annotated for unknown variables {sorted(unknown)}")
        self.choices = choices

    @classmethod
    def read(cls, fmu: Path) -> Model:
        return cls(read_model_description(str(fmu)), choices(model_description_xml(fmu)))

    def code(self, name: str, value) -> int:
        """The integer a choice variable is set to for `value` (an item name or its code)."""
        items = self.choices[name]
        if isinstance(value, str):
            return items[value]
        if int(value) not in items.values():
            raise KeyError(f"{name}: no choice with code {value}")
        return int(value)

    def real_start(self, name: str) -> float:
        """The start value of the Real variable `name` (the model description holds it as
        text)."""
        return float(self.variables[name].start)

    def kind(self, name: str) -> str:
        """How the variable is set and read: Real, Integer, Boolean or String (a choice
        variable is an Integer: its code)."""
        kind = self.variables[name].type
        return "Integer" if name in self.choices else kind

    def set(self, slave: FMU2Slave, values: dict) -> None:
        """Sets every name -> value in order, each with its type's setter (choices by
        item name or code)."""
        for name, value in values.items():
            vr, kind = [self.vr[name]], self.kind(name)
            if name in self.choices:
                slave.setInteger(vr, [self.code(name, value)])
            elif kind == "Real":
                slave.setReal(vr, [float(value)])
            elif kind == "Integer":
                slave.setInteger(vr, [int(value)])
            elif kind == "Boolean":
                slave.setBoolean(vr, [bool(value)])
            else:
                slave.setString(vr, [str(value)])

    def getter(self, slave: FMU2Slave, name: str):
        """A function of no argument that reads the variable `name` of `slave`."""
        vr, kind = [self.vr[name]], self.kind(name)
        read = {
            "Real": slave.getReal,
            "Integer": slave.getInteger,
            "Boolean": slave.getBoolean,
            "String": slave.getString,
        }[kind]
        return lambda: read(vr)[0]


def fidelities(beam: Model) -> tuple[str, ...]:
    """The structural models the scripts run: StickSlipBeam's fidelity.level items in the
    order of their codes, without `auto` (which picks one of them by itself)."""
    items = beam.choices["fidelity.level"]
    return tuple(name for name in sorted(items, key=items.get) if name != AUTO)


class Fmu:
    """One FMU archive unpacked into a temporary folder (removed by close())."""

    def __init__(self, archive: Path, folder: Path | None = None):
        self.path = Path(archive)
        self.folder = Path(folder) if folder else Path(tempfile.mkdtemp(prefix="stickslip-fmu-"))
        self.unzipped = Path(extract(str(self.path), unzipdir=str(self.folder / self.path.stem)))
        self.model = Model.read(self.path)

    def slave(self, instance: str) -> FMU2Slave:
        """A new (not yet instantiated) co-simulation slave of this FMU."""
        return FMU2Slave(
            guid=self.model.guid,
            unzipDirectory=str(self.unzipped),
            modelIdentifier=self.model.identifier,
            instanceName=instance,
        )

    def close(self) -> None:
        shutil.rmtree(self.folder, ignore_errors=True)


class Fmus:
    """Both FMUs, unpacked once into one temporary folder (removed by close())."""

    def __init__(self, paths: dict[str, Path]):
        self.paths = paths
        self.tmp = Path(tempfile.mkdtemp(prefix="fmu-scene-"))
        self.fmus = {name: Fmu(path, self.tmp) for name, path in paths.items()}
        self.dirs = {name: fmu.unzipped for name, fmu in self.fmus.items()}
        self.models = {name: fmu.model for name, fmu in self.fmus.items()}
        self.descriptions = {name: m.description for name, m in self.models.items()}
        self.vr = {name: m.vr for name, m in self.models.items()}

    def slave(self, name: str, instance: str) -> FMU2Slave:
        return self.fmus[name].slave(instance)

    def close(self) -> None:
        shutil.rmtree(self.tmp, ignore_errors=True)
