#!/usr/bin/env bash
# Creates (or reuses) .venv-exporters, the venv of the real ONNX exporters (TensorFlow,
# Keras 3, tf2onnx; pinned in python-checks/requirements-exporters.txt) that
# python-checks/exporters/export_networks.py runs in, and prints the path of its python.
# Idempotent: reinstalls only when the requirements change (hash stamp).
#
# A venv of its own: TensorFlow is 1.5 GB and conflicts with nothing the main venv needs
# only by luck; the main suite stays as fast to create as before, and its exporter test
# skips, saying why, where this venv is absent. scripts/test.sh always creates it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$root/.venv-exporters"
req="$root/python-checks/requirements-exporters.txt"
stamp="$venv/.requirements.sha256"
want="$(sha256sum <"$req" | cut -d' ' -f1)"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv" >&2
fi
if [ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ]; then
  echo "== installing the ONNX exporters into $venv" >&2
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$req" >&2
  echo "$want" >"$stamp"
fi
echo "$venv/bin/python"
