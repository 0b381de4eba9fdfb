#!/usr/bin/env bash
# A handle device's buttons and gripper reach everything that reports a device: the server's recording (lockstep)
# and, over DDS on the loopback interface, the device's description and state as a client reads them (hapticctl
# list, watch and record, the client library's recording of the states). The device is a Force Dimension omega.7 on
# the project's stand-in of the vendor's SDK, found through the vendor's variable FORCEDIM_SDK, its buttons held
# (mask 5) and its gripper open at the stand-in's 0.3 rad.
# Usage: handle_device_test.sh BIN_DIR SOURCE_DIR WORK_DIR STANDIN_DIR DOMAIN
set -eu
bin=$1 src=$2 work=$3 standins=$4 domain=$5
rm -rf "$work"; mkdir -p "$work"; cd "$work"
fail() { echo "FAIL: $*"; cat server.log 2>/dev/null || true; exit 1; }
source "$src/tests/e2e/session_copy.sh"
export FORCEDIM_SDK="$standins/forcedimension" HAPTICD_DHD_STANDIN="omega.7:10002" HAPTICD_DHD_STANDIN_BUTTONS=5
session="$src/config/sessions/forcedimension/omega-wall.yaml"
# The last value of the CSV column `name` in `file`.
column() { awk -F, -v name="$1" 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == name) c = i } NR > 1 && c { v = $c }
                                 END { print v }' "$2"; }

# The server's own recording, in lockstep (each force call one loop period of the stand-in's physics).
deadline="--set devices.omega.device.parameters.call_deadline_ms=1000"  # the machine's load, not the SDK's
HAPTICD_DHD_STANDIN_STEP=0.0005 timeout 60 "$bin/hapticd" --config "$session" --clock lockstep --duration 1 \
  --record lockstep.h5 $deadline > lockstep.log 2>&1 || fail "lockstep run: $(cat lockstep.log)"
grep -q "device 'omega': ok" lockstep.log || fail "lockstep run: $(cat lockstep.log)"
grep -q "device 'omega': forcedimension omega.7, serial 10002; Force Dimension SDK 3.6.0, .*libdrd.so" lockstep.log ||
  fail "the log at start does not say what the device is: $(grep "device 'omega'" lockstep.log)"
"$bin/hapticctl" export lockstep.h5 --csv > /dev/null || fail "export of the server's recording"
[ "$(column handle.buttons lockstep.omega.csv)" = 5 ] || fail "buttons in the recording: $(head -1 lockstep.omega.csv)"
near() { awk -v x="$1" -v y="$2" 'BEGIN { exit !(x - y < 1e-9 && y - x < 1e-9) }'; }
near "$(column handle.gripper lockstep.omega.csv)" 0.3 || fail "gripper in the recording"
echo "ok: the server's recording holds the buttons and the gripper"

# Over DDS, in real time.
timeout 60 "$bin/hapticd" --config "$session" --dds-domain "$domain" --duration 8 --log-level warn \
  --set server.realtime_priority=0 --set server.lock_memory=false $(loose_watchdogs omega) $deadline \
  --set ros2.domain_id=173 > server.log 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT  # TERM: timeout passes it on (-9 would orphan the server)
ctl() { timeout 20 "$bin/hapticctl" --domain "$domain" --timeout 5 "$@"; }
ctl list | tee list.txt
grep -q "^omega " list.txt || fail "hapticctl list does not show the device"
ctl watch omega --duration 0.3 > watch.txt || fail "hapticctl watch: $(cat watch.txt)"
grep -q "buttons 0x5 gripper 0.300 rad" watch.txt || fail "the watch lines lack the buttons: $(tail -3 watch.txt)"
ctl record omega dds.h5 --duration 0.5 > record.txt || fail "hapticctl record: $(cat record.txt)"
"$bin/hapticctl" export dds.h5 --csv > /dev/null || fail "export of the client's recording"
[ "$(column handle.buttons dds.omega.csv)" = 5 ] || fail "buttons over DDS: $(tail -1 dds.omega.csv)"
near "$(column handle.gripper dds.omega.csv)" 0.3 || fail "gripper over DDS"
echo "ok: the DDS state carries the buttons and the gripper"
# On ROS 2's wire (docs/ros2.md): the handle device's sensor_msgs/Joy - as many buttons as its description has (the
# omega.7: one, held) and the gripper's opening as its axis.
timeout 20 "$bin/ros2_subscriber" 173 omega 1 buttons > joy.txt || fail "the ROS 2 reader: $(cat joy.txt)"
grep -q "^buttons 1 axes 0\.300 frame omega/handle$" joy.txt || fail "the ROS 2 buttons: $(cat joy.txt)"
echo "ok: ROS 2's Joy carries them: $(cat joy.txt)"
wait "$server" || fail "the server exited with $?"
trap - EXIT
echo "3 passed, 0 failed"
