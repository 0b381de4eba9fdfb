#!/usr/bin/env bash
# Engines editing the session's haptic scene over the engine socket (docs/haptic-scene.md, "Engines edit the
# scene"): config/sessions/vishard3/socket-scene.yaml (the simulated ViSHaRD3, an empty session scene, an engine
# socket on a free loopback port, no DDS) and tests/engine_socket/scene_client.py, a Python engine (websockets):
# claims (one owner; the claim ends with its connection), a wall added that holds the operator's 15 N push, an
# intruder's edits refused, bad and malformed edits refused with their reasons, moves at 60 Hz, a flood of adds
# rate-limited while the loop runs on, a material changed and the wall removed.
# Usage: scene_socket_test.sh BIN_DIR SOURCE_DIR WORK_DIR
set -u
bin=$1 src=$2 work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work"
source "$src/tests/e2e/session_copy.sh"
fail() { echo "FAIL: $*"; echo "--- client"; cat client.log; echo "--- server"; tail -20 server.log; exit 1; }
py=python3
python3 -c "import websockets" 2> /dev/null || py=/usr/bin/python3
"$py" -c "import websockets" 2> /dev/null || fail "no python3 with the websockets package (scripts/install-deps.sh)"
timeout 60 "$bin/hapticd" --config "$src/config/sessions/vishard3/socket-scene.yaml" --duration 40 --log-level info \
  --set server.realtime_priority=0 --set server.lock_memory=false --set engine_socket.port=0 \
  $(loose_watchdogs vishard3) > server.log 2>&1 &
server=$!
trap 'kill $server 2> /dev/null' EXIT
url=$(socket_url server.log)
[ -n "$url" ] || fail "the server did not say where its engine socket is"
timeout 45 "$py" "$src/tests/engine_socket/scene_client.py" "$url" > client.log 2>&1 || fail "the client failed"
cat client.log
kill -INT "$server"
wait "$server" || fail "the server exited with $?"
trap - EXIT
echo "$(grep -c '^ok:' client.log) passed, 0 failed"
