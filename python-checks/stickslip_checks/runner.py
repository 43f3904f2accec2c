"""What the entry points share around their work: the output folder from the command
line, the FMUs (or the message that says how to build them) and the failure report."""

from __future__ import annotations

import sys
from pathlib import Path

from .artifacts import DEFAULT_OUT, fmu_paths


def out_dir(argv: list[str] | None, create: bool = True, default: Path = DEFAULT_OUT) -> Path:
    """OUT_DIR, the first argument (sys.argv[1:] when `argv` is None), else `default`
    (<repo>/out)."""
    argv = sys.argv[1:] if argv is None else argv
    out = Path(argv[0]) if argv else default
    if create:
        out.mkdir(parents=True, exist_ok=True)
    return out


def find_fmus(script: str) -> dict[str, Path] | None:
    """artifacts.fmu_paths(), or None after printing `script: <how to build them>`."""
    try:
        return fmu_paths()
    except FileNotFoundError as error:
        print(f"{script}: {error}", file=sys.stderr)
        return None


def report_failures(failures: list[str]) -> int:
    """Prints the failed checks to stderr; the script's exit status (1 if any)."""
    if not failures:
        return 0
    print("\nFAILED:", file=sys.stderr)
    for f in failures:
        print(f"  {f}", file=sys.stderr)
    return 1
