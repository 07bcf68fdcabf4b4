#!/usr/bin/env bash
# docs/benchmarks.md's trajectory archive figures: the sizes of trajectories.nc and drones.csv at the
# same log interval, and the wall and CPU time (user + system, all threads) of `salsa run` writing
# drones.csv alone, the archive alone, or neither, in alternating runs (so the machine's load falls on
# all three alike). Prints the medians, the cost of writing each file (its run's median less the bare
# run's) and their ratio; on a busy machine the CPU times are the steadier.
# Usage: scripts/archive-benchmark.sh TEST.json [ROUNDS]   (SALSA: the salsa program to time)
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
test=$1
rounds=${2:-5}
salsa=${SALSA:-$here/build/release/bin/salsa}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
declare -A options=([none]="--no-drones-csv" [csv]="" [archive]="--archive --no-drones-csv")
declare -A times=() cpu=()
for round in $(seq "$rounds"); do
  for kind in none csv archive; do
    start=$(date +%s.%N)
    # shellcheck disable=SC2086  # the options are words
    /usr/bin/time -f "%U %S" -o "$out/cpu" "$salsa" run "$test" --out "$out/$kind" --force --quiet --no-plots --threads 1 ${options[$kind]}
    times[$kind]+="$(awk -v a="$(date +%s.%N)" -v b="$start" 'BEGIN {print a - b}') "
    cpu[$kind]+="$(awk '{print $1 + $2}' "$out/cpu") "
  done
done
median() { tr ' ' '\n' <<<"$1" | grep . | sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
name=$(basename "$(ls -d "$out"/csv/*/ | head -1)")  # the test's folder
csv=$(stat -c %s "$out/csv/$name/drones.csv")
nc=$(stat -c %s "$out/archive/$name/trajectories.nc")
none=$(median "${times[none]}"); with_csv=$(median "${times[csv]}"); with_nc=$(median "${times[archive]}")
cpu_none=$(median "${cpu[none]}"); cpu_csv=$(median "${cpu[csv]}"); cpu_nc=$(median "${cpu[archive]}")
echo "test $name: $(grep -c . "$out/csv/$name/drones.csv") lines of drones.csv"
awk -v csv="$csv" -v nc="$nc" -v none="$none" -v c="$with_csv" -v a="$with_nc" -v rounds="$rounds" \
    -v cn="$cpu_none" -v cc="$cpu_csv" -v ca="$cpu_nc" 'BEGIN {
  printf "drones.csv %d bytes, trajectories.nc %d bytes: drones.csv / archive %.2f\n", csv, nc, csv / nc
  printf "median wall s over %d rounds: neither %.2f, drones.csv %.2f, archive %.2f\n", rounds, none, c, a
  printf "writing cost, wall s: drones.csv %.2f, archive %.2f; archive / drones.csv %.2f\n", c - none, a - none, (a - none) / (c - none)
  printf "median CPU s: neither %.2f, drones.csv %.2f, archive %.2f\n", cn, cc, ca
  printf "writing cost, CPU s: drones.csv %.2f, archive %.2f; archive / drones.csv %.2f\n", cc - cn, ca - cn, (ca - cn) / (cc - cn)
}'
