"""docs/variables.md is what `stickslip_checks.variables_doc` writes from the checked-in
model descriptions (which a Rust test keeps equal to the variable tables), so the page
lists exactly the FMUs' variables."""

from __future__ import annotations

from xml.etree import ElementTree

from stickslip_checks import variables_doc


def test_the_checked_in_variables_page_is_the_generated_one():
    generated = variables_doc.render()
    checked_in = variables_doc.PAGE.read_text(encoding="utf-8")
    assert checked_in == generated, (
        "docs/variables.md differs from the model descriptions; regenerate it with "
        "`python -m stickslip_checks.variables_doc` (in python-checks/)"
    )


def test_every_fmi2_variable_has_one_row_with_its_value_reference():
    page = variables_doc.render()
    for model in variables_doc.MODELS:
        section = page.split(f"## {model}\n", 1)[1].split("\n## ", 1)[0]
        xml = variables_doc.DESCRIPTIONS / f"{model}.xml"
        variables = list(ElementTree.parse(xml).getroot().iter("ScalarVariable"))
        assert variables, f"{xml} lists no variables"
        rows = [line for line in section.splitlines() if line.startswith("| `")]
        assert len(rows) == len(variables)
        for variable in variables:
            row = f"| `{variable.get('name')}` | {variable.get('valueReference')} |"
            assert sum(line.startswith(row) for line in rows) == 1, row


def test_a_pipe_in_a_description_stays_inside_its_cell():
    assert variables_doc._cell("|v_rel| > 0") == "\\|v_rel\\| > 0"
