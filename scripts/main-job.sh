#!/usr/bin/env bash
# The main job: builds the release binary, runs the paper's static check and the paper's
# stick-slip scene at every fidelity level, and prints the validation table. Outputs
# (CSV time series, summaries) go to out/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
out="$root/out"
mkdir -p "$out"
cargo build --release --bins
bin="$root/target/release/stickslip"

echo "== Static check (paper Sec. 2.1): tip load 50 N, plane stress at element size 0.02 m"
"$bin" static --fidelity plane-stress --element-size 0.02
echo
echo "== Mesh convergence (paper Fig. 1b)"
"$bin" static --convergence --out "$out/mesh_convergence.csv"
echo
for fidelity in modal beam plane-stress; do
  for law in analytical neural-plain neural-signed; do
    case "$law" in
      analytical) args=(--friction analytical) ;;
      neural-plain) args=(--friction neural --weights weights/paper-plain.json) ;;
      neural-signed) args=(--friction neural --weights weights/paper-signed.json) ;;
    esac
    echo "== Paper scene: $fidelity, $law friction"
    "$bin" simulate --fidelity "$fidelity" "${args[@]}" \
      --out "$out/paper_${fidelity}_${law}.csv" \
      --summary-json "$out/paper_${fidelity}_${law}.json"
    echo
  done
done
python="$(bash scripts/python-env.sh)"
"$python" python-checks/plot_cli.py "$out"
