#!/usr/bin/env bash
# Any vendor (docs/dds-interface.md): an engine built with eProsima Fast DDS from the project's IDL
# (hapticd-fastdds-engine, types by fastddsgen at build time, the client profile config/dds/fastdds-loopback.xml)
# against the server (Cyclone DDS) on loopback, DDS domain 96: it reads the description (names in arrays and the
# fields after them intact), claims the device, answers every state with a coupling command that the server
# applies (none rejected), holds the pushing operator at its wall, releases.
# Usage: fastdds_engine_test.sh HAPTICD FASTDDS_ENGINE SOURCE_DIR WORK_DIR
set -eu
hapticd=$1; engine=$2; src=$3; work=$4
rm -rf "$work"; mkdir -p "$work"
source "$src/tests/e2e/session_copy.sh"  # loose_watchdogs: why, there
"$hapticd" --config "$src/config/sessions/vishard3/dds-coupling.yaml" --dds-domain 96 --duration 7 \
  --stats-json "$work/stats.json" --log-level warn --set server.realtime_priority=0 --set server.lock_memory=false $(loose_watchdogs vishard3) \
  > "$work/server.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT
out=$(timeout 60 "$engine" --profiles "$src/config/dds/fastdds-loopback.xml" --domain 96 --duration 3 --push 15) || {
  echo "FAIL: the Fast DDS engine: $out"; exit 1; }
wait "$server"
trap - EXIT
echo "$out"
fail() { echo "FAIL: $*"; cat "$work/server.log"; exit 1; }
echo "$out" | grep -q "description: vishard3, data model 17, plugin sim, 3 joints \[joint1,joint2,joint3\], schemes \[default/admittance\], deadline 0.050 s, fade 0.020 s" \
  || fail "the description did not arrive intact"
echo "$out" | grep -q "^push: accepted" || fail "the operator request"
echo "$out" | grep -q "release: accepted" || fail "the release"
answered=$(echo "$out" | sed -n 's/^answered \([0-9]*\) states.*/\1/p')
applied=$(echo "$out" | sed -n 's/.*the server applied engine command \([0-9]*\);.*/\1/p')
past=$(echo "$out" | sed -n 's/.*handle \([-0-9.]*\) m past the start.*/\1/p')
# 3 s at 2 kHz: states answered all along (the engine keeps the newest state: on a machine loaded by the tests
# running beside this one it answers fewer than the 6000 published - 2201 seen, and 963 in a cold CI run on a
# fresh clone), and the server applied the engine's commands up to (nearly) the last. Not a rate: that it answers
# at all, and the applied count below, are the claims.
[ "$answered" -gt 200 ] || fail "only $answered states answered"
[ "$applied" -gt $((answered - 50)) ] || fail "the server applied command $applied of $answered"
awk -v x="$past" 'BEGIN { exit !(x > 0.015 && x < 0.03) }' || fail "the wall did not hold: $past m"
grep -q '"commands_rejected": 0' "$work/stats.json" || fail "commands were rejected: $(grep -o '"dds": {[^}]*}' "$work/stats.json")"
grep -q '"fault": "none"' "$work/stats.json" || fail "the device faulted"
echo "1 passed, 0 failed"
