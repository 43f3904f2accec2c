#!/usr/bin/env bash
# Creates (or reuses) the project's Python venv at .venv from the pinned requirements,
# installs the python-checks package (stickslip_checks, editable) into it and prints the
# path of its python. Idempotent: reinstalls only when requirements.txt or
# pyproject.toml change.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$root/.venv"
req="$root/python-checks/requirements.txt"
project="$root/python-checks/pyproject.toml"
stamp="$venv/.requirements.sha256"
want="$(cat "$req" "$project" | sha256sum | cut -d' ' -f1)"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv" >&2
fi
if [ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]; then
  "$venv/bin/python" -m pip install --quiet --upgrade pip >&2
  "$venv/bin/python" -m pip install --quiet -r "$req" >&2
  # Editable: the package keeps reading the FMUs and weights of this checkout. The
  # pinned requirements above are its dependencies (no resolution, no build isolation).
  # setuptools' UserWarning about editable installs is silenced: it warns of folders named
  # like the package in the working directory, and there are none.
  PYTHONWARNINGS=ignore::UserWarning "$venv/bin/python" -m pip install --quiet --no-deps --no-build-isolation \
    --editable "$root/python-checks" >&2
  echo "$want" > "$stamp"
fi
echo "$venv/bin/python"
