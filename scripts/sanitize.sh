#!/usr/bin/env bash
# The sanitizer presets on the tests that exercise what they catch best (CI runs this after the full suite):
#   asan (AddressSanitizer + UndefinedBehaviorSanitizer): the safety supervisor with fault injection, the
#     fuzzed session loader and the fuzzed DDS command validation, the device session;
#   tsan (ThreadSanitizer): the DDS end-to-end tests (the bridge's threads, Cyclone's receive thread, the
#     loop's lock-free hand-offs) and the scheme switching (loop and monitor threads).
# Only these targets are built, to keep CI short on small machines.
# Usage: scripts/sanitize.sh [asan|tsan]...   (default: both)
set -euo pipefail
cd "$(dirname "$0")/.."
presets=("$@")
[ ${#presets[@]} -eq 0 ] && presets=(asan tsan)
export TSAN_OPTIONS="${TSAN_OPTIONS:-} suppressions=$PWD/tests/tsan.supp halt_on_error=1"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-} halt_on_error=1 print_stacktrace=1"
for preset in "${presets[@]}"; do
  case "$preset" in
    asan) targets=(safety_test config_fuzz_test command_gate_test device_session_test)
          tests='^(Safety|ConfigFuzz|CommandGate|CommandValidation|DeviceSession)\.' ;;
    tsan) targets=(dds_engine_test scheme_switching_test)
          tests='^(DdsEngine|SchemeSwitching)\.' ;;
    *) echo "unknown preset '$preset' (asan, tsan)" >&2; exit 2 ;;
  esac
  cmake --preset "$preset" > /dev/null
  cmake --build --preset "$preset" --target "${targets[@]}"
  ctest --preset "$preset" -R "$tests" -j "$(nproc)"
done
