#!/usr/bin/env bash
# Wake-up latency of the hapticd loop side by side with cyclictest (rt-tests), same period, same SCHED_FIFO
# priority, locked memory, in one run. Writes a markdown table to stdout and the raw files to OUT_DIR.
# Usage: scripts/measure-latency.sh [SECONDS_PER_RUN] [OUT_DIR]   (run as root for SCHED_FIFO)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
out=${2:-build/latency}
hapticd=build/default/bin/hapticd
priority=80
mkdir -p "$out"
[ -x "$hapticd" ] || bash scripts/build.sh default > /dev/null

for rate in 2000 4000; do
  period_us=$((1000000 / rate))
  loops=$((seconds * rate))
  echo "== $rate Hz: hapticd" >&2
  sed "s/rate_hz: 2000/rate_hz: $rate/; s/realtime_priority: 80/realtime_priority: $priority\n  cpu_dma_latency_us: ${HAPTICD_CPU_DMA_LATENCY_US:-0}/" \
    config/sessions/test-mass-spring.yaml > "$out/session-$rate.yaml"
  sed -i "s|^server:|server:\n  plugin_paths: [$(pwd)/build/default/lib/hapticd/plugins]|" "$out/session-$rate.yaml"
  # A watchdog's fault (exit 3) is part of the result, not the end of the measurement: the table names it.
  rc=0
  "$hapticd" --config "$out/session-$rate.yaml" --duration "$seconds" --stats-json "$out/hapticd-$rate.json" \
    --log-level warn || rc=$?
  [ "$rc" -eq 0 ] || [ "$rc" -eq 3 ] || { echo "hapticd failed (exit $rc)" >&2; exit 1; }
  echo "== $rate Hz: cyclictest -p $priority -i $period_us -l $loops -m" >&2
  cyclictest -q -p "$priority" -i "$period_us" -l "$loops" -m -h 4000 --histfile="$out/cyclictest-$rate.hist" \
    > "$out/cyclictest-$rate.txt"
done

/usr/bin/python3 - "$out" "$seconds" <<'PY'
import json, sys, platform
out, seconds = sys.argv[1], sys.argv[2]

def cyclictest_percentiles(path):
    counts = {}
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        us, n = line.split()[:2]
        counts[int(us)] = int(n)
    total = sum(counts.values())
    def q(p):
        seen = 0
        for us in sorted(counts):
            seen += counts[us]
            if seen >= p * total:
                return us
        return max(counts)
    mx = max((us for us, n in counts.items() if n), default=0)
    for line in open(path):
        if line.startswith("# Max Latencies:"):
            mx = int(line.split(":")[1])
    return total, q(0.5), q(0.99), q(0.999), mx

print(f"Machine: {platform.node()} {platform.release()}, {seconds} s per run, SCHED_FIFO priority 80, mlockall.\n")
print("| rate | program | samples | p50 [us] | p99 [us] | p99.9 [us] | max [us] | overruns | fault |")
print("|---|---|---|---|---|---|---|---|---|")
for rate in (2000, 4000):
    s = json.load(open(f"{out}/hapticd-{rate}.json"))
    w = s["wakeup_latency_us"]
    faults = ", ".join(d["fault"] for d in s["devices"] if d["fault"] != "none") or "none"
    print(f"| {rate} Hz | hapticd | {w['count']} | {w['p50']:.1f} | {w['p99']:.1f} | {w['p999']:.1f} | {w['max']:.1f} | {s['overruns']} | {faults} |")
    n, p50, p99, p999, mx = cyclictest_percentiles(f"{out}/cyclictest-{rate}.hist")
    print(f"| {rate} Hz | cyclictest | {n} | {p50} | {p99} | {p999} | {mx} | - | - |")
    print(f"| {rate} Hz | ratio | | {w['p50'] / p50:.2f} | {w['p99'] / p99:.2f} | {w['p999'] / p999:.2f} | | | |")
PY
