#!/usr/bin/env bash
# The main job: builds both FMUs and the release binary, runs the paper's static check and the paper's
# stick-slip scene at every fidelity level, through the command line and through the FMUs
# with fmpy, and prints the validation tables. Outputs
# (CSV time series, summaries) go to out/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
out="$root/out"
mkdir -p "$out"
bash scripts/system-deps.sh
echo "== fmu-build: target/fmu/2.0/*.fmu (FMI 2.0, with the SSP systems and fmucontainer link lists) and target/fmu/3.0/*.fmu (FMI 3.0)"
# zig and cargo-zigbuild (.venv-zig): fmu-build links the FMU binary for glibc 2.17.
bash scripts/zig-env.sh >/dev/null
cargo run --release -p fmu-build
# --workspace: the same feature set as fmu-build's builds, so nothing is rebuilt.
cargo build --release --workspace --bins
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
export STICKSLIP_BIN="$bin"
"$python" -m stickslip_checks.plot_cli "$out"
echo
echo "== The network: retraining (paper Sec. 3), NeuralFriction.fmu on the test set, scikit-learn peer"
"$python" -m stickslip_checks.training "$out"
echo
echo "== The paper scene through the FMUs with fmpy (validation, both friction laws, coupling)"
"$python" -m stickslip_checks.fmu_scene "$out"
echo
echo "== The paper authors' network (their MATLAB fitrnet, converted to ONNX) in the paper scene beside the analytical law (fmpy)"
"$python" -m stickslip_checks.paper_authors "$out"
echo
echo "== The paper scene under our transient algorithm and the paper authors' (--preset paper / paper-authors), analytical law and their network, every fidelity (command line)"
"$python" -m stickslip_checks.paper_algorithms "$out"
echo
echo "== The learned friction law with memory: its velocity-step response beside the generating rate-and-state law (train-memory), the paper scene with both (command line)"
"$python" -m stickslip_checks.learned_memory "$out"
echo
echo "== Friction with memory in the paper scene: the exponential law, LuGre and rate-and-state side by side (command line, beam fidelity, 3 s)"
"$python" -m stickslip_checks.memory_laws "$out"
echo
echo "== The paper scene through the FMI 2.0 and the FMI 3.0 FMUs side by side (fmpy)"
"$python" -m stickslip_checks.fmi_versions
echo
echo "== The FMI 3.0 FMUs: fmpy validation, the paper scene bit for bit against the FMI 2.0 FMUs, state machine, FMU state, the extra_feature array, time"
"$python" -m pytest -q -p no:cacheprovider python-checks/tests/test_fmi3.py
echo
echo "== System-level co-simulation: coupling error against the monolithic FMU, Jacobi and Gauss-Seidel"
"$python" -m stickslip_checks.cosim_convergence "$out"
echo
echo "== FMI 3.0 events: early return at stick/slip switches and Event Mode, coupling error against FMI 2.0 Gauss-Seidel"
"$python" -m stickslip_checks.cosim_events "$out"
echo
echo "== The coupled systems' SSP files in other masters (the network, the learned law, rate-and-state, LuGre): libcosim, Ecos, fmucontainer, fmpy.ssp"
"$python" -m stickslip_checks.masters "$out"
echo
echo "== Stick-slip map: Dask sweep of StickSlipBeam.fmu over belt speed (LocalCluster, 2 workers)"
"$python" -m stickslip_checks.sweep --out "$out"
echo
echo "== Speed against accuracy: the study grid and its Pareto front"
"$bin" study --out "$out/study"
echo
# The reference of each scene: 40 modes of the 0.005 m mesh, each checked against a run
# with twice the modes at half the step (the table's "reference vs finer" column). The
# full mesh and its half-step check cost about 20 minutes over the ten scenes on 2
# cores; the basis costs 14 s and its check is as tight (docs/speed-accuracy.md).
echo "== fidelity = auto on ten scenes over each whole run, against 40 modes of the 0.005 m mesh at 1e-5 s (checked against 80 modes at 5e-6 s)"
"$bin" study --out "$out/study/auto" --modes --elements --element-sizes \
  --plane-stress-modal 0.005:40 --dts 1e-5 --integrators generalized-alpha \
  --verify-auto 1e-4,1e-5,1e-6
"$python" -m stickslip_checks.study_plot "$out/study"
echo
# Issue 24: a small grid per friction law (the full measurement, 1224 runs, is in
# docs/speed-accuracy.md, "Friction laws with memory"); each law against its own
# reference, 40 modes of the 0.005 m mesh at 5e-6 s (the laws with state need a finer
# step than 1e-5 s for a sub-micrometre reference). 168 runs, 14 s on 2 shared cores.
echo "== Speed against accuracy per friction law: exponential, LuGre, rate-and-state and the learned law with memory, each against its own reference"
"$bin" study --out "$out/study/laws" --modes 3,5,10 --elements 10,20,50 --element-sizes \
  --plane-stress-modal 0.005:40 --dts 1e-4,2e-5,5e-6 \
  --laws exponential,lugre,rate-and-state,neural:weights/rate-and-state-learned.json
"$python" -m stickslip_checks.study_plot "$out/study/laws"
