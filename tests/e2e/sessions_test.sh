#!/usr/bin/env bash
# Every shipped session file checks out, every per-scheme session runs, and the demo session (simulated ViSHaRD3 with the simulated
# operator) runs in lockstep, twice with identical recordings, without a device fault; its recording replayed by
# the playback device through the same scheme (config/sessions/playback.yaml) reproduces it bit for bit.
# The sessions of the commercial devices run on the project's stand-ins of the vendors' SDKs, found as a user's
# SDK is: through the vendor's own variable (FORCEDIM_SDK, OH_SDK_BASE); the DHD stand-in steps one loop period per
# force call in lockstep, the HD stand-in's scheduler runs in real time; the Haply session speaks to the Inverse
# Service stand-in, a process on 127.0.0.1.
# Usage: sessions_test.sh HAPTICD SOURCE_DIR WORK_DIR STANDIN_DIR
set -u
hapticd=$1; src=$2; work=$3; standins=$4
export FORCEDIM_SDK="$standins/forcedimension" HAPTICD_DHD_STANDIN="omega.6:10001,omega.7:10002"
export HAPTICD_DHD_STANDIN_STEP=0.0005
export OH_SDK_BASE="$standins/openhaptics" HAPTICD_HD_STANDIN="Default Device=Touch:220-10001,Right Device=Touch X:330-10002"
rm -rf "$work"; mkdir -p "$work"
# Haply's Inverse Service: the stand-in as a process on a port of this test's own (the sessions' URL is set to it);
# the pair session's two Inverse3s (ids 0A1B and 0C2D) each on a stand-in of its own (one device per stand-in).
haply_port=18101
haply_services=""
for spec in "18101" "18102 0 0 0 0 0A1B" "18103 0 0 0 0 0C2D"; do
  set -- $spec
  "$standins/haply/hapticd-standin-inverse-service" "$@" > "$work/inverse-service-$1.log" 2>&1 &
  haply_services="$haply_services $!"
done
trap 'kill $haply_services 2> /dev/null' EXIT
for port in 18101 18102 18103; do
  for _ in $(seq 50); do grep -q "stand-in on" "$work/inverse-service-$port.log" && break; sleep 0.1; done
done
haply_flags() {
  case "$1" in
    */haply/inverse3-pair.yaml) echo "--set devices.left.device.parameters.url=ws://127.0.0.1:18102" \
                                     "--set devices.right.device.parameters.url=ws://127.0.0.1:18103" ;;
    */haply/*) echo "--set devices.inverse3.device.parameters.url=ws://127.0.0.1:$haply_port" ;;
  esac
}
# The Force Dimension SDK's calls have a deadline (call_deadline_ms, 20 ms); a loaded CI machine can delay the SDK
# thread's wake-up that long, so these runs, which test the sessions and not the machine, give it a second.
fd_flags() {
  case "$1" in
    */forcedimension/*) for d in $(sed -n 's/^  - name: *\([A-Za-z0-9_-]*\).*/\1/p' "$1"); do
                          echo "--set devices.$d.device.parameters.call_deadline_ms=1000"; done ;;
  esac
}
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }

for session in $(find "$src/config/sessions" "$src/config/scenes" -name "*.yaml" | sort); do  # as shipped, playback.yaml too
  if out=$(timeout 30 "$hapticd" --check-config "$session" $(haply_flags "$session") 2>&1); then pass "check-config ${session#$src/config/}"
  else fail "check-config ${session#$src/config/}: $out"; fi
done

