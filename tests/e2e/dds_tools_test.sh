#!/usr/bin/env bash
# End to end with separate processes on the loopback interface: the server (real-time clock), hapticctl, the
# plain-C engine built from the IDL alone, and the scene engine killed with SIGKILL.
# Usage: dds_tools_test.sh BIN_DIR SOURCE_DIR WORK_DIR DOMAIN
set -euo pipefail
bin=$1 src=$2 work=$3 domain=$4
mkdir -p "$work"
cd "$work"
ctl() { timeout 20 "$bin/hapticctl" --domain "$domain" --timeout 5 "$@"; }
fail() { echo "FAIL: $*"; cat server.log || true; exit 1; }

source "$src/tests/e2e/session_copy.sh"
session_copy "$src/config/sessions/vishard3/dds-coupling.yaml" "$src" session.yaml
timeout 60 "$bin/hapticd" --config session.yaml --dds-domain "$domain" \
  --duration 12 > server.log 2>&1 &
server=$!
trap 'kill -9 $server 2>/dev/null || true; kill -9 ${engine:-} 2>/dev/null || true' EXIT

ctl list | tee list.txt
grep -q "^vishard3 .*3 joints" list.txt || fail "hapticctl list does not show the device"

# The plain-C engine claims, answers 500 states with its floor, releases.
timeout 30 "$bin/hapticd-minimal-c-engine" "$src/config/dds/cyclonedds-loopback.xml" vishard3 "$domain" 500 | tee c.txt
grep -q "answered 500 states" c.txt || fail "the C engine did not answer"

# Requests: a scheme that does not exist is refused; a parameter is set; the operator is driven.
if ctl scheme vishard3 no-such-scheme; then fail "an unknown scheme was accepted"; fi
ctl set vishard3 virtual_model.damping_n_s_per_m 20 20 20 || fail "set parameter refused"
ctl get vishard3 virtual_model.damping_n_s_per_m | tee get.txt
grep -q "^damping_n_s_per_m = \[20, 20, 20\]" get.txt || fail "get does not show the value set"
if ctl set vishard3 virtual_model.coupling 0; then fail "a parameter that is not tunable was set"; fi
ctl operator vishard3 push 3 0 0 0.2 || fail "operator push refused"

# Record, and watch while an engine dies: the watcher sees the engine's deadline missed.
ctl record vishard3 rec.csv --duration 0.5
[ "$(wc -l < rec.csv)" -gt 100 ] || fail "recorded too few states"
"$bin/hapticd-scene-engine" --domain "$domain" > engine.txt 2>&1 &
engine=$!
ctl watch vishard3 --rate 4 --duration 2.5 > watch.txt &
watcher=$!
sleep 1.2
grep -q "claimed" engine.txt || fail "the scene engine did not claim the device"
kill -9 "$engine"
wait "$watcher" || true
cat watch.txt
grep -q "owner scene-engine" watch.txt || fail "the watcher never saw the engine own the device"
grep -q "event engine stale" watch.txt || fail "no stale-engine event after the engine was killed"

# E-stop: the device goes to its safe state; a watcher started afterwards still gets the fault report with the
# cycles before the stop (transient-local); the device stays safe until `hapticctl recover`, then runs again;
# the session ends with exit code 3 (a device faulted during the session, even though it recovered) and the
# final report lists the stop and the recovery.
ctl estop vishard3 || fail "e-stop refused"
ctl watch vishard3 --rate 4 --duration 1 > fault.txt || true
cat fault.txt
grep -q "^fault report 1: emergency_stop at cycle [0-9]* (emergency stop), 50 cycles of history" fault.txt ||
  fail "the watcher got no fault report"
grep -q " SAFE " fault.txt || fail "the watcher never saw the device in its safe mode"
ctl recover vishard3 || fail "recovery refused"
sleep 0.5
ctl watch vishard3 --rate 4 --duration 0.6 > recovered.txt || true
grep -q "running" recovered.txt || fail "the device did not run again after the recovery"
set +e
wait "$server"
code=$?
set -e
trap - EXIT
grep -q "fault emergency_stop at cycle" server.log || fail "the server log does not mention the emergency stop"
grep -q "recovered from emergency_stop on request" server.log || fail "the server log does not mention the recovery"
grep -q "device 'vishard3': 1 fault, 1 recovery; running at the end" server.log || fail "the final report does not count the fault"
grep -q "FAULT emergency_stop at cycle" server.log || fail "the final report does not list the stop"
grep -q "recovered from emergency_stop at cycle" server.log || fail "the final report does not list the recovery"
[ "$code" -eq 3 ] || fail "server exit code $code, expected 3 (a device faulted during the session)"
echo "dds tools: ok"
