#!/usr/bin/env bash
# Runs one libFuzzer target: fuzz-one.sh FUZZER SECONDS WORKDIR SEED_DIR... (see docs/reliability.md).
# New interesting inputs go to WORKDIR/corpus; a crash leaves WORKDIR/crash-* and fails the run.
set -euo pipefail
fuzzer=$(realpath "$1") seconds=$2 work=$(realpath -m "$3")
shift 3
mkdir -p "$work/corpus"
seeds=()
for d in "$@"; do [ -d "$d" ] && seeds+=("$(realpath "$d")"); done
cd "$work"
exec "$fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=4096 -max_len=200000 \
  -print_final_stats=1 -artifact_prefix="$work/" corpus "${seeds[@]}"
