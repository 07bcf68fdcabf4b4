#!/usr/bin/env bash
# Takes the screenshots in docs/img/gui-*.png from a real window under xvfb-run (Debian: xvfb xauth),
# with the committed build: ./scripts/gui-screenshots.sh [BUILD_DIR] (default build/release).
# Look at every image before committing it.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
gui=$build/bin/salsa-gui
img=docs/img
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export HOME=$work/home  # no settings from earlier sessions
mkdir -p "$HOME"
shot() { xvfb-run -a -s "-screen 0 1700x1100x24" "$gui" "$@"; }

# The sandbox, and a drone inspected.
shot examples/flocking-forest.json --start --screenshot $img/gui-sandbox.png --after 12
shot examples/dynamic-space-partitioning-forest.json --start --view heat,camera,-trails --select 4 \
  --screenshot $img/gui-inspect.png --after 14

# Two groups, 44 s in: the surveyors' 1.8 Wh batteries ran flat at about 37 s, inspector 9 was failed
# at 20 s (a timed fail.drone) and inspector 11 at 42 s (drone_mtbf); surveyor 2 inspected.
cat > "$work/groups.json" <<'JSON'
{"name": "groups", "groups": [
  {"name": "surveyors", "drones": 6, "drone": {"base": "large", "battery_capacity": 1.8}, "behavior": "pheromone_avoidance",
   "spawn": {"point": [150, 150]}},
  {"name": "inspectors", "drones": 12, "behavior": "random_walk"}],
 "map": {"name": "forest", "params": {"size": 600}}, "targets": {"count": 400}, "time": 300, "seed": 2,
 "failures": {"drone_mtbf": 300}, "changes": [{"time": 20, "set": {"fail.drone": 9}}]}
JSON
shot "$work/groups.json" --start --select 2 --screenshot $img/gui-groups.png --after 44

# Communication links and wind, 20 s in: pheromone avoidance sharing its field over an 80 m radio that
# loses a fifth of the messages, in a 3 m/s wind with gusts; drone 3, whose position sensor is noisy, inspected.
cat > "$work/radio.json" <<'JSON'
{"name": "radio", "behavior": {"name": "pheromone_avoidance", "params": {"sharing": 1}}, "drones": 20,
 "drone": {"base": "small", "position_noise": 2},
 "map": {"name": "forest", "params": {"size": 600}}, "targets": {"count": 400}, "time": 300, "seed": 5,
 "comm": {"range": 80, "loss": 0.2}, "wind": {"velocity": [3, 1], "gusts": {"strength": 1, "time_scale": 10}}}
JSON
shot "$work/radio.json" --start --view links --select 3 --screenshot $img/gui-radio-wind.png --after 20

# Queue mode, 1.6 s into a run of the comparison queue.
shot --queue examples/comparison-queue.json --run-queue "$work/results" --screenshot $img/gui-queue.png --after 1.6

# Tune mode, 20 s into CMA-ES tuning flocking's parameters (its defaults: every declared parameter,
# 200 evaluations on 5 worlds) for trees found by 10 drones in a 400 m forest in 60 s.
cat > "$work/small-forest.json" <<'JSON'
{"name": "small-forest", "behavior": "flocking", "drones": 10, "drone": "small",
 "map": {"name": "forest", "params": {"size": 400}}, "targets": {"kind": "tree", "count": 200}, "time": 60, "seed": 3}
JSON
shot "$work/small-forest.json" --run-tune "$work/tune" --screenshot $img/gui-tune.png --after 20

# The map creator: the warehouse map with one self-crossing polygon added (flagged red).
python3 - "$work/warehouse-edited.json" <<'PY'
import json, sys
m = json.load(open("examples/maps/warehouse.json"))
m["obstacles"].append([[240, 40], [280, 70], [280, 40], [240, 70]])
json.dump(m, open(sys.argv[1], "w"))
PY
shot --edit-map "$work/warehouse-edited.json" --screenshot $img/gui-map-creator.png --after 1.5

# Plugins: the dialog with a refused plugin, then a behavior rebuilt while it runs (tests/plugins/reload.cpp,
# version 1 flies along +x, version 2 along -x), written over the loaded file 6 s in.
plugins=$work/plugins
mkdir -p "$plugins"
cp "$build"/tests/test-plugins/reload-v1/*.so "$plugins/reload.so"
cp "$build"/tests/test-plugins/abi99/*.so "$plugins/"
shot --plugin-dir "$plugins" --show-plugins --screenshot $img/gui-plugins.png --after 2
rm "$plugins"/libtest_abi99.so
cat > "$work/reload.json" <<'JSON'
{"name": "reload", "behavior": "test_reload", "drones": 12, "map": {"name": "empty", "params": {"size": 200}},
 "targets": {"kind": "tree", "count": 300, "params": {"radius": 1.5}}, "time": 600, "seed": 3, "decision_lag": 0}
JSON
shot "$work/reload.json" --plugin-dir "$plugins" --start --select 0 --screenshot $img/gui-reload.png --after 12 &
sleep 6
cat "$build"/tests/test-plugins/reload-v2/*.so > "$plugins/reload.so"  # in place, as a linker writes it
wait
ls -l $img/gui-*.png
