#!/usr/bin/env bash
# Installs what is missing, then configures and builds salsa (Release) into build/release.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --parallel "$(nproc)"
