#!/usr/bin/env bash
# Fuzzes every parser of outside bytes with cargo fuzz (libFuzzer):
#   fmu_state     serialized FMU state (fmi2DeSerializeFMUstate + fmi2SetFMUstate)
#   weights       neural weights file (NeuralLaw::from_file / from_json)
#   onnx          ONNX network (stickslip_formats::onnx::read_onnx, then
#                 stickslip::neural::onnx's import)
#   scene         scene file (stickslip simulate --scene FILE)
#   training_csv  training CSV (stickslip train --data FILE.csv)
#
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET] [TARGET...]   (default: 120 s, all five)
#
# First writes the seed inputs (fuzz/seeds.rs: real FMU states, small weights files, ONNX networks,
# scenes, CSV files) into fuzz/corpus/<target>/. Then runs the targets one after the
# other, one process each, minimises each kept corpus with `cargo fuzz cmin`, writes
# the seeds back, and prints per target the executions, executions per second,
# coverage and whether it crashed. A crash leaves its input in fuzz/artifacts/<target>/
# and makes the script exit with status 1: turn it into a test in
# tests/fmu/fuzz_regressions.rs.
#
# Build: `cargo fuzz` builds in release mode with debug assertions and overflow checks
# (its default). `-s none` turns the sanitizers off: they need a nightly compiler,
# while the coverage instrumentation libFuzzer needs (SanitizerCoverage, plain -C
# flags) works on stable Rust, so no RUSTC_BOOTSTRAP is needed. Safe Rust does not need
# AddressSanitizer to catch out-of-bounds accesses, and the code these targets reach
# has two unsafe blocks, both target_feature calls taken only when the CPU reports the
# features (AVX2 and FMA in stickslip::neural::law, AVX2 in stickslip::banded); the
# pointer handling of the C interface (stickslip_fmi::ffi2, ffi3) is not reached: the
# FMU-state target enters one layer below it, at `Instance`, which the ffi functions
# forward to.
#
# Environment: CARGO_TARGET_DIR (default: cargo fuzz's fuzz/target), FUZZ_LOG_DIR
# (libFuzzer output, default: a temporary folder, printed), FUZZ_NO_CMIN=1 to keep the
# corpus unminimised.
set -euo pipefail

cd "$(dirname "$0")/.."
seconds=${1:-120}
shift || true
if [ $# -gt 0 ]; then
    targets=("$@")
else
    targets=(fmu_state weights onnx scene training_csv)
fi
case "$seconds" in
'' | *[!0-9]*)
    echo "usage: $0 [SECONDS_PER_TARGET] [TARGET...]" >&2
    exit 2
    ;;
esac

if ! cargo fuzz --version >/dev/null 2>&1; then
    echo "== installing cargo-fuzz from crates.io"
    cargo install cargo-fuzz --locked
fi

target_dir_args=()
if [ -n "${CARGO_TARGET_DIR:-}" ]; then
    target_dir_args=(--target-dir "$CARGO_TARGET_DIR")
fi
fuzz=(cargo fuzz run -s none "${target_dir_args[@]}")

log_dir=${FUZZ_LOG_DIR:-$(mktemp -d "${TMPDIR:-/tmp}/stickslip-fuzz-logs.XXXXXX")}
mkdir -p "$log_dir"
# Scratch files of the scene and CSV targets (they read a file path, like the CLI).
STICKSLIP_FUZZ_TMP=$(mktemp -d "${TMPDIR:-/tmp}/stickslip-fuzz-scratch.XXXXXX")
export STICKSLIP_FUZZ_TMP
trap 'rm -rf "$STICKSLIP_FUZZ_TMP"' EXIT

# Input size limits (bytes): a little above the largest seed of each target.
max_len() {
    case "$1" in
    fmu_state) echo 16384 ;;
    weights) echo 8192 ;;
    onnx) echo 4096 ;;
    scene) echo 4096 ;;
    training_csv) echo 8192 ;;
    *) echo 4096 ;;
    esac
}

echo "== seed corpora (fuzz/corpus/<target>/seed-*)"
cargo run --quiet --release --manifest-path fuzz/Cargo.toml --example seeds >/dev/null

echo "== building the fuzz targets"
for t in "${targets[@]}"; do
    cargo fuzz build -s none "${target_dir_args[@]}" "$t" >/dev/null
done

if printf '%s\n' "${targets[@]}" | grep -qx weights; then
    # The shipped weights files (656 kB each) are too large to mutate quickly: they are
    # run once each as inputs; the corpus holds small models cut from them.
    echo "== weights: the shipped files as single inputs"
    if ! "${fuzz[@]}" weights weights/paper-plain.json weights/paper-signed.json \
        >"$log_dir/weights-shipped.log" 2>&1; then
        echo "the shipped weights files fail the weights target, see $log_dir/weights-shipped.log"
        exit 1
    fi
fi

status=0
summary=()
for t in "${targets[@]}"; do
    echo "== fuzzing $t for $seconds s"
    mkdir -p "fuzz/corpus/$t"
    log="$log_dir/$t.log"
    before=$(find "fuzz/corpus/$t" -type f | wc -l)
    result=ok
    "${fuzz[@]}" "$t" "fuzz/corpus/$t" -- \
        -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
        -max_len="$(max_len "$t")" -dict="fuzz/dicts/$t.dict" \
        -print_final_stats=1 >"$log" 2>&1 || result=CRASH
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -n 1)
    last=$(grep -E '^#[0-9]+' "$log" | tail -n 1 || true)
    cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
    ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
    if [ "$result" = CRASH ]; then
        status=1
        artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -n 1)
        echo "   CRASH: $artifact (log $log)"
        grep -m 3 -E "panicked at|ERROR: libFuzzer|SUMMARY" "$log" | sed 's/^/   /' || true
    fi
    if [ "${FUZZ_NO_CMIN:-0}" != 1 ]; then
        # Set-cover merge on edge coverage alone (no hit counts): a few hundred files
        # that reach every edge the corpus reached.
        cargo fuzz cmin -s none "${target_dir_args[@]}" "$t" "fuzz/corpus/$t" \
            -- -set_cover_merge=1 -use_counters=0 -max_len="$(max_len "$t")" -timeout=10 \
            >"$log_dir/$t-cmin.log" 2>&1 ||
            echo "   cmin failed, see $log_dir/$t-cmin.log"
    fi
    after=$(find "fuzz/corpus/$t" -type f | wc -l)
    size=$(du -sk --apparent-size "fuzz/corpus/$t" | cut -f1)
    summary+=("$(printf '%-13s %6ss %11s %9s %7s %7s  %4s -> %4s files (%s kB)  %s' \
        "$t" "$seconds" "${runs:-?}" "${rate:-?}" "${cov:-?}" "${ft:-?}" "$before" "$after" "$size" "$result")")
done

# cmin keeps the smallest inputs; put the (valid, larger) seeds back.
cargo run --quiet --release --manifest-path fuzz/Cargo.toml --example seeds >/dev/null

echo
echo "== summary (logs in $log_dir)"
printf '%-13s %7s %11s %9s %7s %7s  %s\n' target time executions exec/s cov ft "corpus before -> after"
printf '%s\n' "${summary[@]}"
exit "$status"
