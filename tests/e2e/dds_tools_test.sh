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
  --duration 16 > server.log 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true; kill -9 ${engine:-} 2>/dev/null || true' EXIT  # TERM: timeout passes it on

ctl list | tee list.txt
grep -q "^vishard3 .*3 joints" list.txt || fail "hapticctl list does not show the device"
# The domain from HAPTICD_DOMAIN, and the options after the subcommand.
HAPTICD_DOMAIN=$domain timeout 20 "$bin/hapticctl" list --timeout 5 | grep -q "^vishard3 " ||
  fail "hapticctl list with HAPTICD_DOMAIN and an option after the subcommand"
"$bin/hapticctl" --help | grep -q -- "--timeout FLOAT=2 " || fail "the help does not show the defaults"

# The plain-C engine claims, answers 500 states with its floor, releases.
timeout 30 "$bin/hapticd-minimal-c-engine" "$src/config/dds/cyclonedds-loopback.xml" vishard3 "$domain" 500 | tee c.txt
grep -q "answered 500 states" c.txt || fail "the C engine did not answer"

# Requests: a scheme that does not exist is refused; a parameter is set; the operator is driven.
if ctl scheme vishard3 no-such-scheme > scheme.txt; then fail "an unknown scheme was accepted"; fi
grep -q "no scheme named 'no-such-scheme' (schemes: default)" scheme.txt || fail "the refusal does not list the schemes: $(cat scheme.txt)"
ctl set vishard3 virtual_model.damping_n_s_per_m 20 20 20 || fail "set parameter refused"
ctl get vishard3 virtual_model.damping_n_s_per_m | tee get.txt
grep -q "^virtual_model.damping_n_s_per_m = \[20, 20, 20\] N s/m$" get.txt || fail "get does not show the value set"
grep -q "^  list of reals; bounds >= 0; tunable at run time$" get.txt || fail "get does not show the bounds and tunability"
if ctl get vishard3 controller.no_such > get-bad.txt; then fail "get of an unknown parameter was accepted"; fi
grep -q "has no parameter 'no_such' (" get-bad.txt || fail "the refusal does not list the parameters: $(cat get-bad.txt)"
# Every parameter of every stage, with the value in effect: the device's, the virtual model's, the controller's,
# and the safety stage's; --tunable keeps those that are.
ctl params vishard3 > params.txt || fail "params refused"
grep -q "^NAME  *VALUE  *UNIT  *BOUNDS  *TUNABLE  *DESCRIPTION" params.txt || fail "params has no header"
grep -q "^virtual_model.damping_n_s_per_m  *\[20, 20, 20\]  *N s/m  *>= 0  *yes " params.txt ||
  fail "params does not show the value set with unit, bounds and tunability"
grep -q "^device.substep_hz  *20000  *Hz  *2000 to 1000000  *no " params.txt || fail "params lacks the device's parameters"
grep -q "^safety.passivity_control  *false  " params.txt || fail "params lacks the safety stage"
ctl params vishard3 --tunable > tunable.txt
grep -q "^device\." tunable.txt && fail "params --tunable shows a parameter that is not tunable"
grep -q "^virtual_model.mass_kg " tunable.txt || fail "params --tunable lacks a tunable parameter"
if ctl set vishard3 virtual_model.coupling 0; then fail "a parameter that is not tunable was set"; fi
ctl operator vishard3 push 3 0 0 0.2 || fail "operator push refused"

# An engine that ends and releases the device cleanly is not "stale": its forces fade, no stale flag or event.
ctl watch vishard3 --rate 20 --duration 2.5 > clean.txt &
watcher=$!
timeout 10 "$bin/hapticd-scene-engine" --domain "$domain" --duration 1 > engine-clean.txt 2>&1 ||
  fail "the scene engine failed: $(cat engine-clean.txt)"
wait "$watcher" || true
grep -q "event owner: - - scene-engine released the device" clean.txt || fail "no release event: $(cat clean.txt)"
grep -q "owner scene-engine .*engine_active" clean.txt || fail "the watcher never saw the engine active"
if grep -q "engine_stale" clean.txt; then fail "a clean release showed the engine as stale: $(cat clean.txt)"; fi

