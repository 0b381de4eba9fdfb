#!/usr/bin/env bash
# Every shipped session file checks out, and the demo session (simulated ViSHaRD3 with the simulated
# operator) runs in lockstep, twice with identical recordings, without a device fault.
# Usage: sessions_test.sh HAPTICD SOURCE_DIR WORK_DIR
set -u
hapticd=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }

for session in "$src"/config/sessions/*.yaml; do
  if out=$(timeout 30 "$hapticd" --check-config "$session" 2>&1); then pass "check-config $(basename "$session")"
  else fail "check-config $(basename "$session"): $out"; fi
done

for run in 1 2; do
  timeout 60 "$hapticd" --config "$src/config/sessions/demo.yaml" --clock lockstep --duration 1 \
    --record "$work/demo$run.csv" > "$work/demo$run.log" 2>&1 || fail "demo run $run exited $?: $(cat "$work/demo$run.log")"
done
cmp -s "$work/demo1.csv" "$work/demo2.csv" && pass "demo lockstep runs identical" || fail "demo recordings differ"
grep -q "device 'vishard3': ok" "$work/demo1.log" && pass "demo device ok" || fail "demo device: $(cat "$work/demo1.log")"
[ "$failures" -eq 0 ]
