#!/usr/bin/env bash
# Fuzzes salsa's readers of untrusted input with libFuzzer (clang): scripts/fuzz.sh [SECONDS] [NAME...]
# NAME is a target of fuzz/ without its prefix (elf, test_json, map_json, drone_json, names, tune_json); default all,
# SECONDS each (default 600). A crash is copied to fuzz/findings/NAME/, where every build then replays
# it as a regression test (fuzz_replay_NAME); fix it, then commit the finding.
set -uo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
shift || true
bash scripts/setup.sh
cmake --preset fuzz >/dev/null && cmake --build --preset fuzz --parallel "$(nproc)" || exit 2
names=("$@")
if ((${#names[@]} == 0)); then
  for f in fuzz/fuzz_*.cpp; do n=${f#fuzz/fuzz_}; names+=("${n%.cpp}"); done
fi
status=0
for name in "${names[@]}"; do
  work=build/fuzz/fuzz/work/$name
  echo "== fuzz_$name for $seconds s"
  if ! scripts/fuzz-one.sh "build/fuzz/bin/fuzz_$name" "$seconds" "$work" "fuzz/seeds/$name" "fuzz/findings/$name"; then
    status=1
    mkdir -p "fuzz/findings/$name"
    for crash in "$work"/crash-* "$work"/timeout-* "$work"/oom-*; do
      [ -e "$crash" ] && cp "$crash" "fuzz/findings/$name/" && echo "finding: fuzz/findings/$name/$(basename "$crash")"
    done
  fi
done
exit $status
