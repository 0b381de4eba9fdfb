#!/usr/bin/env bash
# The attacks of issue 17 that need the real process: a stopped (SIGSTOP) real-time server, recordings onto a
# full file system and /dev/full, config and model files that are no files or not physical, a system library
# folder as plugin path, a plugin that throws as it leaves the loop, and too little address space. Each must end
# with a clear message and its exit code, never an abort or a hang. Usage: hardening_test.sh HAPTICD SOURCE_DIR WORK_DIR
set -uo pipefail
hapticd=$1 src=$2 work=$3
rm -rf "$work"; mkdir -p "$work"; cd "$work"
fail() { echo "FAIL: $*"; exit 1; }
session=$src/config/sessions/vishard3/admittance-resolved-acceleration.yaml
# expect CODE PATTERN -- COMMAND...: runs it (bounded), checks the exit code and that the output says PATTERN.
expect() {
  local code=$1 pattern=$2; shift 3
  timeout 30 "$@" > out.txt 2>&1; local got=$?
  [ "$got" -eq "$code" ] || { cat out.txt; fail "$* -> exit $got, expected $code"; }
  grep -q -- "$pattern" out.txt || { cat out.txt; fail "$* -> no '$pattern' in the output"; }
  echo "ok: exit $got: $(grep -m1 -- "$pattern" out.txt)"
}

# Config and model files.
expect 2 "is a directory" -- "$hapticd" --config "$work"
mkfifo pipe.yaml
expect 2 "not a regular file" -- "$hapticd" --config pipe.yaml
expect 2 "is a directory" -- "$hapticd" --describe-plugin sim --config "$work"
sed "s|urdf: ../../urdf/vishard3.urdf|urdf: /dev/zero|" "$session" > zero.yaml
expect 2 "zero.yaml:17: devices\[0\].device.parameters.urdf: /dev/zero: not a regular file" -- "$hapticd" --check-config zero.yaml
sed 's|ixx="[^"]*"|ixx="nan"|' "$src/config/urdf/vishard3.urdf" > nan.urdf
sed "s|urdf: ../../urdf/vishard3.urdf|urdf: $work/nan.urdf|" "$session" > nan.yaml
expect 2 "nan.urdf:[0-9]*: link '.*': inertia ixx=\"nan\" is not a finite number" -- "$hapticd" --check-config nan.yaml
sed '0,/mass value="[^"]*"/s//mass value="-5"/' "$src/config/urdf/vishard3.urdf" > negative.urdf
sed "s|urdf: ../../urdf/vishard3.urdf|urdf: $work/negative.urdf|" "$session" > negative.yaml
expect 2 "negative.urdf:[0-9]*: link '.*': mass -5.000000 kg: must be above zero" -- "$hapticd" --check-config negative.yaml
{ echo "server: {plugin_paths: [/usr/lib/x86_64-linux-gnu]}"; sed -n '/^devices:/,$p' "$session"; } |
  sed "s%\.\./\.\./\(urdf\|friction\)/%$src/config/\1/%g" > system-libs.yaml
expect 0 ": ok" -- "$hapticd" --check-config system-libs.yaml
{ echo "devices: ["; for i in $(seq 1 1500000); do echo "1,"; done; echo "1]"; } > huge.yaml
expect 2 "at most 4194304 are accepted" -- "$hapticd" --config huge.yaml

# A plugin that throws as it is deactivated (the friction identification, ended before it finished): the device
# is disabled all the same, the error names device, scheme and plugin, exit code 4.
sed "s%\.\./\.\./urdf/%$src/config/urdf/%; s%output_file: .*%output_file: $work/identified.yaml%" \
  "$src/config/sessions/vishard3/identify-friction.yaml" > identify.yaml
expect 4 "device 'vishard3': scheme 'default', controller 'friction_identification': friction identification incomplete" \
  -- "$hapticd" --config identify.yaml --clock lockstep --duration 1
grep -q "device 'vishard3': ok" out.txt || fail "the identification's device did not end in order"

# Too little address space: a message and exit code 4 before any device is powered (Cyclone aborted before).
expect 4 "not enough address space" -- bash -c "ulimit -v 60000; exec '$hapticd' --config '$session' --duration 1 --dds-domain 88"

# Recordings: /dev/full, and a file system that fills up (a file size limit: writes fail with EFBIG).
# The recorder stops before the limit, while the file can still be closed whole: it opens, every dataset has the
# same number of cycles (the export checks), and the summary says how many are in it.
expect 4 "cannot create the recording /dev/full" -- "$hapticd" --config "$session" --clock lockstep --duration 1 --record /dev/full
expect 5 "recording FAILED" -- bash -c "trap '' XFSZ; ulimit -f 2000; exec '$hapticd' --config '$session' --clock lockstep --duration 4 --record rec.h5"
grep -q "lost" out.txt || fail "the lost cycles are not reported"
in_file=$(sed -n 's/.*recording FAILED: .*; \([0-9]*\) device-cycles in rec.h5.*/\1/p' out.txt)
"$(dirname "$hapticd")/hapticctl" export rec.h5 --csv > export.txt 2>&1 || fail "the failed recording does not open: $(cat export.txt)"
grep -q ": $in_file cycles of" export.txt && [ "${in_file:-0}" -gt 0 ] \
  || fail "the recording holds other cycles than reported ($in_file): $(cat export.txt)"

# A stalled process (SIGSTOP for 1.5 s, beyond the test sessions' 1 s) is a fault: loop_stall, the device's safe
# mode, exit code 3.
source "$src/tests/e2e/session_copy.sh"
session_copy "$session" "$src" stall.yaml
"$hapticd" --config stall.yaml --duration 3 > stall.txt 2>&1 &
server=$!
sleep 1.2
kill -STOP "$server"; sleep 1.5; kill -CONT "$server"
wait "$server"; code=$?
grep -q "fault loop_stall" stall.txt || { cat stall.txt; fail "the stall was not a fault"; }
[ "$code" -eq 3 ] || { cat stall.txt; fail "exit $code after a stall, expected 3"; }
echo "ok: exit 3: $(grep -m1 'fault loop_stall' stall.txt)"
echo "hardening: ok"
