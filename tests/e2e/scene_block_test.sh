#!/usr/bin/env bash
# Two-way haptic scene over the engine socket (docs/haptic-scene.md, "A block pushed across a table"): the Python
# example examples/python/block_pusher.py owns the session's scene on config/sessions/vishard3/socket-scene.yaml -
# a table and a block the server renders at loop rate - and moves the block by its own physics at 60 Hz from the
# contacts the server reports. First with the simulated operator's hand at rest (the block must stay), then with the
# hand's target moving forward at 1.5 cm/s from 4 s: the hand meets the block and pushes it across the table, with
# the force of the block's friction (1 kg x 0.3 x 9.81 m/s^2 = 2.94 N) while it slides.
# Usage: scene_block_test.sh BIN_DIR SOURCE_DIR WORK_DIR
set -u
bin=$1 src=$2 work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work"
source "$src/tests/e2e/session_copy.sh"
fail() { echo "FAIL: $*"; for f in still.log pushed.log; do echo "--- $f"; cat "$f" 2> /dev/null; done; echo "--- server"; tail -20 server.log; exit 1; }
py=python3
python3 -c "import websockets" 2> /dev/null || py=/usr/bin/python3
"$py" -c "import websockets" 2> /dev/null || fail "no python3 with the websockets package (scripts/install-deps.sh)"
timeout 60 "$bin/hapticd" --config "$src/config/sessions/vishard3/socket-scene.yaml" --duration 14 --log-level info \
  --set server.realtime_priority=0 --set server.lock_memory=false --set engine_socket.port=0 \
  --set devices.vishard3.device.parameters.operator_motion=ramp \
  --set "devices.vishard3.device.parameters.operator_motion_m=[0.015,0,0]" \
  --set devices.vishard3.device.parameters.operator_motion_start_s=4.0 \
  $(loose_watchdogs vishard3) > server.log 2>&1 &
server=$!
trap 'kill $server 2> /dev/null' EXIT
url=$(socket_url server.log)
[ -n "$url" ] || fail "the server did not say where its engine socket is"
moved() { sed -n 's/^block moved \([0-9.]*\) mm.*/\1/p' "$1"; }
# The hand at rest (it starts moving at 4 s): the block stays where the engine put it.
timeout 20 "$py" "$src/examples/python/block_pusher.py" "$url" 2 > still.log 2>&1 || fail "the engine failed (at rest)"
m=$(moved still.log)
[ -n "$m" ] && awk -v m="$m" 'BEGIN { exit !(m < 0.5) }' || fail "the block moved ${m:-?} mm with the hand at rest"
echo "ok: the block stays while the hand rests (moved $m mm)"
# The hand moves forward from 4 s: it meets the block (3 cm ahead) and pushes it across the table.
sleep 1
timeout 20 "$py" "$src/examples/python/block_pusher.py" "$url" 6 > pushed.log 2>&1 || fail "the engine failed (pushed)"
m=$(moved pushed.log)
[ -n "$m" ] && awk -v m="$m" 'BEGIN { exit !(m > 15 && m < 150) }' || fail "the pushed block moved ${m:-?} mm"
echo "ok: the hand pushes the block across the table (moved $m mm)"
# While it slides, the hand pushes with the block's friction: a second's mean push (the engine prints one a second)
# while the block went on through all of it, within 15 %.
push=$(awk '/^block at/ { x = $3 + 0; if (seen && x - last > 5) p = $(NF - 2); last = x; seen = 1 } END { print p }' pushed.log)
awk -v p="${push:-0}" 'BEGIN { exit !(p > 2.5 && p < 3.4) }' || fail "the sliding block was pushed with ${push:-?} N"
echo "ok: the sliding block is pushed with its friction ($push N against 2.94 N)"
cat pushed.log
kill -INT "$server"
wait "$server" || fail "the server exited with $?"
trap - EXIT
echo "3 passed, 0 failed"
