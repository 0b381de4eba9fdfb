#!/usr/bin/env bash
# DDS Security (docs/deployment.md, "A secure lab network"): scripts/make-security.sh makes a CA, the identities
# server, engine (may command vishard3), other (may command another device only) and watcher and the signed
# governance and permissions documents for DDS domain 89; the server runs with its identity (loopback). The
# engine claims the device and answers its states; a client without credentials is not matched (sees no device);
# 'other' sees the device but may not command it, nor may the watcher (their permissions do not cover the device's
# partition: refused with a clear message); the captured payloads
# on the domain's ports show neither the device's name nor its joint names, which the same capture finds in a
# plain run. The round trip with security against the plain one, in the same run. A teleoperation pair with the
# sides' identities (teleop:lab-m=master,remote, teleop:lab-r=remote,master): a second master server - the round-4
# impostor - with the server identity, or with the remote side's, cannot speak for the master (refused at start by
# access control), and the remote reports no packet from anyone but its master. The session's haptic scene: edited by
# an identity that may command every device (scener=*: hapticd-mujoco-scene's objects go in), refused to one that may
# command vishard3 only (its scene topics are not allowed). The session's ROS 2 topics under the server's identity:
# taken by a ROS 2 subscriber with the watcher's credentials, by none without. Skipped (77) without root (the
# capture needs it). Usage: security_test.sh BIN_DIR SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$1 src=$2 work=$3
rm -rf "$work"; mkdir -p "$work"
[ "$(id -u)" -eq 0 ] || { echo "SKIP: capturing packets needs root"; exit 77; }
fail() { echo "FAIL: $*"; exit 1; }
domain=89
ports=(29650 29900)  # 7400 + 250 * 89 and the participants' unicast ports above it
bash "$src/scripts/make-security.sh" "$work/security" $domain engine=vishard3 other=another-device scener=* \
  teleop:lab-m=master,remote teleop:lab-r=remote,master > /dev/null || fail "make-security.sh"
session=$src/config/sessions/vishard3/dds-coupling.yaml
source "$src/tests/e2e/session_copy.sh"  # loose_watchdogs: why, there
secure() { echo "$work/security/$1/cyclonedds.xml"; }
# serve NAME DURATION EXTRA...: the server in the background; its pid in $server.
serve() {  # NAME DURATION EXTRA...
  local name=$1 duration=$2; shift 2
  "$bin/hapticd" --config "$session" --dds-domain $domain --duration "$duration" --stats-json "$work/stats-$name.json" \
    --set server.realtime_priority=0 --set server.lock_memory=false $(loose_watchdogs vishard3) "$@" > "$work/server-$name.log" 2>&1 &
  server=$!
}
round_trip() { python3 -c "import json,sys; r=json.load(open(sys.argv[1]))['dds_round_trip_us']; print(r['count'], r['p50'], r['p99'])" "$1"; }

# ---- plain: the capture sees the names ----
serve plain 7
sleep 0.5
python3 "$src/tests/e2e/sniff_udp.py" 3 "${ports[@]}" vishard3 joint1 > "$work/sniff-plain.txt" &
sniffer=$!
timeout 20 "$bin/hapticd-scene-engine" --domain $domain --duration 5 --wait 5 > "$work/engine-plain.log" 2>&1
wait $sniffer; wait $server
grep -q "found .*vishard3" "$work/sniff-plain.txt" || fail "the capture did not see the plain traffic: $(cat "$work/sniff-plain.txt")"

# ---- secure ----
serve secure 16 --set "dds.cyclone_config=$(secure server)" --set ros2.domain_id=$domain
sleep 0.5
python3 "$src/tests/e2e/sniff_udp.py" 3 "${ports[@]}" vishard3 joint1 > "$work/sniff-secure.txt" &
sniffer=$!
HAPTICD_DDS_CONFIG=$(secure engine) timeout 20 "$bin/hapticd-scene-engine" --domain $domain --duration 5 --wait 5 \
  > "$work/engine-secure.log" 2>&1 || fail "the engine with credentials: $(cat "$work/engine-secure.log")"
wait $sniffer
# The session's ROS 2 topics (docs/ros2.md) under the same identity: a ROS 2 subscriber with the watcher's
# credentials takes them, one without none (after the capture: a participant without credentials discovers in clear).
HAPTICD_DDS_CONFIG=$(secure watcher) timeout 20 "$bin/ros2_subscriber" $domain vishard3 2 > "$work/ros2-watcher.txt" 2>&1 &
ros2_watcher=$!
timeout 20 "$bin/ros2_subscriber" $domain vishard3 2 > "$work/ros2-plain.txt" 2>&1 &
ros2_plain=$!
# Without credentials: not matched. The watcher: sees the device, may not request.
timeout 20 "$bin/hapticctl" --domain $domain --timeout 2 list > "$work/list-plain.txt" 2>&1
HAPTICD_DDS_CONFIG=$(secure watcher) timeout 20 "$bin/hapticctl" --domain $domain --timeout 3 --id watcher list \
  > "$work/list-watcher.txt" 2>&1
HAPTICD_DDS_CONFIG=$(secure watcher) timeout 20 "$bin/hapticctl" --domain $domain --timeout 3 --id watcher claim vishard3 \
  > "$work/claim-watcher.txt" 2>&1
claim_code=$?
HAPTICD_DDS_CONFIG=$(secure other) timeout 20 "$bin/hapticctl" --domain $domain --timeout 3 --id other claim vishard3 \
  > "$work/claim-other.txt" 2>&1
