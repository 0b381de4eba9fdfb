#!/usr/bin/env bash
# Installs the dependencies (idempotent), builds hapticd with a CMake preset and, for the default and ci presets,
# installs it (programs, libraries, the SDK, the Python package) to HAPTICD_PREFIX (default /usr/local; with
# HAPTICD_INSTALL=0 nothing is installed). The Python package is built for one interpreter (Debian's python3
# unless -DPython3_EXECUTABLE says otherwise, cmake/HapticdPython.cmake); after installing, this says plainly
# whether the python3 first on your PATH imports it, and what to do when it does not.
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

# Which Python: the package is built for one interpreter; say whether the user's python3 is that one.
built_for=$("build/$preset/bin/hapticd-python" --which 2> /dev/null || true)
[ -n "$built_for" ] && [ -d "build/$preset/python/hapticd" ] || exit 0
if ! command -v python3 > /dev/null; then
  echo "build: the Python package is built for $built_for (no python3 on your PATH); run Python scripts with hapticd-python"
elif why=$(cd / && python3 -c "import hapticd" 2>&1); then
  echo "build: your python3 ($(command -v python3)) imports the hapticd package"
else
  direct="  - or use that interpreter directly: $built_for my_engine.py"
  if ! (cd / && "$built_for" -c "import hapticd" > /dev/null 2>&1); then
    package=$(find "$prefix/lib" -maxdepth 4 -type d -path '*-packages/hapticd' 2> /dev/null | head -n 1)
    direct="  - or that interpreter with the package's folder: PYTHONPATH=$(dirname "${package:-$prefix/lib/python3/dist-packages/hapticd}") $built_for my_engine.py"
  fi
  cat << EOF
build: note - your python3 ($(command -v python3), $(python3 --version 2>&1)) cannot import the hapticd package:
  ${why##*$'\n'}
  The package is built for $built_for, which has NumPy, Matplotlib, h5py and pytest from Debian. Either
  - run your scripts with hapticd-python (that interpreter, the package on its path): hapticd-python my_engine.py
$direct
  - or build for yours (it needs NumPy; the tests also pytest and h5py):
    cmake --preset $preset -DPython3_EXECUTABLE=$(command -v python3) && scripts/build.sh $preset
  The programs (hapticd-plot-recording, hapticd-eval's report) name their interpreter themselves.
EOF
fi
