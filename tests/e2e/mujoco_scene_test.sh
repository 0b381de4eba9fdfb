#!/usr/bin/env bash
# Two-way over DDS (docs/haptic-scene.md, "A block pushed in MuJoCo"): hapticd-mujoco-scene puts a MuJoCo table and
# block (config/scenes/scene-block.xml) into the server's haptic scene (vishard3/dds-scene.yaml, real time, domain
# DOMAIN), applies the contacts the scene reports to the block and moves it where MuJoCo puts it, at 60 Hz. With
# the hand at rest the block stays; with the simulated operator's hand moving forward (1.5 cm/s from 4 s) it meets
# the block and pushes it across the table in MuJoCo's world.
# Usage: mujoco_scene_test.sh BIN_DIR SOURCE_DIR WORK_DIR DOMAIN
set -u
bin=$1 src=$2 work=$3 domain=$4
rm -rf "$work"; mkdir -p "$work"; cd "$work"
source "$src/tests/e2e/session_copy.sh"
fail() { echo "FAIL: $*"; for f in still.log pushed.log; do echo "--- $f"; cat "$f" 2> /dev/null; done; echo "--- server"; tail -20 server.log; exit 1; }
timeout 60 "$bin/hapticd" --config "$src/config/sessions/vishard3/dds-scene.yaml" --dds-domain "$domain" --duration 16 \
  --log-level info --set server.realtime_priority=0 --set server.lock_memory=false \
  --set devices.vishard3.device.parameters.operator_motion=ramp \
  --set "devices.vishard3.device.parameters.operator_motion_m=[0.015,0,0]" \
  --set devices.vishard3.device.parameters.operator_motion_start_s=4.0 \
  $(loose_watchdogs vishard3) > server.log 2>&1 &
server=$!
trap 'kill $server 2> /dev/null' EXIT
engine() {
  timeout 30 "$bin/hapticd-mujoco-scene" "$src/config/scenes/scene-block.xml" --device vishard3 --domain "$domain" \
    --duration "$1" --watch block
}
moved_x() { sed -n "s/^body 'block' moved \[\([-+0-9.]*\),.*/\1/p" "$1"; }
engine 2 > still.log 2>&1 || fail "the engine failed (at rest)"
m=$(moved_x still.log)
[ -n "$m" ] && awk -v m="$m" 'BEGIN { exit !(m > -0.5 && m < 0.5) }' || fail "the block moved ${m:-?} mm with the hand at rest"
echo "ok: the block stays while the hand rests (moved $m mm along x)"
sleep 1
engine 7 > pushed.log 2>&1 || fail "the engine failed (pushed)"
m=$(moved_x pushed.log)
[ -n "$m" ] && awk -v m="$m" 'BEGIN { exit !(m > 15 && m < 150) }' || fail "the pushed block moved ${m:-?} mm"
echo "ok: the hand pushes the block across MuJoCo's table (moved $m mm along x)"
grep -q "; 0 refused moves" pushed.log || fail "moves were refused"
echo "ok: every move of the block went through"
cat pushed.log
kill -INT "$server"
wait "$server" || fail "the server exited with $?"
trap - EXIT
echo "3 passed, 0 failed"
