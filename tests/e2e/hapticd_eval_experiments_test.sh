#!/usr/bin/env bash
# hapticd-eval's experiments, short lockstep runs (--quick) of the full protocols through `all`: each writes its
# JSON with the figures the analysis gives; one report (PNG, HTML), drawn by hapticd-eval-report on the
# interpreter it names, whatever python3 the PATH finds first (here one that cannot run anything).
set -euo pipefail
eval_bin=$1
work=$2
rm -rf "$work" && mkdir -p "$work"
# The checks below read the JSON with the interpreter the Python tools are built for.
py=$(head -n 1 "$(dirname "$eval_bin")/hapticd-eval-report" | sed 's/^#!//')
mkdir -p "$work/fake-bin"
printf '#!/bin/sh\necho "not this python3" >&2\nexit 1\n' > "$work/fake-bin/python3"
chmod +x "$work/fake-bin/python3"

PATH="$work/fake-bin:$PATH" timeout 200 "$eval_bin" all --quick --out "$work" > "$work/all.txt"
cat "$work/all.txt"

# On ViSHaRD3 the Jacobian inner loops run on the thesis's constant inertias (CONTROL-METHODS.md section 2).
for scheme in ijc:500:ff tjc:500:ff; do
  timeout 60 "$eval_bin" backdrivability --quick --no-figures --schemes "$scheme" --out "$work/${scheme%%:*}" > /dev/null
done
grep -q "joint_inertia: \[0.93, 0.416, 0.279\]" "$work/ijc/backdrivability.json" || { echo "FAIL: IJC's M_hat"; exit 1; }
grep -q "task_mass: \[6.813, 9.35, 4.812\]" "$work/tjc/backdrivability.json" || { echo "FAIL: TJC's Mx_hat"; exit 1; }

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

mi = json.loads((work / "minimum-inertia.json").read_text())
[scheme] = mi["schemes"]
[x] = scheme["directions"]
# The bisection brackets a boundary inside the range, and the unstable end says which load broke it.
assert not x["below_range"] and not x["above_range"], x
assert x["quantity"] == "mass" and x["unit"] == "kg", x
assert 0.2 < x["minimum"] < 20 and x["largest_unstable"] < x["minimum"], x
assert x["unstable"]["load"] in {"firm-grasp", "loose-grasp", "voluntary-motion", "wall-collision"}, x
assert scheme["published_kg"] == 2.5, scheme
# ViSHaRD3's figure is a pure mass m I (the thesis's one mass per scheme): the rig renders it on every axis.
assert mi["shape"] == "isotropic", mi["shape"]
import re
masses = re.search(r"mass_kg: \[([^\]]*)\]", mi["example_session"]).group(1).split(",")
assert len(set(float(m) for m in masses)) == 1, masses
# The admittance loops compensate ViSHaRD3's identified friction (the thesis's `+ h`); the impedance schemes not.
assert "friction_compensation: true" in mi["example_session"] and "friction/vishard3.yaml" in mi["example_session"]
assert "friction_compensation" not in json.loads((work / "force-gain.json").read_text())["example_session"]

fg = json.loads((work / "force-gain.json").read_text())
[fx] = fg["directions"]
# Force feedback has a largest stable gain inside the range (the firm grasp's mode breaks it), and the thesis's
# figure is beside it.
assert fx["direction"] == "x" and not fx["below_range"] and not fx["above_range"], fx
assert 0.1 < fx["largest_kp"] < fx["smallest_unstable_kp"] < 50, fx
assert fg["published_kp"] == 3.75 and fg["worst_kp"] == fx["largest_kp"], fg

tr = json.loads((work / "tracking.json").read_text())
tby = {s["id"]: s for s in tr["schemes"]}
assert set(tby) == {"rac-kp10000-ff", "tjc-kp10000"}, tby.keys()
assert all(not s["fault"] for s in tr["schemes"]), tr["schemes"]
# Resolved acceleration with feedforward tracks the fast path better than the transposed Jacobian without.
assert 0 < tby["rac-kp10000-ff"]["rms_error_mm"] < tby["tjc-kp10000"]["rms_error_mm"], tby
assert tr["path"]["worst_condition"] > 3, tr["path"]

