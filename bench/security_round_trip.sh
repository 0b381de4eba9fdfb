#!/usr/bin/env bash
# The round trip with DDS Security against the plain one, side by side in one run (docs/deployment.md): the
# server with the simulated ViSHaRD3 coupled over DDS (state every cycle at 2 kHz, loopback, domain 89) and the
# scene engine, alternately plain and with the identities of scripts/make-security.sh (authenticated, encrypted
# payloads), REPEATS times each; the server measures state written -> command accepted. Prints each run and the
# medians. Usage: bench/security_round_trip.sh BIN_DIR [REPEATS] [SECONDS]
set -euo pipefail
bin=$1 repeats=${2:-3} seconds=${3:-5}
src=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
bash "$src/scripts/make-security.sh" "$work/security" 89 > /dev/null
run() {  # plain|secure -> "p50 p99"
  local extra=() engine_env=()
  if [ "$1" = secure ]; then
    extra=(--set "dds.cyclone_config=$work/security/server/cyclonedds.xml")
    engine_env=(HAPTICD_DDS_CONFIG="$work/security/engine/cyclonedds.xml")
  fi
  "$bin/hapticd" --config "$src/config/sessions/vishard3/dds-coupling.yaml" --dds-domain 89 --duration "$((seconds + 2))" \
    --stats-json "$work/stats.json" --log-level warn "${extra[@]}" > /dev/null 2>&1 &
  local server=$!
  sleep 0.3
  env "${engine_env[@]}" "$bin/hapticd-scene-engine" --domain 89 --duration "$((seconds + 4))" --wait 5 > /dev/null 2>&1 &
  local engine=$!
  wait $server; wait $engine || true
  python3 -c "import json,sys; r=json.load(open(sys.argv[1]))['dds_round_trip_us']; print(r['p50'], r['p99'], r['count'])" "$work/stats.json"
}
for k in $(seq "$repeats"); do
  for mode in plain secure; do
    read -r p50 p99 n < <(run $mode)
    echo "run $k $mode: round trip p50 $p50 us, p99 $p99 us ($n samples)"
    echo "$mode $p50 $p99" >> "$work/results"
  done
done
python3 - "$work/results" << 'PY'
import sys
from statistics import median
rows = [l.split() for l in open(sys.argv[1])]
m = {mode: (median(float(r[1]) for r in rows if r[0] == mode), median(float(r[2]) for r in rows if r[0] == mode))
     for mode in ("plain", "secure")}
for mode, (p50, p99) in m.items():
    print(f"{mode:6}: p50 {p50:.1f} us, p99 {p99:.1f} us (median of the runs)")
print(f"security / plain: p50 {m['secure'][0] / m['plain'][0]:.2f}x, p99 {m['secure'][1] / m['plain'][1]:.2f}x")
PY
