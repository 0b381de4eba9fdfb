#!/usr/bin/env bash
# False trips of the loop watchdogs on this machine: SESSIONS real-time sessions of SECONDS each of the 1-DOF test
# session (config/sessions/test-mass-spring.yaml) at RATE Hz with the default safety settings (10 overruns in a
# row, a 20 ms stall; SCHED_FIFO 80, mlockall, the CPU latency limit at 0) on an otherwise idle machine; a trip
# there is a false one (the session is healthy: 1 joint, about 10 us of compute per cycle). Prints each session's
# outcome and the trips per hour of loop time. Run as root (SCHED_FIFO).
# Usage: scripts/measure-watchdog.sh [SESSIONS] [SECONDS] [RATE] [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
sessions=${1:-10}
seconds=${2:-30}
rate=${3:-2000}
out=${4:-build/watchdog}
hapticd=build/default/bin/hapticd
mkdir -p "$out"
[ -x "$hapticd" ] || bash scripts/build.sh default > /dev/null
sed "s/rate_hz: 2000/rate_hz: $rate/; s|^server:|server:\n  plugin_paths: [$(pwd)/build/default/lib/hapticd/plugins]|" \
  config/sessions/test-mass-spring.yaml > "$out/session.yaml"
overrun_trips=0 stall_trips=0
for i in $(seq 1 "$sessions"); do
  rc=0
  "$hapticd" --config "$out/session.yaml" --duration "$seconds" --stats-json "$out/stats-$i.json" --log-level error \
    > "$out/log-$i.txt" 2>&1 || rc=$?
  [ "$rc" -eq 0 ] || [ "$rc" -eq 3 ] || { echo "hapticd failed (exit $rc): $(cat "$out/log-$i.txt")" >&2; exit 1; }
  line=$(/usr/bin/python3 -c "
import json, sys
s = json.load(open(sys.argv[1]))
w = s['wakeup_latency_us']
print(s['devices'][0]['fault'], s['max_consecutive_overruns'], s['overruns'], round(w['max'] / 1000, 2))" "$out/stats-$i.json")
  read -r fault longest overruns max_ms <<< "$line"
  echo "session $i: fault $fault, longest run of overruns $longest, overruns $overruns, latest wake-up $max_ms ms"
  case $fault in
    loop_overrun_violation) overrun_trips=$((overrun_trips + 1)) ;;
    loop_stall) stall_trips=$((stall_trips + 1)) ;;
  esac
done
/usr/bin/python3 -c "
import sys
n, s, o, st = map(float, sys.argv[1:5])
hours = n * s / 3600
print(f'{int(n)} sessions of {s:.0f} s at $rate Hz ({hours:.2f} h of loop time): loop_overrun_violation in '
      f'{int(o)}, loop_stall in {int(st)} (a session counts one trip at most)')" \
  "$sessions" "$seconds" "$overrun_trips" "$stall_trips"
