"""What the entry points share: their argument parser (help from the entry point's
docstring, OUT_DIR, refusal of unknown arguments), the FMUs or the message that says
how to build them, and progress lines on stderr."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .artifacts import DEFAULT_OUT, fmu_paths


def parser(prog: str, doc: str, out: Path | None = DEFAULT_OUT) -> argparse.ArgumentParser:
    """The parser of entry point `prog` (its console script name) described by its module
    docstring `doc`; with the optional positional OUT_DIR (default `out`) unless `out` is
    None."""
    p = argparse.ArgumentParser(
        prog=prog, description=doc, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    if out is not None:
        p.add_argument(
            "out", nargs="?", type=Path, default=out, metavar="OUT_DIR",
            help=f"output folder (default {out})",
        )
    return p


def find_fmus(script: str) -> dict[str, Path] | None:
    """artifacts.fmu_paths(), or None after printing `script: <how to build them>`."""
    try:
        return fmu_paths()
    except FileNotFoundError as error:
        print(f"{script}: {error}", file=sys.stderr)
        return None


def progress(text: str) -> None:
    """One line of progress of a long run, on stderr (stdout keeps the tables)."""
    print(text, file=sys.stderr, flush=True)
