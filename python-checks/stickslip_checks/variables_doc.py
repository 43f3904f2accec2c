"""docs/variables.md, written from the checked-in model descriptions.

The variable tables in `src/fmi` are the one definition of every FMU variable; fmu-build
writes them into modelDescription.xml, and a Rust test keeps the copies in
`modelDescription/` (FMI 2.0) and `modelDescription/3.0/` equal to what the tables
generate. This module turns those copies into the Markdown reference, so the page cannot
drift from the FMUs: `python-checks/tests/test_variables_doc.py` fails when the checked-in
page differs from `render()`.

Regenerate after a variable change (after `cargo run --release -p fmu-build --
--update-model-descriptions`):

    python -m stickslip_checks.variables_doc

Only the standard library is used, so the page can be written without fmpy or a build.
"""

from __future__ import annotations

import sys
from pathlib import Path
from xml.etree import ElementTree

REPO = Path(__file__).resolve().parents[2]
DESCRIPTIONS = REPO / "modelDescription"
PAGE = REPO / "docs" / "variables.md"
MODELS = ("StickSlipBeam", "NeuralFriction")
# The order of a model's table: what an importer sets, feeds, then reads.
CAUSALITIES = ("parameter", "input", "output")


def _cell(text: str) -> str:
    """`text` as one Markdown table cell: a `|` would end the cell."""
    return text.replace("|", "\\|")


def _fmi2_rows(xml: Path) -> list[dict[str, str]]:
    """One row per ScalarVariable of an FMI 2.0 description, in document order."""
    rows = []
    for variable in ElementTree.parse(xml).getroot().iter("ScalarVariable"):
        value = next(iter(variable))  # <Real>, <Integer>, <Boolean> or <String>
        rows.append(
            {
                "name": variable.get("name"),
                "vr": variable.get("valueReference"),
                "causality": variable.get("causality"),
                "variability": variable.get("variability"),
                "type": value.tag,
                "unit": value.get("unit", ""),
                "start": value.get("start", ""),
                "range": _range(value),
                "description": variable.get("description", ""),
            }
        )
    return rows


def _range(value: ElementTree.Element) -> str:
    low, high = value.get("min"), value.get("max")
    if low is None and high is None:
        return ""
    return f"{low or ''}..{high or ''}"


def _fmi3_names(xml: Path) -> dict[str, tuple[str, str]]:
    """name -> (value reference, type, with the array size) of an FMI 3.0 description."""
    names = {}
    variables = ElementTree.parse(xml).getroot().find("ModelVariables")
    for variable in variables:
        kind = variable.tag
        dimension = variable.find("Dimension")
        if dimension is not None:
            kind = f"{kind} array [{dimension.get('start')}]"
        names[variable.get("name")] = (variable.get("valueReference"), kind)
    return names


def _model_section(model: str) -> list[str]:
    rows = _fmi2_rows(DESCRIPTIONS / f"{model}.xml")
    lines = [f"## {model}", ""]
    for causality in CAUSALITIES:
        chosen = [row for row in rows if row["causality"] == causality]
        if not chosen:
            continue
        lines += [
            f"### {model}: {causality}s",
            "",
            "| name | value reference | type | unit | start | range | variability | description |",
            "| --- | --- | --- | --- | --- | --- | --- | --- |",
        ]
        for row in chosen:
            start = f"`{row['start']}`" if row["start"] else ""
            lines.append(
                f"| `{row['name']}` | {row['vr']} | {row['type']} | {row['unit']} | {start} "
                f"| {row['range']} | {row['variability']} | {_cell(row['description'])} |"
            )
        lines.append("")
    lines += _fmi3_section(model, rows)
    return lines


def _fmi3_section(model: str, rows: list[dict[str, str]]) -> list[str]:
    """What the FMI 3.0 description names differently: variables only one version has."""
    fmi3 = _fmi3_names(DESCRIPTIONS / "3.0" / f"{model}.xml")
    fmi2 = {row["name"]: row["vr"] for row in rows}
    only3 = [name for name in fmi3 if name not in fmi2]
    only2 = [name for name in fmi2 if name not in fmi3]
    moved = [name for name in fmi2 if name in fmi3 and fmi3[name][0] != fmi2[name]]
    lines = [f"### {model}: FMI 3.0", ""]
    if not only3 and not only2 and not moved:
        return lines + ["The same names and value references as FMI 2.0.", ""]
    lines.append(
        "The same names and value references as FMI 2.0 (types Float64, Int32, Boolean "
        "and String), except:"
    )
    lines.append("")
    for name in only3:
        vr, kind = fmi3[name]
        lines.append(f"- only in FMI 3.0: `{name}` (value reference {vr}, {kind})")
    for name in only2:
        lines.append(f"- only in FMI 2.0: `{name}` (value reference {fmi2[name]})")
    for name in moved:
        lines.append(
            f"- `{name}`: value reference {fmi2[name]} in FMI 2.0, {fmi3[name][0]} in FMI 3.0"
        )
    lines.append("")
    return lines


def render() -> str:
    """The whole page, as `docs/variables.md` must hold it."""
    lines = [
        "# FMU variables",
        "",
        "<!-- Generated by `python -m stickslip_checks.variables_doc` from modelDescription/;",
        "     do not edit: python-checks/tests/test_variables_doc.py compares it. -->",
        "",
        "Every variable of both FMUs, read from the checked-in model descriptions",
        "(`modelDescription/*.xml` for FMI 2.0, `modelDescription/3.0/` for FMI 3.0), which",
        "fmu-build generates from the variable tables in `src/fmi`. A choice is an Integer",
        "code; its words are at the end of the description. What the variables do:",
        "[fmu-reference.md](fmu-reference.md).",
        "",
    ]
    for model in MODELS:
        lines += _model_section(model)
    return "\n".join(lines).rstrip("\n") + "\n"


def main(argv: list[str] | None = None) -> int:
    """Writes docs/variables.md (or the path given)."""
    argv = sys.argv[1:] if argv is None else argv
    target = Path(argv[0]) if argv else PAGE
    target.write_text(render(), encoding="utf-8")
    print(f"wrote {target}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
