#!/usr/bin/env bash
# hapticd-eval output-capability: a small grid per device writes JSON with finite figures; bad input fails.
set -euo pipefail
eval_bin=$1
work=$2
rm -rf "$work" && mkdir -p "$work"

for device in vishard3 vishard6 vishard10; do
  timeout 60 "$eval_bin" output-capability --device "$device" --points 2 --orientation-steps 2 \
    --json "$work/$device.json" > "$work/$device.txt"
  /usr/bin/python3 - "$work/$device.json" "$device" <<'PY'
import json, math, sys
r = json.load(open(sys.argv[1]))
assert r["device"] == sys.argv[2], r
t = r["translation"]
assert t["reached"] == t["poses"] > 0, t
for k in ("force", "velocity", "acceleration"):
    assert math.isfinite(t[k]["worst"]) and t[k]["worst"] >= 0, (k, t[k])
    assert t[k]["mean"] >= t[k]["worst"], (k, t[k])
print(sys.argv[2], "ok:", {k: round(t[k]["worst"], 3) for k in ("force", "velocity", "acceleration")})
PY
done

if "$eval_bin" output-capability --device no_such_device > "$work/bad.txt" 2>&1; then
  echo "an unknown device was accepted"; exit 1
fi
grep -q "device 'no_such_device'" "$work/bad.txt" || { cat "$work/bad.txt"; exit 1; }
echo "hapticd-eval ok"
