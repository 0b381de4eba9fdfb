#!/usr/bin/env bash
# ROS 2's other default middleware (docs/ros2.md, "Tested"): a Fast DDS participant - rmw_fastrtps's DDS - with
# fastddsgen's types of the rosidl-generated IDL (tests/fastdds/ros2_fastdds_node.cpp, the loopback profile
# config/dds/fastdds-loopback.xml) against the server's ROS 2 topics (Cyclone DDS) in ROS domain 169: the shipped
# dds-coupling session (admittance display) with a ros2 section giving the device to ROS. The node reads the pose,
# the joint states, /tf and, arriving late, the robot description; pushes 6 N along x with wrench commands for 1.5 s
# (the server applies them, none refused); calls the estop service (the device stops) and the recover service
# (it recovers).
# Usage: ros2_fastdds_test.sh HAPTICD NODE SOURCE_DIR WORK_DIR
set -u
hapticd=$1; node=$2; src=$3; work=$4
rm -rf "$work"; mkdir -p "$work"
source "$src/tests/e2e/session_copy.sh"  # loose_watchdogs: why, there
fail() { echo "FAIL: $*"; echo "--- node"; cat "$work/node.log"; echo "--- server"; tail -20 "$work/server.log"; exit 1; }
"$hapticd" --config "$src/config/sessions/vishard3/dds-coupling.yaml" --dds-domain 170 --duration 12 \
  --stats-json "$work/stats.json" --log-level info --set server.realtime_priority=0 --set server.lock_memory=false \
  --set ros2.domain_id=169 --set "ros2.commands=[vishard3]" $(loose_watchdogs vishard3) > "$work/server.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT
timeout 60 "$node" "$src/config/dds/fastdds-loopback.xml" 169 vishard3 6.0 1.5 > "$work/node.log" 2>&1 ||
  fail "the Fast DDS node failed"
kill -INT $server
wait $server
trap - EXIT
cat "$work/node.log"
grep -Eq "^pose: frame world, stamp -?0\.[0-9] s from the wall clock, quaternion norm 1\.0000" "$work/node.log" ||
  fail "the pose"
grep -q "^joint_states: frame vishard3/base, names \[joint1,joint2,joint3\], 3 positions" "$work/node.log" ||
  fail "the joint states"
grep -q "^tf: world -> vishard3/base -> vishard3/handle" "$work/node.log" || fail "the TF tree"
grep -Eq "^robot_description: [0-9]+ bytes, a URDF" "$work/node.log" || fail "the robot description"
grep -q "^twist: frame vishard3/handle" "$work/node.log" || fail "the twist"
grep -q "^wrench: frame vishard3/handle" "$work/node.log" || fail "the operator's wrench"
grep -q "^estop: success 1, 'emergency stop'" "$work/node.log" || fail "the estop service"
grep -q "^recover: success 1, " "$work/node.log" || fail "the recover service"
sent=$(sed -n 's/^wrench_command: \([0-9]*\) sent/\1/p' "$work/node.log")
accepted=$(sed -n 's/.*vishard3: engine commands accepted \([0-9]*\), rejected.*/\1/p' "$work/server.log")
[ -n "$accepted" ] && [ "$accepted" -gt 100 ] || fail "the server accepted ${accepted:-?} of $sent wrench commands"
grep -q '"commands_rejected": 0' "$work/stats.json" || fail "wrench commands were rejected"
grep -q "FAULT emergency_stop" "$work/server.log" || fail "the E-stop did not stop the device"
grep -q "1 fault, 1 recover" "$work/server.log" || fail "the device did not recover"
echo "ok: Fast DDS reads every topic, its wrench commands are applied ($accepted of $sent), its estop and recover calls are answered"
echo "1 passed, 0 failed"