# Every per-scheme and multi-device session runs in lockstep for a second (2000 cycles) without a device fault. A fault in the
# 0.2 s shutdown ramp after it is not the scheme's: the unpowered ViSHaRD6 falls under gravity and trips the
# speed monitor (no brakes are simulated).
# Sessions with the DDS interface run on this test's own domain.
dds_flags() { grep -q "^dds:" "$1" && echo "--dds-domain 68"; }
# A teleoperation side runs here alone: its peer never comes (the link waits for it: docs/teleoperation.md); the
# long timeout keeps the test of the scheme alone whatever the link does.
teleop_flags() { grep -q "^teleoperation:" "$1" && echo "--set teleoperation.link_timeout_s=10"; }
for session in $(find "$src/config/sessions" -mindepth 2 -name "*.yaml" ! -name "identify-*" | sort); do
  name=${session#$src/config/sessions/}
  out=$(timeout 60 "$hapticd" --config "$session" --clock lockstep --duration 1 $(dds_flags "$session") \
    $(teleop_flags "$session") $(haply_flags "$session") $(fd_flags "$session") 2>&1)
  # Every device of the session: no fault within the second (a multi-device session reports each), and no group
  # whose hard minimum tripped.
  fault_cycles=$(echo "$out" | grep -oE "FAULT at cycle [0-9]+" | grep -oE "[0-9]+$" || true)
  early=0
  for c in $fault_cycles; do [ "$c" -lt 2000 ] && early=1; done
  if echo "$out" | grep -q "group '.*[1-9][0-9]* trips\?$"; then early=1; fi
  if [ "$early" -eq 0 ] && { echo "$out" | grep -q "': ok" || [ -n "$fault_cycles" ]; }; then
    pass "runs $name"
  else
    fail "runs $name: $(echo "$out" | tail -3)"
  fi
done

for run in 1 2; do
  timeout 60 "$hapticd" --config "$src/config/sessions/demo.yaml" --clock lockstep --duration 1 --dds-domain 68 \
    --record "$work/demo$run.h5" > "$work/demo$run.log" 2>&1 || fail "demo run $run exited $?: $(cat "$work/demo$run.log")"
  # the recordings' data without the machine's timing
  "$(dirname "$hapticd")/hapticctl" export "$work/demo$run.h5" --csv --exclude timing > /dev/null || fail "export of run $run"
done
cmp -s "$work/demo1.vishard3.csv" "$work/demo2.vishard3.csv" && pass "demo lockstep runs identical" \
  || fail "demo recordings differ"
grep -q "device 'vishard3': ok" "$work/demo1.log" && pass "demo device ok" || fail "demo device: $(cat "$work/demo1.log")"

# Playback: the demo's recording replayed through the demo's scheme gives the same recording - every joint,
# torque command, wrench and flag of every cycle (the input is the recorded device's; the chain is deterministic).
replay=(--set "devices.vishard3.device.parameters.recording=$work/demo1.h5")
"$hapticd" --check-config "$src/config/sessions/playback.yaml" "${replay[@]}" > /dev/null 2>&1 && pass "check-config playback.yaml" \
  || fail "check-config playback.yaml: $("$hapticd" --check-config "$src/config/sessions/playback.yaml" "${replay[@]}" 2>&1)"
timeout 60 "$hapticd" --config "$src/config/sessions/playback.yaml" "${replay[@]}" --clock lockstep --duration 1 \
  --dds-domain 68 --record "$work/replay.h5" > "$work/replay.log" 2>&1 || fail "replay exited $?: $(cat "$work/replay.log")"
"$(dirname "$hapticd")/hapticctl" export "$work/replay.h5" --csv --exclude timing > /dev/null || fail "export of the replay"
cmp -s "$work/demo1.vishard3.csv" "$work/replay.vishard3.csv" && pass "the replay reproduces the recording" \
  || fail "the replay differs from the recording: $(cmp "$work/demo1.vishard3.csv" "$work/replay.vishard3.csv")"
if "$hapticd" --check-config "$src/config/sessions/playback.yaml" \
  --set "devices.vishard3.device.parameters.recording=$work/none.h5" > "$work/no-recording.txt" 2>&1; then
  fail "a playback session without its recording checked out"
fi
grep -q "devices\[0\].device.parameters.recording: cannot open" "$work/no-recording.txt" \
  && pass "a missing recording names the file, line and key" || fail "missing recording: $(cat "$work/no-recording.txt")"
[ "$failures" -eq 0 ]
