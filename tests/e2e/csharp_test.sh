#!/usr/bin/env bash
# The C# bindings (clients/csharp) on Debian's Mono (mono-mcs, mono-runtime; scripts/install-deps.sh installs
# them): the assembly and the Unity sample (against a stand-in of the few UnityEngine types it uses) compile; the
# structs match the C API's committed layout; every error path is a HapticdException with its status; and a C#
# wall engine (Hapticd.Engine) against the server over DDS on loopback (domain DOMAIN): its per-cycle calls make
# no managed garbage, stopped (SIGSTOP) beyond the server's claim hold it is told of its lost claim and claims
# again, and it holds the simulated operator's 15 N push at its wall (about 5 mm past it through the 3000 N/m
# coupling); and the session's haptic scene from C# (a server on vishard3/dds-scene.yaml, domain DOMAIN + 10).
# Unity itself is not run here.
# Usage: csharp_test.sh BIN_DIR LIB_DIR SOURCE_DIR WORK_DIR DOMAIN GENERATED_DIR (NativeTypes.g.cs: the structs,
# generated from idl/hapticd_wire.toml)
set -u
bin=$1 lib=$2 src=$3 work=$4 domain=$5 generated=$6
rm -rf "$work"; mkdir -p "$work"; cd "$work"
source "$src/tests/e2e/session_copy.sh"
command -v mcs > /dev/null && command -v mono > /dev/null ||
  { echo "FAIL: Mono is not installed (mono-mcs, mono-runtime: scripts/install-deps.sh installs them)"; exit 1; }
fail() { echo "FAIL: $*"; for f in engine.log server.log; do [ -f $f ] && { echo "--- $f"; tail -20 $f; }; done; exit 1; }
mcs -unsafe -target:library -out:Hapticd.dll "$src"/clients/csharp/Hapticd/*.cs "$generated/NativeTypes.g.cs" > build.log 2>&1 ||
  fail "the assembly does not compile: $(cat build.log)"
mcs -unsafe -r:Hapticd.dll -out:test.exe "$src/tests/csharp/CSharpClientTest.cs" > build.log 2>&1 ||
  fail "the test does not compile: $(cat build.log)"
mcs -unsafe -target:library -r:Hapticd.dll -out:sample.dll "$src/clients/csharp/unity/Samples/HapticWall.cs" \
  "$src/clients/csharp/unity/Samples/HapticSceneMirror.cs" "$src/tests/csharp/UnityEngineStandIn.cs" > build.log 2>&1 || fail "the Unity sample does not compile: $(cat build.log)"
echo "ok: Hapticd.dll, the test and the Unity samples compile"
export LD_LIBRARY_PATH="$lib" MONO_PATH="$work"
mono test.exe layout "$src/clients/c/abi/hapticd_c.layout" > layout.log 2>&1 || fail "layout: $(grep FAIL layout.log)"
echo "ok: $(grep -c '^ok' layout.log) layout checks"
timeout 60 mono test.exe errors "$domain" > errors.log 2>&1 || fail "errors: $(cat errors.log)"
echo "ok: $(grep -c '^ok' errors.log) error paths"
timeout 60 mono test.exe callbacks > callbacks.log 2>&1 || fail "callbacks: $(cat callbacks.log)"
timeout 60 mono test.exe symbols "$src/clients/c/abi/hapticd_c.symbols" > symbols.log 2>&1 || fail "symbols: $(grep FAIL symbols.log)"
echo "ok: $(grep -c '^ok.*is bound' symbols.log) C functions, each bound in C#"
echo "ok: $(grep -c '^ok' callbacks.log) checks: only static [MonoPInvokeCallback] methods are handed to native code"

timeout 60 "$bin/hapticd" --config "$src/config/sessions/vishard3/dds-coupling.yaml" --dds-domain "$domain" \
  --duration 18 --log-level warn --set server.realtime_priority=0 --set server.lock_memory=false \
  --set dds.claim_hold_s=0.5 $(loose_watchdogs vishard3) > server.log 2>&1 &
server=$!
mono test.exe engine "$domain" vishard3 10 0 > engine.log 2>&1 &  # bounded by its own 10 s
engine=$!
trap 'kill -CONT $engine 2> /dev/null; kill $server $engine 2> /dev/null' EXIT
why=$(freeze_beyond_claim_hold "$engine" engine.log vishard3) || fail "$why"
echo "ok: the C# engine was told of its lost claim and claimed again"
timeout 20 "$bin/hapticctl" --domain "$domain" --timeout 5 operator vishard3 push 15 0 0 0.2 > push.log 2>&1 ||
  fail "the operator's push: $(cat push.log)"
wait "$engine" || fail "the C# engine: $(grep FAIL engine.log)"
grep "garbage\|answered" engine.log
past=$(sed -n 's/.*handle \([-0-9.]*\) m past the start.*/\1/p' engine.log)
awk -v x="$past" 'BEGIN { exit !(x > 0.015 && x < 0.03) }' || fail "the wall did not hold: $past m"
echo "ok: the C# engine's wall holds the 15 N push ($past m past the start)"
wait "$server" || fail "the server exited with $?"
trap - EXIT

# The session's haptic scene from C# (its own server, on the next domain).
timeout 60 "$bin/hapticd" --config "$src/config/sessions/vishard3/dds-scene.yaml" --dds-domain $((domain + 10)) \
  --duration 30 --log-level warn --set server.realtime_priority=0 --set server.lock_memory=false \
  $(loose_watchdogs vishard3) > server.log 2>&1 &
server=$!
trap 'kill $server 2> /dev/null' EXIT
timeout 60 mono test.exe scene $((domain + 10)) > scene.log 2>&1 || { cp scene.log engine.log; fail "scene: $(grep FAIL scene.log)"; }
grep "wall holds" scene.log
echo "ok: $(grep -c '^ok' scene.log) checks of the haptic scene from C#"
kill -INT $server
wait "$server" || fail "the scene's server exited with $?"
trap - EXIT
echo "7 passed, 0 failed"
