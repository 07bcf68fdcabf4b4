#!/usr/bin/env bash
# The main job: set up, build, then a small forest survey with each built-in behavior.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
out=${1:-results/demo}
build/release/bin/salsa run examples/*.json --out "$out" --force
echo "demo: one folder per behavior in $out/ (summary.csv, drones.csv, targets.csv, config.json)"
