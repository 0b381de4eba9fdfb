#!/usr/bin/env bash
# Quick start, command 2: install dependencies, build, run the whole test suite.
# Usage: scripts/test.sh [PRESET]   (default: "ci" when CI=true, else "default"; also: asan, tsan)
set -euo pipefail
cd "$(dirname "$0")/.."
preset=${1:-$([ "${CI:-}" = "true" ] && echo ci || echo default)}
bash scripts/build.sh "$preset"
# The tests bind to the loopback interface whatever the shell says (the LAN test sets its own, in its namespaces).
unset HAPTICD_DDS_NETWORK HAPTICD_DDS_CONFIG
# Cyclone DDS is not built with ThreadSanitizer: its internals are suppressed, ours are not.
export TSAN_OPTIONS="${TSAN_OPTIONS:-} suppressions=$PWD/tests/tsan.supp"
ctest --preset "$preset" -j "$(nproc)"
