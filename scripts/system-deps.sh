#!/usr/bin/env bash
# Debian packages the build needs beyond Rust, Python and gcc: libclang-dev, for the
# bindgen step of the `fmi` importer crate used by fmu-build's tests, and libtbb12
# (libtbb.so.12), which ecospy's Ecos library links (python-checks/tests/test_masters.py).
# Installs only what is missing.
set -euo pipefail
# The foreign FMU binaries and their tests (win64, aarch64 Linux): scripts/cross-deps.sh.
bash "$(dirname "${BASH_SOURCE[0]}")/cross-deps.sh"
missing=()
for package in libclang-dev libtbb12; do
  dpkg -s "$package" >/dev/null 2>&1 || missing+=("$package")
done
if [ "${#missing[@]}" -eq 0 ]; then
  exit 0
fi
if [ "$(id -u)" -eq 0 ]; then
  sudo=()
else
  sudo=(sudo)
fi
echo "== apt-get install ${missing[*]}" >&2
"${sudo[@]}" apt-get update -qq >&2
DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq "${missing[@]}" >&2
