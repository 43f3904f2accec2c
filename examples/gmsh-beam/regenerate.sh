#!/usr/bin/env bash
# Regenerates the paper beam's Gmsh mesh (beam.geo -> beam.msh, MSH 4.1 ASCII) in this
# directory. Needs gmsh (Debian gmsh; bash scripts/system-deps.sh installs it). The
# committed beam.msh was written by gmsh 4.8.4; another version may number the nodes
# otherwise (tests/physics/gmsh_beam.rs compares the physics, not the bytes): scene.toml
# names its clamp and its contact by physical group ("clamp", "tip"), not by node
# number, so it follows.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")"
gmsh -2 beam.geo -format msh41 -o beam.msh > /dev/null
