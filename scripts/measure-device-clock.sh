#!/usr/bin/env bash
# A device-clocked session against the same session on the server's clock (docs/measurements.md, "Device
# clocks"): the shipped Touch and Inverse3 wall sessions on the project's stand-ins (OpenHaptics' libHD, whose
# scheduler thread calls back at 1 kHz; Haply's Inverse Service as a process on 127.0.0.1), each run for DURATION
# seconds with `--clock device` and with `--clock realtime`, alternately, RUNS times. Prints a table of the loop's
# statistics from --stats-json: wake-up latency (on the device's clock: from the device's tick to the loop awake;
# on the server's: from the deadline), overruns and skipped periods. Run it on an otherwise idle machine.
# Usage: scripts/measure-device-clock.sh [BUILD_DIR] [DURATION] [RUNS]   (default: build/ci 20 2)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/ci}; duration=${2:-20}; runs=${3:-2}
out=$build/measure-device-clock
mkdir -p "$out"
unset HAPTICD_DDS_NETWORK HAPTICD_DDS_CONFIG
export OH_SDK_BASE=$PWD/$build/tests/standins/openhaptics
"$build/tests/standins/haply/hapticd-standin-inverse-service" 18111 0.5 0 0 > "$out/service.log" 2>&1 &
service=$!
trap 'kill $service 2> /dev/null' EXIT
sleep 0.5
echo "| session | clock | run | cycles | wake-up p50 [us] | p99 | p99.9 | max | overruns | skipped | fault |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for run in $(seq "$runs"); do
  for session in openhaptics/touch-wall haply/inverse3-wall; do
    for clock in device realtime; do
      stats=$out/${session//\//-}-$clock-$run.json
      extra=()
      [ "$session" = haply/inverse3-wall ] && extra=(--set devices.inverse3.device.parameters.url=ws://127.0.0.1:18111)
      log=$out/${session//\//-}-$clock-$run.log rc=0
      "$build/bin/hapticd" --config "config/sessions/$session.yaml" --clock "$clock" --duration "$duration" \
        --stats-json "$stats" "${extra[@]}" > "$log" 2>&1 || rc=$?
      # Exit code 3: a device faulted (a watchdog tripped: the fault goes in the table); anything else fails.
      [ "$rc" -eq 0 ] || [ "$rc" -eq 3 ] || { echo "$session ($clock) failed: $(tail -3 "$log")" >&2; exit 1; }
      fault=$(grep -oE "FAULT [a-z_]+ at cycle [0-9]+" "$log" | head -1 || true)
      python3 - "$stats" "$session" "$clock" "$run" "${fault:-none}" << 'PY'
import json, sys
s = json.load(open(sys.argv[1])); w = s["wakeup_latency_us"]
print(f"| {sys.argv[2]} | {sys.argv[3]} | {sys.argv[4]} | {s['cycles']} | {w['p50']:.1f} | {w['p99']:.1f} | "
      f"{w['p999']:.1f} | {w['max']:.0f} | {s['overruns']} | {s['skipped_cycles']} | {sys.argv[5]} |")
PY
    done
  done
done
