#!/usr/bin/env bash
# The whole evaluation suite on the three simulated devices (docs/evaluation.md): `hapticd-eval all` per device,
# each into its own folder with its own report. Not part of CI (CI runs `all --quick`); about 4 minutes here.
# Usage: eval/evaluate.sh [OUT] [hapticd-eval options...]   (OUT: build/eval-results)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$root/build/eval-results}
shift || true
eval_bin=${HAPTICD_EVAL:-$root/build/default/bin/hapticd-eval}
[ -x "$eval_bin" ] || { echo "no $eval_bin: build first (scripts/build.sh) or set HAPTICD_EVAL" >&2; exit 2; }
start=$SECONDS
for device in vishard3 vishard6 vishard10; do
  t=$SECONDS
  "$eval_bin" all --device "$device" --out "$out/$device" "$@"
  echo "== $device: $((SECONDS - t)) s, results in $out/$device"
done
echo "== the whole suite: $((SECONDS - start)) s"
