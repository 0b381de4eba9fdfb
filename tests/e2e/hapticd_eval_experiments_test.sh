#!/usr/bin/env bash
# hapticd-eval's experiments, short lockstep runs (--quick) of the full protocols: each writes its JSON with
# the figures the analysis gives; the report (PNG, HTML) where python3 with matplotlib is installed.
set -euo pipefail
eval_bin=$1
work=$2
rm -rf "$work" && mkdir -p "$work"
# Debian's interpreter (the one python3-matplotlib installs into), also for the report hapticd-eval draws.
py=/usr/bin/python3
export HAPTICD_PYTHON=$py

timeout 120 "$eval_bin" force-response --quick --out "$work" > "$work/force-response.txt"
timeout 120 "$eval_bin" backdrivability --quick --out "$work" > "$work/backdrivability.txt"
cat "$work/force-response.txt" "$work/backdrivability.txt"

"$py" - "$work" <<'PY'
import json, math, pathlib, sys
work = pathlib.Path(sys.argv[1])
fr = json.loads((work / "force-response.json").read_text())
assert fr["experiment"] == "force-response" and fr["quick"], fr.keys()
ids = [s["id"] for s in fr["schemes"]]
assert ids == ["open-loop", "pd-kp2.5-kd0.003", "rac-kp10000-m3-ff", "rac-kp1000-m3-ff"], ids
for s in fr["schemes"]:
    n = len(s["frequency_hz"]) + len(s["faults"])
    assert n == 6, (s["id"], n)
    assert all(math.isfinite(g) and g > 0 for g in s["gain"]), s
    assert len(s["phase_deg"]) == len(s["gain"]) == len(s["distortion_percent"])
# Force feedback raises the gain of the low frequencies towards 1 (friction is what open loop loses).
ol, pd = fr["schemes"][0], fr["schemes"][1]
assert pd["gain"][0] > ol["gain"][0], (pd["gain"][0], ol["gain"][0])
assert "scripted_wrench" in fr["example_session"]

bd = json.loads((work / "backdrivability.json").read_text())
by = {s["id"]: s for s in bd["schemes"]}
assert set(by) == {"open-loop", "pd-kp1.5-kd0.003", "rac-kp500-m5-ff", "ijc-kp500-m5-ff", "tjc-kp500-m5-ff"}, by.keys()
# Dragging the device in open loop takes force (friction, inertia); an admittance scheme rendering 5 kg has a
# smaller error than that.
assert by["open-loop"]["rms_error_n"] > 1.0, by["open-loop"]
assert by["rac-kp500-m5-ff"]["rms_error_n"] < by["open-loop"]["rms_error_n"]
assert len(by["open-loop"]["time_s"]) == len(by["open-loop"]["force_error_n"]) > 50
print("experiments ok")
PY

if "$py" -c "import matplotlib" 2> /dev/null; then
  for f in report.html force-response.png backdrivability.png; do
    [ -s "$work/$f" ] || { echo "missing $f"; exit 1; }
  done
  grep -q "data:image/png;base64" "$work/report.html"
  echo "report ok"
else
  echo "python3-matplotlib not installed: the figures were not checked"
fi

if "$eval_bin" force-response --quick --schemes nonsense --out "$work/bad" > "$work/bad.txt" 2>&1; then
  echo "an unknown scheme was accepted"; exit 1
fi
grep -q "unknown scheme 'nonsense'" "$work/bad.txt" || { cat "$work/bad.txt"; exit 1; }
echo "hapticd-eval experiments ok"
