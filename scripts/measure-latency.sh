#!/usr/bin/env bash
# Wake-up latency of the hapticd loop side by side with cyclictest (rt-tests), same period, same SCHED_FIFO
# priority, locked memory, in one run. Writes markdown tables to stdout and the raw files to OUT_DIR.
# Usage: scripts/measure-latency.sh [SECONDS_PER_RUN] [OUT_DIR] [ROUNDS]   (run as root for SCHED_FIFO)
# Each round runs, per rate, hapticd, cyclictest, and cyclictest once more: the second cyclictest against the
# first is the null comparison - the ratio two runs of the same program give on this machine. With ROUNDS > 1
# the rounds alternate and a last table gives the median ratios and their ranges.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-20}
out=${2:-build/latency}
rounds=${3:-1}
hapticd=build/default/bin/hapticd
priority=80
mkdir -p "$out"
[ -x "$hapticd" ] || bash scripts/build.sh default > /dev/null

for round in $(seq 1 "$rounds"); do
  for rate in 2000 4000; do
    period_us=$((1000000 / rate))
    loops=$((seconds * rate))
    tag="$rate-r$round"
    echo "== round $round, $rate Hz: hapticd" >&2
    sed "s/rate_hz: 2000/rate_hz: $rate/; s/realtime_priority: 80/realtime_priority: $priority\n  cpu_dma_latency_us: ${HAPTICD_CPU_DMA_LATENCY_US:-0}/" \
      config/sessions/test-mass-spring.yaml > "$out/session-$rate.yaml"
    sed -i "s|^server:|server:\n  plugin_paths: [$(pwd)/build/default/lib/hapticd/plugins]|" "$out/session-$rate.yaml"
    # A watchdog's fault (exit 3) is part of the result, not the end of the measurement: the table names it.
    rc=0
    "$hapticd" --config "$out/session-$rate.yaml" --duration "$seconds" --stats-json "$out/hapticd-$tag.json" \
      --log-level warn || rc=$?
    [ "$rc" -eq 0 ] || [ "$rc" -eq 3 ] || { echo "hapticd failed (exit $rc)" >&2; exit 1; }
    for run in a b; do
      echo "== round $round, $rate Hz: cyclictest ($run) -p $priority -i $period_us -l $loops -m" >&2
      cyclictest -q -p "$priority" -i "$period_us" -l "$loops" -m -h 4000 --histfile="$out/cyclictest-$tag-$run.hist" \
        > "$out/cyclictest-$tag-$run.txt"
    done
  done
done

/usr/bin/python3 - "$out" "$seconds" "$rounds" <<'PY'
import json, platform, statistics, sys
out, seconds, rounds = sys.argv[1], sys.argv[2], int(sys.argv[3])

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

print(f"Machine: {platform.node()} {platform.release()}, {seconds} s per run, SCHED_FIFO priority 80, mlockall, "
      f"{rounds} round(s).\n")
print("| round | rate | program | samples | p50 [us] | p99 [us] | p99.9 [us] | max [us] | overruns | fault |")
print("|---|---|---|---|---|---|---|---|---|---|")
ratios = {}  # (rate, which) -> [(p50 ratio, p99 ratio)]
for r in range(1, rounds + 1):
    for rate in (2000, 4000):
        tag = f"{rate}-r{r}"
        s = json.load(open(f"{out}/hapticd-{tag}.json"))
        w = s["wakeup_latency_us"]
        faults = ", ".join(d["fault"] for d in s["devices"] if d["fault"] != "none") or "none"
        print(f"| {r} | {rate} Hz | hapticd | {w['count']} | {w['p50']:.1f} | {w['p99']:.1f} | {w['p999']:.1f} | "
              f"{w['max']:.1f} | {s['overruns']} | {faults} |")
        a = cyclictest_percentiles(f"{out}/cyclictest-{tag}-a.hist")
        b = cyclictest_percentiles(f"{out}/cyclictest-{tag}-b.hist")
        for name, c in (("cyclictest", a), ("cyclictest again", b)):
            print(f"| {r} | {rate} Hz | {name} | {c[0]} | {c[1]} | {c[2]} | {c[3]} | {c[4]} | - | - |")
        print(f"| {r} | {rate} Hz | ratio hapticd / cyclictest | | {w['p50'] / a[1]:.2f} | {w['p99'] / a[2]:.2f} | "
              f"{w['p999'] / a[3]:.2f} | | | |")
        print(f"| {r} | {rate} Hz | ratio cyclictest again / cyclictest | | {b[1] / a[1]:.2f} | {b[2] / a[2]:.2f} | "
              f"{b[3] / a[3]:.2f} | | | |")
        ratios.setdefault((rate, "hapticd / cyclictest"), []).append((w["p50"] / a[1], w["p99"] / a[2]))
        ratios.setdefault((rate, "cyclictest again / cyclictest"), []).append((b[1] / a[1], b[2] / a[2]))
if rounds > 1:
    print(f"\nOver {rounds} rounds: median ratio (range)\n")
    print("| rate | ratio | p50 | p99 |")
    print("|---|---|---|---|")
    for (rate, which), v in ratios.items():
        cols = []
        for i in (0, 1):
            x = [p[i] for p in v]
            cols.append(f"{statistics.median(x):.2f} ({min(x):.2f} - {max(x):.2f})")
        print(f"| {rate} Hz | {which} | {cols[0]} | {cols[1]} |")
PY
