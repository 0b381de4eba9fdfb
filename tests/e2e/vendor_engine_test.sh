#!/usr/bin/env bash
# The scene engine's wall rendered over DDS on each vendor's device (the project's stand-ins of the vendors' SDKs
# and service), as a lab would run it: the shipped engine-coupling session (impedance display, the server's
# coupling spring-damper to the engine's proxy) in real time on the loopback interface, and
# hapticd-scene-engine claiming the device. Once the engine holds the device, the stand-in's hand pushes into the
# engine's wall (x = +30 mm from the start) with a constant force F, and lets go after 2.8 s. Checked from 1 s to
# 2 s after the first contact:
# the rendered force balances the hand (within 10 %), the handle rests a penetration F / K_coupling past the wall
# (within 15 %), and the handle's buttons reach the DDS state (hapticctl watch). The figures are printed.
# Usage: vendor_engine_test.sh BIN_DIR SOURCE_DIR WORK_DIR STANDIN_DIR DOMAIN
set -u
bin=$1 src=$2 work=$3 standins=$4 domain=$5
rm -rf "$work"; mkdir -p "$work"; cd "$work"
source "$src/tests/e2e/session_copy.sh"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pids=""
trap 'kill $pids 2> /dev/null' EXIT
export HAPTICD_STANDIN_HAND_WHEN="$work/push"  # the stand-ins' hands push while this file exists
ctl() { timeout 20 "$bin/hapticctl" --domain "$domain" --timeout 5 "$@"; }

# run VENDOR DEVICE SESSION HAND_N STIFFNESS BUTTONS_SHOWN [--set ...]
run() {
  local vendor=$1 device=$2 session=$3 hand=$4 stiffness=$5 buttons=$6
  shift 6
  rm -f "$work/push"
  timeout 60 "$bin/hapticd" --config "$src/config/sessions/$session" --dds-domain "$domain" --duration 10 \
    --log-level warn --set server.realtime_priority=0 --set server.lock_memory=false $(loose_watchdogs "$device") \
    "$@" > "$vendor-server.log" 2>&1 &
  local server=$!
  pids="$pids $server"
  timeout 60 "$bin/hapticd-scene-engine" --device "$device" --domain "$domain" --wait 15 --duration 5 \
    --csv "$vendor.csv" > "$vendor-engine.log" 2>&1 &
  local engine=$!
  pids="$pids $engine"
  for _ in $(seq 150); do grep -q "claimed" "$vendor-engine.log" && break; sleep 0.1; done
  grep -q "claimed" "$vendor-engine.log" || { fail "$vendor: the engine did not claim: $(cat "$vendor-engine.log")"; return; }
  sleep 0.3
  touch "$work/push"
  sleep 1
  ctl watch "$device" --duration 0.3 > "$vendor-watch.txt" 2>&1
  grep -q "buttons $buttons" "$vendor-watch.txt" || fail "$vendor: buttons over DDS: $(tail -2 "$vendor-watch.txt")"
  sleep 1.5
  rm -f "$work/push"  # the hand lets go while the engine still holds the device (a free handle pushed on speeds up)
  wait "$engine" || fail "$vendor: the engine exited with $?: $(tail -3 "$vendor-engine.log")"
  wait "$server" || fail "$vendor: the server exited with $?: $(tail -3 "$vendor-server.log")"
  # From 1 s to 2 s after the first contact (the hand pushes for about 2.5 s): the handle's penetration past the
  # wall (x - proxy) and the rendered force.
  local figures
  figures=$(awk -F, 'NR > 1 { if (!c && $2 - $5 > 0) c = $1; if (c && $1 >= c + 1.0 && $1 < c + 2.0) {
                                p += $2 - $5; F += $8; k++ } n++ }
    END { if (k < 100) exit 1; printf "%.6f %.4f %d", p / k, F / k, n }' "$vendor.csv") ||
    { fail "$vendor: no contact rows in $vendor.csv"; return; }
  set -- $figures
  local penetration=$1 force=$2 rows=$3
  echo "$vendor: penetration $(awk -v p="$penetration" 'BEGIN { printf "%.2f", 1e3 * p }') mm" \
       "(F/K $(awk -v f="$hand" -v k="$stiffness" 'BEGIN { printf "%.2f", 1e3 * f / k }') mm)," \
       "rendered force $force N against the hand's $hand N, $rows states answered;" \
       "$(grep -o "deepest penetration.*" "$vendor-engine.log")"
  awk -v f="$force" -v h="$hand" 'BEGIN { exit !((f + h) < 0.1 * h && -(f + h) < 0.1 * h) }' ||
    fail "$vendor: the rendered force $force N does not balance the hand's $hand N"
  awk -v p="$penetration" -v h="$hand" -v k="$stiffness" 'BEGIN { e = h / k; exit !(p - e < 0.15 * e && e - p < 0.15 * e) }' ||
    fail "$vendor: the penetration $penetration m is not F/K"
  [ "$failures" -eq 0 ] && echo "ok: $vendor"
}

export FORCEDIM_SDK="$standins/forcedimension" HAPTICD_DHD_STANDIN="omega.7:10002" HAPTICD_DHD_STANDIN_BUTTONS=1 \
  HAPTICD_DHD_STANDIN_HAND=2,0,0
run forcedimension omega forcedimension/omega-engine.yaml 2 2000 0x1 \
  --set devices.omega.device.parameters.call_deadline_ms=1000  # the machine's load, not the SDK (sessions_test.sh)

export OH_SDK_BASE="$standins/openhaptics" HAPTICD_HD_STANDIN="Default Device=Touch:220-10001" \
  HAPTICD_HD_STANDIN_BUTTONS=2 HAPTICD_HD_STANDIN_HAND=1.5,0,0
run openhaptics touch openhaptics/touch-engine.yaml 1.5 800 0x2

port=18111
"$standins/haply/hapticd-standin-inverse-service" $port 1.5 0 0 5 > inverse-service.log 2>&1 &
pids="$pids $!"
for _ in $(seq 50); do grep -q "stand-in on" inverse-service.log && break; sleep 0.1; done
run haply inverse3 haply/inverse3-engine.yaml 1.5 1000 0x5 --set devices.inverse3.device.parameters.url=ws://127.0.0.1:$port

echo "$((3 - failures > 0 ? 3 - failures : 0)) vendors passed, $failures failures"
[ "$failures" -eq 0 ]
