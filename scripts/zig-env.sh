#!/usr/bin/env bash
# Creates (or reuses) .venv-zig, the build venv of the portable FMU binary: zig (the
# `ziglang` wheel) and cargo-zigbuild, both from PyPI, pinned in
# scripts/zig-requirements.txt. fmu-build looks for cargo-zigbuild and zig in
# .venv-zig/bin. Prints that folder. Idempotent: reinstalls only when the requirements
# change.
#
# A separate venv from .venv (python-env.sh): fmu-build needs only these two packages,
# not the checks' numpy, matplotlib, dask, ... ; and a developer who only builds the FMUs
# gets them in about 15 s.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
venv="$root/.venv-zig"
req="$root/scripts/zig-requirements.txt"
stamp="$venv/.requirements.sha256"
want="$(sha256sum <"$req" | cut -d' ' -f1)"
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv" >&2
fi
if [ "$(cat "$stamp" 2>/dev/null || true)" != "$want" ] || [ ! -x "$venv/bin/zig" ]; then
  echo "== installing zig and cargo-zigbuild into $venv" >&2
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r "$req" >&2
  # The wheel keeps the zig executable inside the package (next to its lib/ folder) and
  # puts no `zig` on PATH. zig finds its lib/ from its own resolved path, so a symlink
  # in bin/ works.
  zig="$("$venv/bin/python" -c 'import os, ziglang; print(os.path.join(os.path.dirname(ziglang.__file__), "zig"))')"
  ln -sf "$zig" "$venv/bin/zig"
  echo "$want" >"$stamp"
fi
echo "$venv/bin"