# Record, and watch while an engine dies: the watcher sees the engine's deadline missed.
# hapticctl record writes the server's recording format (HDF5): the same export reads it.
if ctl record vishard3 rec.csv --duration 0.1 2> csv-refused.txt; then fail "record to .csv was accepted"; fi
grep -q "a recording is an HDF5 file, named .h5 or .hdf5; for CSV record to rec.h5, then hapticctl export it" csv-refused.txt || fail "record to .csv: $(cat csv-refused.txt)"
ctl record vishard3 rec.h5 --duration 0.5 | tee record.txt
"$bin/hapticctl" export rec.h5 --csv > /dev/null || fail "the client's recording does not export"
[ "$(wc -l < rec.vishard3.csv)" -gt 100 ] || fail "recorded too few states"
head -1 rec.vishard3.csv | grep -q "^cycle,time_s,joints.position.joint1,.*handle.pose.x," ||
  fail "the client's recording lacks the schema's columns: $(head -1 rec.vishard3.csv)"
"$bin/hapticd-scene-engine" --domain "$domain" > engine.txt 2>&1 &
engine=$!
ctl watch vishard3 --rate 4 --duration 2.5 > watch.txt &
watcher=$!
sleep 1.2
grep -q "claimed" engine.txt || fail "the scene engine did not claim the device"
kill -9 "$engine"
wait "$watcher" || true
cat watch.txt
grep -q "^vishard3 t=.*owner scene-engine .*flags .*engine_active" watch.txt ||
  fail "the watcher never saw the engine own the device (its lines named, flags by name)"
grep -q "event engine_stale" watch.txt || fail "no stale-engine event after the engine was killed"

# E-stop: the device goes to its safe state; a watcher started afterwards still gets the fault report with the
# cycles before the stop (transient-local); the device stays safe until `hapticctl recover`, then runs again;
# the session ends with exit code 3 (a device faulted during the session, even though it recovered) and the
# final report lists the stop and the recovery.
ctl estop vishard3 || fail "e-stop refused"
ctl watch vishard3 --rate 4 --duration 1 > fault.txt || true
cat fault.txt
grep -q "^vishard3 fault report 1 (from before this watch): emergency_stop at cycle [0-9]* (emergency stop), 50 cycles of history" fault.txt ||
  fail "the watcher got no fault report, or did not mark it as from before the watch"
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

# Device groups: a dual-arm session's group is listed; a group claim holds both arms, a second claimant gets
# none; a group E-stop stops both; a group recovery by another client than the stopper is refused;
# `estop --all` stops every device.
sed -e "s|\.\./\.\./urdf/|$src/config/urdf/|" \
    -e 's|^  - name: \(left\|right\)$|  - name: \1\n    safety: {max_consecutive_overruns: 2000, max_stall_s: 1.0}|' \
    "$src/config/sessions/dual-arm/vishard3-pair.yaml" > pair.yaml  # session_copy, for the devices only
timeout 60 "$bin/hapticd" --config pair.yaml --dds-domain "$domain" --duration 20 > server.log 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true; kill -9 ${holder:-} 2>/dev/null || true' EXIT
ctl groups | tee groups.txt
grep -q "^table .*devices: left, right; hard minimum 0.03 m, repulsion from 0.1 m" groups.txt ||
  fail "hapticctl groups does not show the pair's group"
timeout 20 "$bin/hapticctl" --domain "$domain" --id holder claim --group table --hold 6 > holder.txt &
holder=$!
sleep 1.5
grep -q "accepted: claimed left, right" holder.txt || fail "the group claim did not take both arms"
if ctl claim --group table; then fail "a second group claim was accepted"; fi
ctl claim right | tee single.txt || true
grep -q "refused: claimed by 'holder'" single.txt || fail "a single arm of a claimed group could be claimed"
ctl estop --group table | tee stop.txt || fail "group e-stop refused"
grep -q "accepted: stopped left, right" stop.txt || fail "the group e-stop did not name both arms"
# The stop holds until its stopper (here the id "hapticctl", whose one-shot process has left) releases it: a
# client under another id, the group's owner among them, recovers nothing.
if ctl --id bystander recover --group table > recover.txt; then fail "another client recovered the stopped group"; fi
grep -q "none recovered.*stopped by 'hapticctl'" recover.txt || fail "the refused group recovery does not say why: $(cat recover.txt)"
ctl estop --all | tee all.txt || fail "estop --all refused"
grep -q "accepted: stopped left, right" all.txt || fail "estop --all did not stop every device"
kill "$holder" 2>/dev/null || true  # TERM: timeout passes it on to hapticctl
kill -INT "$server"
wait "$server" || true
trap - EXIT
grep -q "device 'left' fault emergency_stop" server.log || fail "the server log does not show the group e-stop"
echo "dds tools: ok"
