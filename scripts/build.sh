#!/usr/bin/env bash
# Installs the dependencies (idempotent), builds hapticd with a CMake preset and, for the default and ci presets,
# installs it (programs, libraries, the SDK, the Python package) to HAPTICD_PREFIX (default /usr/local; with
# HAPTICD_INSTALL=0 nothing is installed). Debian's python3 finds the package there: python3 -c "import hapticd".
# Usage: scripts/build.sh [PRESET]   (default: "ci" when CI=true, else "default")
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-$([ "${CI:-}" = "true" ] && echo ci || echo default)}
bash scripts/install-deps.sh
cmake --preset "$preset" > /dev/null
cmake --build --preset "$preset" -j "$(nproc)"

case "$preset" in default | ci) ;; *) exit 0 ;; esac
[ "${HAPTICD_INSTALL:-1}" = "0" ] && exit 0
prefix=${HAPTICD_PREFIX:-/usr/local}
sudo_cmd=()
if [ ! -w "$prefix" ] && [ "$(id -u)" -ne 0 ]; then
  if ! command -v sudo > /dev/null; then
    echo "build: not installed (no write access to $prefix and no sudo); use PYTHONPATH=build/$preset/python" >&2
    exit 0
  fi
  sudo_cmd=(sudo)
fi
"${sudo_cmd[@]}" cmake --install "build/$preset" --prefix "$prefix" > "build/$preset/install.log"
echo "build: installed to $prefix ($(wc -l < "build/$preset/install.log") files; build/$preset/install.log)"
