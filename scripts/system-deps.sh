#!/usr/bin/env bash
# Debian packages the build needs beyond Rust, Python and gcc: libclang-dev, for the
# bindgen step of the `fmi` importer crate used by fmu-build's tests, and libtbb12
# (libtbb.so.12), which ecospy's Ecos library links (python-checks/tests/test_masters.py),
# and qemu-user-static, whose qemu-x86_64-static runs the bit-identity test on a CPU
# without AVX2/FMA (tests/physics/reproducible.rs), and calculix-ccx, whose ccx regenerates
# the CalculiX example's matrices (tests/physics/calculix_beam.rs), and gmsh, which meshes the
# Gmsh example again (tests/physics/gmsh_beam.rs); then those of the Windows and
# aarch64 FMU binaries and their tests (cross-deps.sh).
# Installs only what is missing.
set -euo pipefail
scripts="$(dirname "${BASH_SOURCE[0]}")"
bash "$scripts/apt-install.sh" libclang-dev libtbb12 qemu-user-static calculix-ccx gmsh
bash "$scripts/cross-deps.sh"
