#!/usr/bin/env bash
# Installs every Debian 12 package hapticd needs to build, test, benchmark and plot (chromium, headless: the live
# view's picture in the docs), and the live view test's
# client from the npm registry (tests/live_view: @foxglove/ws-protocol and ws, pinned by its package-lock.json).
# Idempotent: packages already present are not reinstalled, and apt is not touched when nothing is missing.
# Works as root or through sudo. Nothing else is ever downloaded: the build uses only these packages.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config ccache git
  libeigen3-dev
  cyclonedds-dev cyclonedds-tools
  liburdfdom-dev libtinyxml-dev
  libboost-dev libboost-filesystem-dev libssl-dev
  libspdlog-dev libfmt-dev
  libyaml-cpp-dev
  libcli11-dev
  libgtest-dev libgmock-dev
  libbenchmark-dev
  liborocos-kdl-dev
  libnlopt-dev
  libmujoco-dev
  libembree-dev libassimp-dev
  rt-tests
  clang-14 libclang-rt-14-dev clang-format-14 lld
  python3 python3-matplotlib python3-dev python3-numpy python3-pytest pybind11-dev
  libfastrtps-dev fastddsgen
  libhdf5-dev python3-h5py
  iproute2
  chromium
  mono-mcs mono-runtime
  python3-websockets
  rosidl-tools python3-rosidl python3-catkin-pkg python3-empy
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js and npm for the live view test: Debian's, unless the machine has a node and npm already (Debian's npm
# package conflicts with the nodejs builds that bring their own npm).
if ! command -v node > /dev/null || ! command -v npm > /dev/null; then
  missing+=(nodejs npm)
fi

# The live view test's npm packages, into tests/live_view/node_modules (again only when the lock file changed).
install_npm_packages() {
  local dir
  dir="$(cd "$(dirname "$0")/.." && pwd)/tests/live_view"
  if [ -f "$dir/node_modules/.package-lock.json" ] && cmp -s "$dir/package-lock.json" "$dir/.installed-lock.json"; then
    echo "install-deps: npm packages of tests/live_view present"
    return
  fi
  echo "install-deps: npm ci in tests/live_view"
  if ! (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error); then
    echo "install-deps: npm ci in tests/live_view failed (the live view test needs it)" >&2
    exit 1
  fi
  cp "$dir/package-lock.json" "$dir/.installed-lock.json"
}

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  install_npm_packages
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
install_npm_packages
