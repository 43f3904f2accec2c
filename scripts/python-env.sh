#!/usr/bin/env bash
# Creates (or reuses) the project's Python venv at .venv from the pinned requirements
# (requirements.txt, and requirements-masters.txt: the co-simulation masters the tests
# run), installs the python-checks package (stickslip_checks, editable) into it and
# prints the path of its python. Idempotent: reinstalls only when a requirements file or
# pyproject.toml changes.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$root/.venv"
req="$root/python-checks/requirements.txt"
masters="$root/python-checks/requirements-masters.txt"
project="$root/python-checks/pyproject.toml"
stamp="$venv/.requirements.sha256"
want="$(cat "$req" "$masters" "$project" | sha256sum | cut -d' ' -f1)"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv" >&2
fi
if [ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]; then
  "$venv/bin/python" -m pip install --quiet --upgrade pip >&2
  "$venv/bin/python" -m pip install --quiet -r "$req" -r "$masters" >&2
  # Editable: the package keeps reading the FMUs and weights of this checkout. The
  # pinned requirements above are its dependencies (no resolution, no build isolation).
  # setuptools' UserWarning about editable installs is silenced: it warns of folders named
  # like the package in the working directory, and there are none.
  PYTHONWARNINGS=ignore::UserWarning "$venv/bin/python" -m pip install --quiet --no-deps --no-build-isolation \
    --editable "$root/python-checks" >&2
  # ecospy's wheel ships the programs it starts (ecos, and proxyfmu for FMUs run in a
  # process of their own) without the execute bit.
  "$venv/bin/python" - >&2 <<'PY'
import os, stat
from importlib.util import find_spec
binaries = os.path.join(os.path.dirname(find_spec("ecospy").origin), "binaries")
for name in ("ecos", "proxyfmu"):
    path = os.path.join(binaries, name)
    os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
PY
  echo "$want" > "$stamp"
fi
echo "$venv/bin/python"
