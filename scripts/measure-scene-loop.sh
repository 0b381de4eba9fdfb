#!/usr/bin/env bash
# The loop at 4 kHz with a 1.3 million-triangle scene (docs/haptic-scene.md, "Measured"): the simulated ViSHaRD3
# in real time (SCHED_FIFO 80, locked memory: run as root) strokes a pebble mesh of 1 310 720 triangles
# (scripts/make-pebble-mesh.py at 8 levels, 50 x 36 x 24 mm) - the operator presses 8 N down onto its top and sways
# 2 cm to and fro - for SECONDS, side by side with the same run on the shipped pebble of 5 120 triangles and on an
# analytic sphere in its place: the loop's overruns and compute time (--stats-json), the same method as
# scripts/measure-latency.sh's.
# Usage: scripts/measure-scene-loop.sh [SECONDS] [OUT_DIR] [RATE_HZ]   (BUILD=build/ci to use another build)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
out=$(realpath -m "${2:-build/scene-loop}")
rate=${3:-4000}
build=${BUILD:-build/default}
hapticd=$build/bin/hapticd
mkdir -p "$out"
[ -x "$hapticd" ] || bash scripts/build.sh default > /dev/null
[ -s "$out/pebble-8.obj" ] || python3 scripts/make-pebble-mesh.py "$out/pebble-8.obj" 8 >&2
cp config/haptic-scenes/pebble.obj "$out/pebble-4.obj"

scene() { # NAME SHAPE: the scene file, the pebble's top 8 mm under the proxy (its radius 5 mm) at the start
  local shape
  case "$2" in
    sphere) shape="shape: sphere, radius: 0.012" ;;
    *) shape="shape: mesh, file: $2" ;;
  esac
  cat > "$out/scene-$1.yaml" <<EOF
objects:
  - {name: pebble, $shape, position: [0.0, 0.0, -0.025],
     material: {stiffness: 3000, damping: 6, static_friction: 0.4, dynamic_friction: 0.3}}
EOF
}
scene analytic sphere
scene 5k pebble-4.obj
scene 1m pebble-8.obj

for run in analytic 5k 1m; do
  echo "== $run: $seconds s at $rate Hz" >&2
  rc=0
  "$hapticd" --config config/sessions/vishard3/haptic-scene.yaml --duration "$seconds" --log-level warn \
    --set dds.enabled=false --set "server.rate_hz=$rate" \
    --set "devices.vishard3.virtual_model.parameters.scene=$out/scene-$run.yaml" \
    --set "devices.vishard3.device.parameters.operator_force_n=[0,0,-8]" \
    --set devices.vishard3.device.parameters.operator_motion=sine \
    --set "devices.vishard3.device.parameters.operator_motion_m=[0.02,0,0]" \
    --set devices.vishard3.device.parameters.operator_motion_frequency_hz=0.5 \
    --stats-json "$out/stats-$run.json" > "$out/hapticd-$run.log" 2>&1 || rc=$?
  [ "$rc" -eq 0 ] || [ "$rc" -eq 3 ] || { echo "hapticd failed (exit $rc)" >&2; cat "$out/hapticd-$run.log" >&2; exit 1; }
done

python3 - "$out" "$seconds" "$rate" <<'PY'
import json, os, platform, sys
out, seconds, rate = sys.argv[1], sys.argv[2], sys.argv[3]
print(f"The loop at {rate} Hz for {seconds} s, stroking the scene (this machine: {platform.node()}, "
      f"{platform.release()}, {os.cpu_count()} cores; SCHED_FIFO 80, mlockall)\n")
print("| scene | cycles | overruns (most in a row) | compute p50 / p99 / p99.9 / max (us) | wake-up p99 (us) | fault |")
print("|---|---|---|---|---|---|")
names = {"analytic": "analytic sphere (the reference)", "5k": "pebble, 5 120 triangles",
         "1m": "pebble, 1 310 720 triangles"}
for run in ("analytic", "5k", "1m"):
    s = json.load(open(f"{out}/stats-{run}.json"))
    c, w = s["compute_time_us"], s["wakeup_latency_us"]
    faults = ", ".join(d["fault"] for d in s["devices"] if d["fault"] != "none") or "none"
    print(f"| {names[run]} | {s['cycles']} | {s['overruns']} ({s['max_consecutive_overruns']}) | "
          f"{c['p50']:.1f} / {c['p99']:.1f} / {c['p999']:.1f} / {c['max']:.0f} | {w['p99']:.0f} | {faults} |")
PY
