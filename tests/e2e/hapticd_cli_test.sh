#!/usr/bin/env bash
# End-to-end checks of the hapticd executable: --check-config (good and bad), lockstep determinism through
# --record, --stats-json, and a clean SIGTERM shutdown through the safe mode (damping, then zero torque), exit 0.
# Usage: hapticd_cli_test.sh HAPTICD SOURCE_DIR WORK_DIR
set -u
hapticd=$1; src=$2; work=$3
hapticctl="$(dirname "$hapticd")/hapticctl"
rm -rf "$work"; mkdir -p "$work"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }

session="$src/config/sessions/test-mass-spring.yaml"

# 1. A good config checks out.
if out=$(timeout 30 "$hapticd" --check-config "$session" 2>&1); then pass "check-config accepts $session"
else fail "check-config rejected a good file: $out"; fi

# 2. A bad config: message with file:line: key, exit code 2; --config refuses to start on it.
bad="$work/bad.yaml"
sed 's/kp: 400/kp: -400/' "$session" > "$bad"
line=$(grep -n 'kp: -400' "$bad" | cut -d: -f1)
out=$(timeout 30 "$hapticd" --check-config "$bad" 2>&1); rc=$?
expected="error: $bad:$line: devices[0].controller.parameters.kp: value -400 is below the minimum 0"
[ "$rc" -eq 2 ] && [ "$out" = "$expected" ] && pass "check-config reports: $out" || fail "check-config gave rc=$rc: '$out' (expected '$expected')"
out=$(timeout 30 "$hapticd" --config "$bad" --clock lockstep --duration 1 2>&1); rc=$?
[ "$rc" -eq 2 ] && [[ "$out" == *"$expected"* ]] && pass "--config refuses to start" || fail "--config started on a bad file: rc=$rc $out"

# 2b. --set overrides a key before validation; an error in an overridden value names the override.
name=$(grep -m1 -- '- name:' "$session" | sed 's/.*name: *//')
out=$(timeout 30 "$hapticd" --check-config "$session" --set "devices.$name.controller.parameters.kp=-5" 2>&1); rc=$?
expected="error: override 'devices.$name.controller.parameters.kp=-5': devices[0].controller.parameters.kp: value -5 is below the minimum 0"
[ "$rc" -eq 2 ] && [ "$out" = "$expected" ] && pass "--set error names the override" || fail "--set gave rc=$rc: '$out' (expected '$expected')"
out=$(timeout 30 "$hapticd" --check-config "$bad" --set "devices.0.controller.parameters.kp=400" 2>&1) \
  && pass "--set mends a bad file" || fail "--set did not override: $out"

# 3. Lockstep determinism through the executable: two runs, identical recordings.
for run in 1 2; do
  timeout 60 "$hapticd" --config "$session" --clock lockstep --duration 2 --record "$work/run$run.h5" \
    --stats-json "$work/stats$run.json" --log-level warn || fail "lockstep run $run exited $?"
  "$hapticctl" export "$work/run$run.h5" --csv --exclude timing > /dev/null || fail "export of run $run"
done
rows=$(cat "$work"/run1.*.csv | wc -l)
if [ "$rows" -gt 4000 ] && cmp -s <(cat "$work"/run1.*.csv) <(cat "$work"/run2.*.csv); then
  pass "lockstep runs are identical ($rows rows)"
else fail "lockstep recordings differ or are short ($rows rows)"; fi
grep -q '"cycles": 4400' "$work/stats1.json" && pass "stats: 4400 cycles (2 s + 0.2 s ramp)" || fail "stats: $(head -5 "$work/stats1.json")"
grep -q '"compute_time_us": {"count": 4400' "$work/stats1.json" && pass "stats: compute-time histogram" || fail "no compute histogram"

# 4. SIGTERM: every device stops through its safe mode, exit 0, last torque zero.
timeout 60 "$hapticd" --config "$session" --clock realtime --duration 0 --record "$work/term.h5" \
  --stats-json "$work/term.json" --log-level info > "$work/term.log" 2>&1 &
pid=$!
sleep 1
kill -TERM "$pid"
wait "$pid"; rc=$?
[ "$rc" -eq 0 ] && pass "SIGTERM: exit code 0" || fail "SIGTERM: exit code $rc; log: $(cat "$work/term.log")"
grep -q '"stop_requested": true' "$work/term.json" && pass "SIGTERM: stop was requested" || fail "SIGTERM: stats say no stop request"
"$hapticctl" export "$work/term.h5" --csv > /dev/null || fail "SIGTERM: the recording does not export"
# the first device's first joint: its torque command in the last cycle
last=$(awk -F, 'NR == 1 { for (i = NF; i >= 1; --i) if ($i ~ /^joints\.torque_command\./) c = i; next } { v = $c }
                END { print v }' "$(ls "$work"/term.*.csv | head -n 1)")
[ "$last" = "0" ] && pass "SIGTERM: last torque command is 0" || fail "SIGTERM: last torque command is '$last'"
grep -q "stops through its safe mode" "$work/term.log" && pass "SIGTERM: safe stop logged" || fail "SIGTERM: no safe stop in log"

# 6. --record refuses a file name that says other than HDF5 (it once wrote HDF5 into run.csv), and so does
#    hapticctl record; nothing is written.
out=$(timeout 30 "$hapticd" --config "$session" --clock lockstep --duration 0.1 --record "$work/run.csv" 2>&1); rc=$?
if [ "$rc" -ne 0 ] && echo "$out" | grep -q "run.csv: a recording is an HDF5 file, named .h5 or .hdf5; for CSV record to" \
  && [ ! -e "$work/run.csv" ]; then pass "--record run.csv refused: $out"
else fail "--record run.csv: rc=$rc, $out, $(ls "$work")"; fi
out=$(timeout 30 "$hapticctl" record some_device "$work/state.csv" --duration 1 2>&1); rc=$?
[ "$rc" -ne 0 ] && echo "$out" | grep -q "a recording is an HDF5 file" && [ ! -e "$work/state.csv" ] \
  && pass "hapticctl record state.csv refused" || fail "hapticctl record state.csv: rc=$rc, $out"

# 7. --list-plugins: one column each for name, kind and version, however long a name (friction_identification
#    pushed its row's columns out of line).
"$hapticd" --list-plugins > "$work/plugins.txt" 2> /dev/null
kind_columns=$(awk 'NR > 1 { match($0, / (device|virtual_model|inverse_kinematics|controller|group_model|scene) /); print RSTART }' \
  "$work/plugins.txt" | sort -u | wc -l)
longest=$(awk 'NR > 1 { if (length($1) > n) n = length($1) } END { print n }' "$work/plugins.txt")
[ "$kind_columns" -eq 1 ] && [ "$longest" -gt 20 ] && pass "--list-plugins aligned (longest name $longest)" \
  || fail "--list-plugins: the kind starts in $kind_columns columns: $(cat "$work/plugins.txt")"

echo "$(( 15 - failures )) passed, $failures failed"
[ "$failures" -eq 0 ]
