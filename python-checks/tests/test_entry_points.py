"""Every console script of pyproject.toml (each is also `python -m
stickslip_checks.<module>`): `--help` prints its usage and exits 0, and an unknown
argument exits 2 (argparse's refusal), both without writing anything (the working
directory, where a folder named after the argument used to appear, stays empty).
Parses only: no FMU is run. Runs in a few seconds."""

from __future__ import annotations

import importlib
import tomllib
from pathlib import Path

import pytest

PYPROJECT = Path(__file__).resolve().parents[1] / "pyproject.toml"
SCRIPTS = tomllib.loads(PYPROJECT.read_text())["project"]["scripts"]


def entry(target: str):
    module, function = target.split(":")
    return getattr(importlib.import_module(module), function)


@pytest.mark.parametrize("script", sorted(SCRIPTS))
def test_help_prints_usage_and_writes_nothing(script, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exit_info:
        entry(SCRIPTS[script])(["--help"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out.startswith(f"usage: {script}")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("script", sorted(SCRIPTS))
@pytest.mark.parametrize("argv", [["--bogus"], [".", "extra"]], ids=["option", "positional"])
def test_unknown_arguments_are_refused(script, argv, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exit_info:
        entry(SCRIPTS[script])(argv)
    assert exit_info.value.code == 2
    assert "unrecognized arguments" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_every_script_is_an_entry_module():
    """`python -m stickslip_checks.<module>` runs the same main as the console script."""
    for target in SCRIPTS.values():
        module = importlib.import_module(target.split(":")[0])
        assert target.endswith(":main")
        assert 'if __name__ == "__main__":' in Path(module.__file__).read_text(), target
