#!/usr/bin/env bash
# The loop's timing with live-view viewers against none: ROUNDS pairs of real-time sessions of SECONDS each of
# the demo's device (config/sessions/vishard3/admittance-resolved-acceleration.yaml with a live view), one with no
# viewer, one with four viewers subscribed to every channel - one of them never reading (tests/live_view/
# viewers.mjs) - side by side. Prints each session's wake-up p99 and max and its overruns, and the medians.
# Needs the build (build/default or BUILD_DIR) and tests/live_view's npm packages (scripts/install-deps.sh).
# Usage: scripts/measure-live-view.sh [ROUNDS] [SECONDS] [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-3}
seconds=${2:-20}
out=${3:-build/live-view-measurement}
build=${BUILD_DIR:-build/default}
hapticd=$build/bin/hapticd
[ -x "$hapticd" ] || { echo "no $hapticd: build first (scripts/build.sh)" >&2; exit 1; }
mkdir -p "$out"
source tests/e2e/session_copy.sh
sed -e "s%\.\./\.\./\(urdf\|friction\)/%$(pwd)/config/\1/%g" config/sessions/vishard3/admittance-resolved-acceleration.yaml \
  > "$out/session.yaml"
printf 'live_view: {port: 0}\n' >> "$out/session.yaml"
run() {  # run NAME VIEWERS
  local name=$1 viewers=$2
  "$hapticd" --config "$out/session.yaml" --duration "$seconds" --stats-json "$out/$name.json" > "$out/$name.log" 2>&1 &
  local server=$!
  local url=""
  for _ in $(seq 1 100); do
    url=$(sed -n 's/.*live view on \(ws:[^ ]*\).*/\1/p' "$out/$name.log" | head -1)
    [ -n "$url" ] && break
    sleep 0.05
  done
  if [ "$viewers" -gt 0 ] && [ -n "$url" ]; then
    timeout $((seconds + 10)) node tests/live_view/viewers.mjs "$url" "$viewers" 1 $((seconds - 2)) > "$out/$name.viewers" 2>&1 || true
  fi
  wait "$server" || true
  /usr/bin/python3 -c "
import json, sys
s = json.load(open(sys.argv[1]))
w = s['wakeup_latency_us']
print(f\"{sys.argv[2]:<24} wake-up p99 {w['p99']:8.1f} us, max {w['max']:8.1f} us, overruns {s['overruns']}\")" "$out/$name.json" "$name"
}
for r in $(seq 1 "$rounds"); do
  run "none-$r" 0
  run "four-viewers-$r" 4
  cat "$out/four-viewers-$r.viewers"
done
/usr/bin/python3 - "$out" "$rounds" << 'PY'
import json, statistics, sys
out, rounds = sys.argv[1], int(sys.argv[2])
def med(kind, key):
    values = []
    for r in range(1, rounds + 1):
        s = json.load(open(f"{out}/{kind}-{r}.json"))
        values.append(s["wakeup_latency_us"][key] if key != "overruns" else s["overruns"])
    return statistics.median(values)
for kind in ("none", "four-viewers"):
    print(f"median of {rounds}: {kind:<13} wake-up p99 {med(kind, 'p99'):8.1f} us, max {med(kind, 'max'):8.1f} us, "
          f"overruns {med(kind, 'overruns'):.0f}")
PY
