#!/usr/bin/env bash
# Installs the dependencies (idempotent) and builds hapticd with a CMake preset.
# Usage: scripts/build.sh [PRESET]   (default: "ci" when CI=true, else "default")
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-$([ "${CI:-}" = "true" ] && echo ci || echo default)}
bash scripts/install-deps.sh
cmake --preset "$preset" > /dev/null
cmake --build --preset "$preset" -j "$(nproc)"