zw = json.loads((work / "z-width.json").read_text())
zby = {s["id"]: s for s in zw["schemes"]}
rac = [p["stiffness_n_per_m"] for p in zby["rac-kp10000-m5-ff"]["region"]]
# Wall damping never narrows the region of an admittance display (in the short run both may reach the range's
# end: the region saturates at 1e6 N/m). The 5 kg display renders a wall at all (a 3 kg one, below the smallest
# stable mass under the firm grasp, oscillated whatever the wall: every K below the range).
assert rac[1] >= rac[0] > 1000, rac
assert zby["rac-kp10000-m5-ff"]["mass_damping_stiffness"], zby["rac-kp10000-m5-ff"].keys()

tp = json.loads((work / "transparency.json").read_text())
assert len(tp["points"]) == 8, len(tp["points"])
w = tp["worst"]
assert w["condition"] >= 1 and 0 <= w["angle_deg"] < 90, w
assert all(m > 0 for m in w["least_mass_kg"]) and all(f > 0 for f in w["friction_n"]), w

fr_id = json.loads((work / "friction.json").read_text())
[j1] = fr_id["joints"]
assert j1["joint"] == "joint1" and j1["rms_error_percent"] < 10, j1
assert len(j1["velocity_rad_s"]) > 20, len(j1["velocity_rad_s"])
tele = json.loads((work / "teleoperation.json").read_text())
rows = {(r["task"], r["passivity"], r["round_trip_ms"], r["loss_percent"]): r for r in tele["rows"]}
assert len(rows) == 8, sorted(rows)
# With the time-domain passivity controllers every row is passive and stable; without, the 200 ms rows are neither.
assert all(r["passive"] and r["stable"] for k, r in rows.items() if k[1] == "tdpa"), rows
assert all(not r["passive"] and not r["stable"] for k, r in rows.items() if k[1] == "none" and k[2] == 200), rows
assert 900 < rows[("wall", "tdpa", 0.0, 0.0)]["felt_stiffness_n_per_m"] < 1400, rows
assert [t["passivity"] for t in tele["traces"]] == ["none", "tdpa"] and len(tele["traces"][0]["time_s"]) == 400, tele["traces"]
print("experiments ok")
PY

# Rotation on a device that renders it: the bisection of a rotational inertia about a handle axis, computed
# torque on the ViSHaRD10's partitioned inverse functions, SCARA pair 1-2 along y (the thesis's scheme there).
timeout 100 "$eval_bin" minimum-inertia --device vishard10 --quick --directions rx --no-figures --out "$work/v10" \
  > "$work/v10.txt"
"$py" - "$work/v10/minimum-inertia.json" <<'PY'
import json, sys
mi = json.load(open(sys.argv[1]))
[scheme] = mi["schemes"]
assert scheme["id"] == "ctc-kp250-ff", scheme["id"]
[rx] = scheme["directions"]
assert rx["quantity"] == "inertia" and rx["unit"] == "kg m^2" and rx["published"] == 0.01, rx
assert not rx["below_range"] and not rx["above_range"], rx
assert 0.001 < rx["minimum"] < 5 and rx["largest_unstable"] < rx["minimum"], rx
assert rx["unstable"]["load"] in {"firm-grasp", "loose-grasp", "voluntary-motion"}, rx
session = mi["example_session"]
assert "plugin: vishard10_ik" in session and "scara: inverse_function" in session, session
assert "scara_axes_yaw_rad: 1.5707963267948966" in session and "task:" not in session.split("vishard10_ik")[1].split("\n")[1]
assert "inertia_kg_m2" in session
assert mi["shape"] == "per-direction", mi["shape"]  # the thesis's diagonal per direction
assert "friction_compensation" not in mi["example_session"]  # no identified friction file for ViSHaRD10
assert [l["id"] for l in mi["rotational_loads"]] == ["firm-grasp", "loose-grasp", "voluntary-motion"]
print("rotation ok")
PY

# The devices without ViSHaRD3's translational handle: `all` runs the experiments written for them (output
# capability, minimum inertia, friction); the friction identification swings ViSHaRD10's heavy joint 1 with its
# gentle strokes (0.8 rad/s at most, 2 rad/s^2) without faulting.
timeout 100 "$eval_bin" all --device vishard10 --quick --no-figures --out "$work/all10" > "$work/all10.txt" 2>&1 \
  || { cat "$work/all10.txt"; exit 1; }
