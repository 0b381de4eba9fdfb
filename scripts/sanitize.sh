#!/usr/bin/env bash
# The sanitizer presets on the tests that exercise what they catch best (CI runs this after the full suite):
#   asan (AddressSanitizer + UndefinedBehaviorSanitizer): the safety supervisor with fault injection, the
#     fuzzed session loader and the fuzzed DDS command validation, the device session, the live view's server
#     under its attacks, crafted recordings, the engine socket's parser of untrusted JSON, the engines' worlds' check;
#   tsan (ThreadSanitizer): the DDS end-to-end tests (the bridge's threads, Cyclone's receive thread and its
#     liveliness callbacks, the loop's lock-free hand-offs; the ownership tests with their claimant processes;
#     the device groups' snapshots, requests and group commands; requests racing a scheme switch), groups on loop
#     threads of their own (with the recorder's rings), the bridge's round-trip probe and the scheme switching
#     (loop and monitor threads), the loop on a device's clock (a ticking thread, the loop waiting on its ticks),
#     the C API (its commands handed to the sender thread, against a server process), the engine socket (its
#     thread, the publisher's hand-off and the receiver's requests, with its Node, Python and browser clients);
#   fuzz (libFuzzer with ASan + UBSan): the DDS engine-command validation, the session loader and a teleoperation
#     link's packets into both sides of a link, each for a fixed number of inputs from a fixed seed (FUZZ_RUNS
#     scales them; findings are written to build/fuzz/findings and fail the run).
# All three build with Debian's clang-14 at -O1 and line tables only; the fuzzers are built in the asan build
# (the libraries the fuzzers explore - DDS validation, server core, teleoperation - carry libFuzzer's coverage
# instrumentation too: fuzz/CMakeLists.txt), so the server is compiled twice, not three times.
# Only these targets are built, to keep CI short on small machines.
# Usage: scripts/sanitize.sh [asan|tsan|fuzz]...   (default: all three)
set -euo pipefail
cd "$(dirname "$0")/.."
presets=("$@")
unset HAPTICD_DDS_NETWORK HAPTICD_DDS_CONFIG  # the tests bind to the loopback interface
[ ${#presets[@]} -eq 0 ] && presets=(asan tsan fuzz)
export TSAN_OPTIONS="${TSAN_OPTIONS:-} suppressions=$PWD/tests/tsan.supp halt_on_error=1"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-} halt_on_error=1 print_stacktrace=1"
fuzz() {
  cmake --preset asan > /dev/null
  cmake --build --preset asan --target engine_command_fuzzer session_config_fuzzer teleop_packet_fuzzer
  local out=build/fuzz/findings scale=${FUZZ_RUNS:-1}
  mkdir -p "$out" build/fuzz/corpus/engine_command build/fuzz/corpus/session_config build/fuzz/corpus/teleop_packet
  for f in config/sessions/*.yaml config/sessions/*/*.yaml; do cp "$f" "build/fuzz/corpus/session_config/${f//\//_}"; done
  # -runs bounds the work (deterministic from -seed on a fresh corpus); -max_total_time only guards the time.
  build/asan/bin/engine_command_fuzzer -seed=1 -runs=$((400000 * scale)) -max_total_time=300 -max_len=4096 \
    -artifact_prefix="$out/engine_command-" build/fuzz/corpus/engine_command
  build/asan/bin/session_config_fuzzer -seed=1 -runs=$((20000 * scale)) -max_total_time=300 -max_len=8192 \
    -artifact_prefix="$out/session_config-" build/fuzz/corpus/session_config
  build/asan/bin/teleop_packet_fuzzer -seed=1 -runs=$((200000 * scale)) -max_total_time=120 -max_len=512 \
    -artifact_prefix="$out/teleop_packet-" build/fuzz/corpus/teleop_packet
}

# The asan test preset sets ASAN_OPTIONS=intercept_tls_get_addr=0: up to LLVM 16 the runtime's __tls_get_addr
# interceptor takes a dynamic TLS block that happens to start 16 bytes past a page for a pre-2.25 glibc header and
# reads a made-up range from it, and LeakSanitizer's tracer then crashes at exit ("Tracer caught signal 11") in a
# test that passed - seen once in CI (ForceDimension, which dlopens its plugin and the vendor's stand-in).
for preset in "${presets[@]}"; do
  case "$preset" in
    asan) targets=(safety_test config_fuzz_test command_gate_test device_session_test foxglove_server_test
                   forcedimension_test
                   playback_device_test socket_messages_test world_view_test)
          tests='^(Safety|ConfigFuzz|CommandGate|CommandValidation|DeviceSession|FoxgloveServer|PlaybackDevice|SocketMessages|WorldView|ForceDimension)\.' ;;
    tsan) targets=(dds_engine_test dds_ownership_test dds_groups_test dds_attacks_test separate_loops_test hapticctl
                   hapticd-scene-engine scheme_switching_test round_trip_probe_test device_clock_test c_api_test hapticd
                   forcedimension_test)
          tests='^(DdsEngine|DdsOwnership|DdsGroups|DdsAttacks|SeparateLoops|SchemeSwitching|RoundTripProbe|DeviceClock|CApi|ForceDimension)\.|^engine_socket$' ;;
    fuzz) fuzz ; continue ;;
    *) echo "unknown preset '$preset' (asan, tsan, fuzz)" >&2; exit 2 ;;
  esac
  cmake --preset "$preset" > /dev/null
  cmake --build --preset "$preset" --target "${targets[@]}"
  ctest --preset "$preset" -R "$tests" -j "$(nproc)"
done
