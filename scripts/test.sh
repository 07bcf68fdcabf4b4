#!/usr/bin/env bash
# Set up, build and run the whole test suite (what CI runs): the Release build, the same suite under
# AddressSanitizer + UBSan, and a short run of every fuzz target (clang + libFuzzer).
#   ./scripts/test.sh            everything (CI)
#   ./scripts/test.sh --quick    the Release suite only
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
ctest --preset release --parallel "$(nproc)"
[ "${1:-}" = "--quick" ] && exit 0

echo "== the suite under AddressSanitizer + UndefinedBehaviorSanitizer"
cmake --preset asan-ubsan >/dev/null
cmake --build --preset asan-ubsan --parallel "$(nproc)"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 LSAN_OPTIONS=suppressions="$PWD/tests/lsan.supp":print_suppressions=0 UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
  ctest --preset asan-ubsan --parallel "$(nproc)"

echo "== fuzz smoke run (scripts/fuzz.sh runs them long)"
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz --parallel "$(nproc)"
ctest --preset fuzz
