#!/usr/bin/env bash
# Eight simulated ViSHaRD3 at 2 kHz in real time (config/sessions/multi-user/eight-vishard3.yaml), on two loops
# pinned to CPUs 0 and 1 (the session as shipped) and on one loop (the same session without the groups' `loop`
# settings), run alternately ROUNDS times each. Prints a markdown table of overruns and compute time per loop;
# raw reports (hapticd --stats-json) in OUT_DIR. Run as root for SCHED_FIFO and locked memory.
# Usage: scripts/measure-loops.sh [SECONDS_PER_RUN] [ROUNDS] [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
rounds=${2:-2}
out=${3:-build/loops}
hapticd=build/default/bin/hapticd
session=config/sessions/multi-user/eight-vishard3.yaml
mkdir -p "$out"
[ -x "$hapticd" ] || bash scripts/build.sh default > /dev/null

# The one-loop variant: the same file without the loop settings, its relative paths kept.
sed '/^    loop: /d' "$session" > "$(dirname "$session")/.one-loop.yaml"
trap 'rm -f "$(dirname "$session")/.one-loop.yaml"' EXIT

for round in $(seq 1 "$rounds"); do
  for variant in two-loops one-loop; do
    file=$session
    [ "$variant" = one-loop ] && file=$(dirname "$session")/.one-loop.yaml
    echo "== round $round: $variant" >&2
    "$hapticd" --config "$file" --duration "$seconds" --stats-json "$out/$variant-$round.json" --log-level warn ||
      echo "   (exit $?: a device faulted; the report says which)" >&2
  done
done

/usr/bin/python3 - "$out" "$seconds" "$rounds" <<'PY'
import json, sys, platform
out, seconds, rounds = sys.argv[1], sys.argv[2], int(sys.argv[3])
print(f"Machine: {platform.node()} {platform.release()}, {seconds} s per run, SCHED_FIFO priority 80, mlockall.\n")
print("| run | loop | CPU | devices | cycles | overruns | share | compute p50 [us] | p99 [us] | wake-up p99 [us] |")
print("|---|---|---|---|---|---|---|---|---|---|")
for r in range(1, rounds + 1):
    for variant in ("two-loops", "one-loop"):
        s = json.load(open(f"{out}/{variant}-{r}.json"))
        for l in s["loops"]:
            share = 100.0 * l["overruns"] / max(1, l["cycles"])
            c, w = l["compute_time_us"], l["wakeup_latency_us"]
            cpu = l["cpu"] if l["cpu"] >= 0 else "-"
            print(f"| {variant} {r} | {l['name']} | {cpu} | {len(l['devices'])} | {l['cycles']} | {l['overruns']} "
                  f"| {share:.3f} % | {c['p50']:.1f} | {c['p99']:.1f} | {w['p99']:.1f} |")
PY
