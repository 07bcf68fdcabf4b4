#!/usr/bin/env bash
# The main job: set up, build, survey a forest with each built-in behavior, then compare them in a small
# queue (4 behaviors x 2 swarm sizes x 3 paired repeats) and show where the pictures are.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh salsa salsa_plugins  # what the demo runs: not the desktop, nor the test suites
out=${1:-results/demo}
salsa=build/release/bin/salsa
"$salsa" run examples/{flocking,pheromone-avoidance,dynamic-space-partitioning,random-walk}-forest.json --out "$out/surveys" --force
"$salsa" run examples/comparison-queue.json --out "$out/comparison" --force
echo
echo "demo: one folder per behavior in $out/surveys/ (config.json, summary.csv, outcome.csv, drones.csv, targets.csv)"
echo "demo: plots of each survey:    $out/surveys/<test>/plots/*.png (trajectories, found, coverage, speeds, heat map)"
echo "demo: the comparison:          $out/comparison/summary.csv, $out/comparison/comparison.csv"
echo "demo: its plots:               $(ls "$out"/comparison/plots/*.png | tr '\n' ' ')"
