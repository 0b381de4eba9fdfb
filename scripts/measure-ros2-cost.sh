#!/usr/bin/env bash
# What the ROS 2 topics cost the loop (docs/ros2.md, "What it costs the loop"): the shipped ROS 2 session
# (config/sessions/vishard3/ros2.yaml: the simulated ViSHaRD3 at the desk, 2 kHz, real time, SCHED_FIFO 80, locked
# memory) run side by side with the ROS 2 topics off (the section taken out), on at 250 Hz with a ROS 2 node's
# subscriptions listening (tests/e2e/ros2_subscriber.cpp, the rosidl types, ROS 2's QoS), and off once more - the
# null comparison, the ratio two runs of the same program give on this machine. The rounds alternate; a table of
# the loop's compute time and wake-up latency per run, and the ratios on/off and off/off per round.
# Usage: scripts/measure-ros2-cost.sh [SECONDS_PER_RUN] [ROUNDS] [OUT_DIR]   (as root, for SCHED_FIFO)
#        BUILD=build/ci (default) or another build tree with bin/hapticd and bin/ros2_subscriber
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
rounds=${2:-3}
out=${3:-build/ros2-cost}
build=${BUILD:-build/ci}
mkdir -p "$out"
session=config/sessions/vishard3/ros2.yaml
# Off: the same file without its ros2 section.
awk '/^ros2:/ { skip = 1; next } skip && /^[^ ]/ { skip = 0 } !skip' "$session" > "$out/off.yaml"
sed -i "s|\.\./\.\./|$(pwd)/config/|g" "$out/off.yaml"
sed "s|\.\./\.\./|$(pwd)/config/|g" "$session" > "$out/on.yaml"
run() {  # run NAME CONFIG [listen]
  local name=$1 config=$2
  echo "== $name" >&2
  if [ "${3:-}" = listen ]; then
    "$build/bin/ros2_subscriber" 171 vishard3 "$((seconds + 2))" > "$out/$name.subscriber" &
  fi
  "$build/bin/hapticd" --config "$config" --duration "$seconds" --stats-json "$out/$name.json" --log-level warn \
    --set dds.domain_id=172 $([ "${3:-}" = listen ] && echo --set ros2.domain_id=171) || true
  wait
}
for r in $(seq 1 "$rounds"); do
  run "off-$r" "$out/off.yaml"
  run "on-$r" "$out/on.yaml" listen
  run "null-$r" "$out/off.yaml"
done
/usr/bin/python3 - "$out" "$rounds" <<'PY'
import json, statistics, sys
out, rounds = sys.argv[1], int(sys.argv[2])
def load(name):
    d = json.load(open(f"{out}/{name}.json"))
    return d["compute_time_us"], d["wakeup_latency_us"], d["overruns"], d["cycles"]
print("| run | cycles | overruns | compute p50 / p99 / p99.9 (us) | wake-up p50 / p99 (us) | ROS 2 samples taken |")
print("|---|---|---|---|---|---|")
ratios = {"on/off": [], "null/off": []}
for r in range(1, rounds + 1):
    rows = {}
    for kind in ("off", "on", "null"):
        c, w, o, n = load(f"{kind}-{r}")
        rows[kind] = c
        taken = ""
        if kind == "on":
            taken = ", ".join(" ".join(l.split()) for l in open(f"{out}/on-{r}.subscriber"))
        print(f"| {kind} {r} | {n} | {o} | {c['p50']:.1f} / {c['p99']:.1f} / {c['p999']:.1f} | "
              f"{w['p50']:.1f} / {w['p99']:.1f} | {taken} |")
    for key, a in (("on/off", "on"), ("null/off", "null")):
        ratios[key].append([rows[a][q] / rows["off"][q] for q in ("p50", "p99", "p999")])
print()
print("| ratio of compute time | p50 | p99 | p99.9 |")
print("|---|---|---|---|")
for key, rs in ratios.items():
    cols = list(zip(*rs))
    print(f"| {key} (median of {rounds}; range) | " + " | ".join(
        f"{statistics.median(c):.2f} ({min(c):.2f}-{max(c):.2f})" for c in cols) + " |")
PY
