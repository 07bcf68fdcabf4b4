#!/usr/bin/env bash
# Installs what is missing, then configures and builds salsa (Release) into build/release: everything,
# or only the targets named (scripts/demo.sh: the CLI and the built-in plugins).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --parallel "$(nproc)" ${1:+--target "$@"}