other_code=$?
wait $ros2_watcher $ros2_plain
wait $server
echo "secure engine: $(tail -1 "$work/engine-secure.log")"
echo "ROS 2 topics, the watcher: $(tr '\n' ' ' < "$work/ros2-watcher.txt"); without credentials: $(tr '\n' ' ' < "$work/ros2-plain.txt")"
grep -Eq "^pose [1-9]" "$work/ros2-watcher.txt" || fail "the watcher took no ROS 2 pose: $(cat "$work/ros2-watcher.txt")"
grep -q "^pose 0$" "$work/ros2-plain.txt" || fail "a ROS 2 subscriber without credentials: $(cat "$work/ros2-plain.txt")"
echo "capture, plain:  $(cat "$work/sniff-plain.txt")"
echo "capture, secure: $(cat "$work/sniff-secure.txt")"
grep -q "answered [1-9]" "$work/engine-secure.log" || fail "the engine with credentials answered no state"
grep -q '"fault": "none"' "$work/stats-secure.json" || fail "the device faulted"
grep -q "^packets [1-9].* found -$" "$work/sniff-secure.txt" || fail "plain text in the secure traffic: $(cat "$work/sniff-secure.txt")"
grep -q "no devices on domain $domain" "$work/list-plain.txt" || fail "a client without credentials saw: $(cat "$work/list-plain.txt")"
grep -q "^vishard3 " "$work/list-watcher.txt" || fail "the watcher did not see the device: $(cat "$work/list-watcher.txt")"
[ $claim_code -ne 0 ] && grep -q "may not send requests to 'vishard3'" "$work/claim-watcher.txt" ||
  fail "the watcher's claim: exit $claim_code: $(cat "$work/claim-watcher.txt")"
[ $other_code -ne 0 ] && grep -q "may not send requests to 'vishard3'" "$work/claim-other.txt" ||
  fail "the other device's engine claimed: exit $other_code: $(cat "$work/claim-other.txt")"
echo "watcher's claim: $(cat "$work/claim-watcher.txt")"
read -r n_plain p50_plain p99_plain < <(round_trip "$work/stats-plain.json")
read -r n_secure p50_secure p99_secure < <(round_trip "$work/stats-secure.json")
echo "round trip, plain:  $n_plain samples, p50 $p50_plain us, p99 $p99_plain us"
echo "round trip, secure: $n_secure samples, p50 $p50_secure us, p99 $p99_secure us"
python3 -c "print(f'security / plain: p50 {$p50_secure / $p50_plain:.2f}x, p99 {$p99_secure / $p99_plain:.2f}x')"

# ---- teleoperation: only the sides' identities speak for them ----
teleop() {  # NAME SIDE IDENTITY DURATION: a teleoperation server in the background; its pid in $side_pid
  "$bin/hapticd" --config "$src/config/sessions/teleoperation/$2.yaml" --dds-domain $domain --duration "$4" \
    --set "dds.cyclone_config=$(secure "$3")" --set server.realtime_priority=0 --set server.lock_memory=false \
    $(loose_watchdogs "$2") > "$work/teleop-$1.log" 2>&1 &
  side_pid=$!
}
teleop remote remote lab-r 8; remote_pid=$side_pid
teleop master master lab-m 8; master_pid=$side_pid
sleep 1
teleop impostor-server master server 4; imp1=$side_pid
teleop impostor-remote master lab-r 4; imp2=$side_pid
wait $imp1 $imp2 $master_pid $remote_pid
for i in impostor-server impostor-remote; do
  grep -q "Not Allowed By Security" "$work/teleop-$i.log" ||
    fail "a second master with the identity of '$i' was not refused: $(tail -3 "$work/teleop-$i.log")"
done
grep -q "peer: bound 1 times; 0 packets rejected" "$work/teleop-remote.log" ||
  fail "the remote's link: $(grep "link's peer" "$work/teleop-remote.log")"
grep -q "device 'remote': ok" "$work/teleop-remote.log" || fail "the remote: $(tail -3 "$work/teleop-remote.log")"
echo "teleoperation: $(grep -o "peer: bound.*participant than the bound peer" "$work/teleop-remote.log"); impostors: $(grep -o "cannot create.*Security" "$work/teleop-impostor-server.log")"

# ---- the haptic scene: felt by every device, so edited only by an identity that may command every device ----
session=$src/config/sessions/vishard3/dds-scene.yaml
serve scene 14 --set "dds.cyclone_config=$(secure server)"
sleep 0.5
mirror() {  # IDENTITY: hapticd-mujoco-scene's block on the table, for a moment, with that identity
  HAPTICD_DDS_CONFIG=$(secure "$1") timeout 30 "$bin/hapticd-mujoco-scene" "$src/config/scenes/scene-block.xml" \
    --device vishard3 --domain $domain --duration 1 --wait 8 --id "$1" > "$work/scene-$1.log" 2>&1
}
mirror scener || fail "the identity that may command every device could not edit the scene: $(cat "$work/scene-scener.log")"
grep -q "2 objects in the scene" "$work/scene-scener.log" || fail "the scene: $(cat "$work/scene-scener.log")"
mirror engine && fail "an identity that may command vishard3 only edited the scene: $(cat "$work/scene-engine.log")"
grep -q "Not Allowed By Security" "$work/scene-engine.log" || fail "the refusal: $(cat "$work/scene-engine.log")"
wait $server
echo "haptic scene: 'scener' (every device) edits it; 'engine' (vishard3 only): $(grep -o "cannot create.*Security" "$work/scene-engine.log")"
echo "1 passed, 0 failed"
