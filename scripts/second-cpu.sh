#!/usr/bin/env bash
# The Python checks on a second CPU model. numpy, OpenBLAS, glibc's libm and onnxruntime
# each pick their float64 kernels by the CPU, so a test that holds its numbers to the
# last bit passes on the machine that recorded them and fails on another (issue 33: an
# AVX-512 EPYC). This runs the checks under kernels this machine would not pick itself.
#
#   bash scripts/second-cpu.sh [masked|qemu] [pytest arguments]
#
# masked (default): in this CPU, with numpy's dispatch limited to its SSE3 baseline
#   (NPY_DISABLE_CPU_FEATURES: every dispatched feature), OpenBLAS's Nehalem kernels
#   (OPENBLAS_CORETYPE, numpy's and scipy's copies alike) and glibc's ifuncs without
#   AVX, AVX2 and FMA (GLIBC_TUNABLES; glibc 2.33 and later name them AVX2, FMA, not
#   AVX2_Usable). onnxruntime reads the CPU itself and keeps its kernels. Default
#   arguments: the whole of python-checks.
# qemu: python under `qemu-x86_64-static -cpu Nehalem` (no AVX, AVX2 nor FMA): every
#   library in the process, onnxruntime and our FMU binaries included, sees that CPU.
#   Child processes (the stickslip command line, Dask workers) run natively: qemu-user
#   does not follow exec. About 10 to 30 times slower; default arguments: the numerically
#   sensitive files (PYTHON_SENSITIVE below).
#
# Both first print the kernels' fingerprints (stickslip_checks.cpu_kernels) natively and
# under the setting, and stop if none differs (the setting would prove nothing): exit 3,
# or 0 with SECOND_CPU_ALLOW_SAME=1 (the test command's choice: on a CPU without AVX the
# ordinary run already is the other kernels' run).
# Needs the FMUs (cargo run --release -p fmu-build) and the release binary
# (cargo build --release --workspace --bins); STICKSLIP_BIN defaults to it.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

mode="${1:-masked}"
case "$mode" in
  masked | qemu) shift || true ;;
  -*) mode=masked ;;
  *) echo "second-cpu.sh: unknown mode '$mode' (masked or qemu)" >&2; exit 2 ;;
esac

# The files whose assertions compare numbers computed by numpy, scikit-learn or
# onnxruntime (docs/python-harness.md, "On any CPU").
PYTHON_SENSITIVE=(
  python-checks/tests/test_paper_authors_network.py
  python-checks/tests/test_onnx_import.py
  python-checks/tests/test_sklearn_peer.py
  python-checks/tests/test_slip_metrics.py
  python-checks/tests/test_paper_algorithms.py
)

python="$(bash scripts/python-env.sh)"
export STICKSLIP_BIN="${STICKSLIP_BIN:-$root/target/release/stickslip}"
if [ ! -x "$STICKSLIP_BIN" ]; then
  echo "second-cpu.sh: no $STICKSLIP_BIN; run cargo build --release --workspace --bins" >&2
  exit 2
fi

dispatched="$("$python" -c 'import numpy._core._multiarray_umath as m; print(" ".join(m.__cpu_dispatch__))')"
masked_env=(
  "NPY_DISABLE_CPU_FEATURES=$dispatched"
  "OPENBLAS_CORETYPE=Nehalem"
  "GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX,-AVX2,-FMA,-FMA4,-AVX512F"
)
if [ "$mode" = masked ]; then
  run=(env "${masked_env[@]}" "$python")
  [ "$#" -gt 0 ] || set -- python-checks
else
  qemu="$(command -v qemu-x86_64-static || true)"
  if [ -z "$qemu" ]; then
    echo "second-cpu.sh: qemu-x86_64-static not found (bash scripts/system-deps.sh installs it)" >&2
    exit 2
  fi
  run=("$qemu" -cpu Nehalem "$python")
  [ "$#" -gt 0 ] || set -- "${PYTHON_SENSITIVE[@]}"
fi

echo "== kernels: native against $mode"
mkdir -p target/second-cpu
"$python" -m stickslip_checks.cpu_kernels --json target/second-cpu/native.json >/dev/null
"${run[@]}" -m stickslip_checks.cpu_kernels --json "target/second-cpu/$mode.json" >/dev/null
set +e
"$python" - "target/second-cpu/native.json" "target/second-cpu/$mode.json" <<'PY'
import json, sys
native, other = (json.load(open(p)) for p in sys.argv[1:])
changed = [k for k in native if native[k] != other[k]]
for k in native:
    print(f"  {k:34} {native[k]}  {other[k]}  {'differs' if k in changed else 'same'}")
if not changed:
    print("second-cpu.sh: no kernel gives other bits under this setting; it proves nothing",
          file=sys.stderr)
    sys.exit(3)
PY
kernels=$?
set -e
if [ "$kernels" -eq 3 ] && [ "${SECOND_CPU_ALLOW_SAME:-0}" = 1 ]; then
  # A CPU without AVX already runs the masked kernels: the main pytest run was the
  # second CPU model's run.
  echo "second-cpu.sh: this CPU already runs the masked kernels; nothing more to run"
  exit 0
elif [ "$kernels" -ne 0 ]; then
  exit "$kernels"
fi

echo "== pytest ($mode): $*"
"${run[@]}" -m pytest -q "$@"