"$py" - "$work/all10" <<'PY'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
assert sorted(p.name for p in out.glob("*.json")) == ["friction.json", "minimum-inertia.json",
                                                       "output-capability-table.json"], list(out.iterdir())
fr = json.loads((out / "friction.json").read_text())
[j1] = fr["joints"]
assert fr["device"] == "vishard10" and j1["joint"] == "joint1", fr["device"]
assert "acceleration: 2" in fr["example_session"] and "0.8]" in fr["example_session"], fr["example_session"]
assert 0 < j1["coulomb_nm"] and j1["rms_error_percent"] < 25, j1
print("vishard10 all ok")
PY

# A joint whose every cruise carries a load has no truth to compare with: the friction experiment says so and
# writes no error (null), never 0 %. ViSHaRD10's joint 8 at the minimum-inertia rig's start carries the wrist.
timeout 100 "$eval_bin" friction --device vishard10 --joints 8 --speeds 0.1 0.2 0.3 0.5 0.8 --duration 60 --no-figures \
  --out "$work/fr8" --sim "initial_position=[2.8369, -2.532207, 4.819213, -3.964626, -1.159279, -1.146954, 2.293908, -2.717751, 1.570796, 0]" \
  > "$work/fr8.txt" 2>&1 || { cat "$work/fr8.txt"; exit 1; }
grep -q "joint8 .*not compared: no cruise without load" "$work/fr8.txt" || { cat "$work/fr8.txt"; exit 1; }
"$py" - "$work/fr8/friction.json" <<'PY'
import json, sys
[j8] = json.load(open(sys.argv[1]))["joints"]
assert j8["joint"] == "joint8" and j8["coulomb_nm"] > 0, j8
assert j8["rms_error_percent"] is None and j8["worst_error_percent"] is None and j8["velocity_rad_s"] == [], j8
print("uncompared joint ok")
PY

for f in report.html force-response.png backdrivability.png minimum-inertia.png force-gain.png tracking.png z-width.png \
  transparency.png friction.png teleoperation.png; do
  [ -s "$work/$f" ] || { echo "missing $f"; exit 1; }
done
grep -q "data:image/png;base64" "$work/report.html"
echo "report ok"

# --no-friction-compensation runs the admittance loops without the friction term.
timeout 60 "$eval_bin" force-response --quick --schemes rac:10000:ff --frequencies 1 --no-friction-compensation \
  --no-figures --out "$work/nofc" > "$work/nofc.txt"
"$py" -c 'import json, sys; s = json.load(open(sys.argv[1]))["example_session"]; assert "resolved_acceleration" in s and "friction_compensation" not in s, s' \
  "$work/nofc/force-response.json"

if "$eval_bin" force-response --quick --schemes nonsense --out "$work/bad" > "$work/bad.txt" 2>&1; then
  echo "an unknown scheme was accepted"; exit 1
fi
grep -q "unknown scheme 'nonsense'" "$work/bad.txt" || { cat "$work/bad.txt"; exit 1; }

# The teleoperation report's trace: with only a lossy grid it is the lowest loss's (it used to be written only at
# 0 % loss, so such a run silently had no figure); a trace round trip the grid lacks is an error.
timeout 120 "$eval_bin" teleoperation --duration 4 --losses 20 --round-trips 100 --passivity tdpa --no-figures \
  --out "$work/lossy" > "$work/lossy.txt"
"$py" -c 'import json, sys; t = json.load(open(sys.argv[1]))["traces"]; assert [(x["round_trip_ms"], x["loss_percent"]) for x in t] == [(100, 20)] and len(t[0]["time_s"]) > 100, t' \
  "$work/lossy/teleoperation.json"
if "$eval_bin" teleoperation --quick --trace-round-trip 300 --out "$work/bad" > "$work/bad.txt" 2>&1; then
  echo "a trace round trip outside the grid was accepted"; exit 1
fi
grep -q "trace-round-trip 300 is not one of the round trips run" "$work/bad.txt" || { cat "$work/bad.txt"; exit 1; }
echo "hapticd-eval experiments ok"
