#!/usr/bin/env bash
# Runs an FMI importer loop under valgrind (memcheck) and fails on any invalid read or
# write, use of uninitialised memory, or definitely lost block.
#
# The loop is the ignored test `valgrind_driver_loop` in
# tests/fmu/threads_resources/valgrind_driver.rs: both FMUs through the C ABI,
# instantiate -> parameters -> initialise -> steps with reads and writes -> FMU state
# get/serialize/deserialize/set/free -> an error and the recovery from it -> reset ->
# free, with a logger, with a NULL logger, and with allocateMemory/freeMemory callbacks
# (calloc/free wrappers, which the FMU must not call: canNotUseMemoryManagementFunctions
# = true). One FMU state per life is left for fmi2FreeInstance to free. Then
# `valgrind_driver_loop3` in tests/fmu/ffi3/valgrind_driver.rs: the same kind of life
# through the FMI 3.0 interface (fmi3* functions of the same library).
#
# scripts/test.sh runs it after the Rust tests; it also runs on its own. Honours
# CARGO_TARGET_DIR. STICKSLIP_VALGRIND_ROUNDS sets the lives per FMU and kind of
# callbacks (default 2; about 10 s under valgrind).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

if ! command -v valgrind >/dev/null 2>&1; then
  echo "== installing valgrind"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then
    sudo="sudo"
  fi
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq valgrind
fi
valgrind --version

echo "== building the driver (cargo test --release --workspace --no-run --test fmu)"
bin="$(cargo test --release --workspace --no-run --test fmu --message-format=json \
  | grep '"name":"fmu"' \
  | sed -n 's/.*"executable":"\([^"]*\)".*/\1/p' | tail -n 1)"
if [ -z "$bin" ] || [ ! -x "$bin" ]; then
  echo "could not find the test binary" >&2
  exit 2
fi

target="${CARGO_TARGET_DIR:-$root/target}"
mkdir -p "$target"
log="$target/valgrind.log"
echo "== valgrind $bin (log: $log)"
set +e
valgrind --leak-check=full --errors-for-leak-kinds=definite --error-exitcode=1 \
  --log-file="$log" \
  "$bin" --ignored --exact threads_resources::valgrind_driver::valgrind_driver_loop \
  ffi3::valgrind_driver::valgrind_driver_loop3 \
  --test-threads=1 --nocapture
status=$?
set -e

echo "== valgrind summary"
grep -E "Invalid (read|write)|uninitialised|definitely lost|indirectly lost|possibly lost|ERROR SUMMARY" "$log" \
  | sed 's/^==[0-9]*== *//' || true
printf 'invalid reads: %s, invalid writes: %s\n' \
  "$(grep -c 'Invalid read' "$log" || true)" "$(grep -c 'Invalid write' "$log" || true)"
if [ "$status" -ne 0 ]; then
  echo "valgrind: FAILED (exit $status); see $log" >&2
  exit "$status"
fi
echo "valgrind: clean"
