#!/usr/bin/env bash
# Runs every test: formatting and lints, the Rust test suite, and the Python checks in
# the project's venv (created on the fly from pinned requirements).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

bash scripts/system-deps.sh
# system-deps.sh installed ccx and gmsh: the tests that regenerate the examples' files
# must run them, not skip (tests/physics/fe_tools.rs).
export STICKSLIP_REQUIRE_FE_TOOLS=1
echo "== cargo fmt --check"
cargo fmt --all -- --check
echo "== cargo clippy -D warnings"
cargo clippy --release --workspace --all-targets -- -D warnings
echo "== fmu-build (the FMU tests import the packaged .fmu files)"
# zig and cargo-zigbuild (.venv-zig): fmu-build links the FMU binary for glibc 2.17.
bash scripts/zig-env.sh >/dev/null
cargo run --release -p fmu-build
echo "== cargo test"
mkdir -p target
cargo test --release --workspace --all-targets 2>&1 | tee target/cargo-test.log
# A summary line that the CI log readers understand, over every test binary.
awk '/^test result:/ {p += $4; f += $6; i += $8} END {printf "rust: %d passed, %d failed, %d skipped\n", p, f, i}' target/cargo-test.log

echo "== the packaged FMU binary under Debian 11's glibc 2.31 (scripts/old-glibc.sh)"
bash scripts/old-glibc.sh

echo "== valgrind (memcheck) over an FMI importer loop"
bash scripts/valgrind.sh

echo "== python-checks (pytest)"
python="$(bash scripts/python-env.sh)"
# The real ONNX exporters (TensorFlow, Keras 3, tf2onnx) in .venv-exporters, which
# python-checks/tests/test_onnx_exporters.py runs; created here so that the test never
# skips in the full run.
bash scripts/exporters-env.sh >/dev/null
# --workspace: the same feature set as fmu-build's builds, so nothing is rebuilt.
cargo build --release --workspace --bins
export STICKSLIP_BIN="$root/target/release/stickslip"
# Written afresh by test_cross_platform.py and test_onnx_exporters.py.
rm -f target/cross-platform.md target/onnx-exporters.md
set +e
"$python" -m pytest -q python-checks
status=$?
set -e
# The foreign-binary table test_cross_platform.py wrote (pytest -q does not show it).
if [ -f target/cross-platform.md ]; then
  cat target/cross-platform.md
fi
# The exporter table test_onnx_exporters.py wrote.
if [ -f target/onnx-exporters.md ]; then
  cat target/onnx-exporters.md
fi

echo "== python-checks on a second CPU model (scripts/second-cpu.sh masked)"
# numpy, OpenBLAS and glibc without AVX, AVX2 and FMA, on the two files that compare
# numbers recorded on one CPU (the paper authors' metrics, the retrained weights); the
# whole suite and the qemu run: docs/python-harness.md, "On any CPU".
set +e
SECOND_CPU_ALLOW_SAME=1 bash scripts/second-cpu.sh masked python-checks/tests/test_paper_authors_network.py \
  python-checks/tests/test_training.py
second=$?
set -e
# pytest exits 5 when it collects no test; that is not a failure of this project.
if [ "$status" -ne 0 ] && [ "$status" -ne 5 ]; then
  exit "$status"
fi
exit "$second"
