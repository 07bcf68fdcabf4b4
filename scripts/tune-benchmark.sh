#!/usr/bin/env bash
# docs/tuning.md's benchmark: flocking's four numeric parameters tuned for trees found in the
# forest-health scenario (20 drones, 600 s) by the grid of the paper's permutations (3 values per
# parameter: 81 candidates), random search and CMA-ES with racing, each with 410 evaluations on 5
# tuning worlds, then validated on 20 held-out worlds. Usage: scripts/tune-benchmark.sh [OUT] [JOBS]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-results/tune-benchmark}
jobs=${2:-2}
salsa=${SALSA:-$here/build/release/bin/salsa}
mkdir -p "$out"
for method in cmaes grid random; do
  start=$(date +%s)
  # --resume: a stopped benchmark continues where it was (a fresh folder simply starts).
  "$salsa" tune "$here/examples/tune/benchmark/$method.json" --out "$out/$method" --jobs "$jobs" --resume --quiet
  cat "$out/$method/report.txt"
  echo "$method: $(( $(date +%s) - start )) s wall" | tee -a "$out/wall.txt"
done
