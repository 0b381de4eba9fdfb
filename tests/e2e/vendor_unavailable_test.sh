#!/usr/bin/env bash
# A commercial device whose vendor's library or service is not there is not a mistake in the session file: the
# server says what it looked for and exits with code 4 before anything is powered (docs/running.md, exit codes),
# for each vendor - Force Dimension's SDK, OpenHaptics, Haply's Inverse Service - and --check-config says the same.
# Usage: vendor_unavailable_test.sh HAPTICD SOURCE_DIR
set -u
hapticd=$1; src=$2
unset FORCEDIM_SDK OH_SDK_BASE
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
expect_unavailable() {  # name, expected text, hapticd arguments...
  local name=$1 text=$2
  shift 2
  local out rc
  out=$(timeout 30 "$hapticd" "$@" 2>&1); rc=$?
  if [ "$rc" -ne 4 ]; then fail "$name: exit code $rc, not 4: $out"; return; fi
  echo "$out" | grep -q "device unavailable: .*$text" || fail "$name: the message does not say what was missing: $out"
  echo "$out" | grep -q "no device was powered" || fail "$name: the message does not say nothing was powered: $out"
  echo "ok: $name"
}
for mode in --config --check-config; do
  expect_unavailable "forcedimension $mode" "Force Dimension SDK library was not found" $mode \
    "$src/config/sessions/forcedimension/omega-wall.yaml" --set devices.omega.device.parameters.sdk_path=/nonexistent
  expect_unavailable "openhaptics $mode" "OpenHaptics library was not found" $mode \
    "$src/config/sessions/openhaptics/touch-wall.yaml" --set devices.touch.device.parameters.sdk_path=/nonexistent
  # Port 9 (discard) on loopback: nothing listens there.
  expect_unavailable "haply $mode" "cannot connect to the Inverse Service at ws://127.0.0.1:9" $mode \
    "$src/config/sessions/haply/inverse3-wall.yaml" --set devices.inverse3.device.parameters.url=ws://127.0.0.1:9
done
# A mistake in the session is still a configuration error (code 2).
out=$(timeout 30 "$hapticd" --check-config "$src/config/sessions/haply/inverse3-wall.yaml" \
  --set devices.inverse3.device.parameters.max_force_n=50 2>&1); rc=$?
[ "$rc" -eq 2 ] || fail "a parameter out of range: exit code $rc, not 2: $out"
[ "$failures" -eq 0 ] && echo "all passed" || exit 1
