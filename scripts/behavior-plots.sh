#!/usr/bin/env bash
# The trajectory plots of docs/behaviors.md: each built-in behavior flies 10 drones for 120 s over a
# 400 m forest with 300 trees (seed 7, decision lag 0 as table1 defines it), `salsa plot` draws the test folder, and its trajectories.png is
# copied to docs/img/behavior-<name>.png. Usage: scripts/behavior-plots.sh [salsa executable]
set -euo pipefail
cd "$(dirname "$0")/.."
salsa=${1:-build/release/bin/salsa}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p docs/img
for behavior in flocking pheromone_avoidance dynamic_space_partitioning dynamic_space_partitioning_paper random_walk; do
  params='{}'
  # Table I's separation distance (250 m) exceeds the detection range: a flock needs a shorter one.
  [ "$behavior" = flocking ] && params='{"separation_distance": 60}'
  cat > "$work/$behavior.json" <<EOF
{"name": "$behavior", "behavior": {"name": "$behavior", "params": $params}, "drones": 10,
 "map": {"name": "forest", "params": {"size": 400}}, "targets": {"kind": "tree", "count": 300},
 "time": 120, "log_interval": 0.5, "decision_lag": 0, "seed": 7}
EOF
  "$salsa" run "$work/$behavior.json" --out "$work/$behavior-out" >/dev/null
  "$salsa" plot "$work/$behavior-out/$behavior"
  cp "$work/$behavior-out/$behavior/plots/trajectories.png" "docs/img/behavior-$behavior.png"
  echo "docs/img/behavior-$behavior.png"
done
