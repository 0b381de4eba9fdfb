#!/usr/bin/python3
"""The DDS round trip, side by side with ddsperf, in one run (docs/dds-interface.md).

For each loop rate (1 kHz, 2 kHz): hapticd with the simulated ViSHaRD3 publishing its state every cycle and the
example scene engine (a separate process) answering every state with a coupling command; the server measures
state written -> command accepted (validated and handed to the loop). Then ddsperf ping/pong (two processes)
at the same rate with the same payload size (the state's, 712 bytes), the same Cyclone configuration
(config/dds/cyclonedds-loopback.xml) and the same triggering (listeners: ddsperf's default, and what the
server's command path and the client library's state path use) and the same placement (the engine and
both ddsperf processes on CPU 0, where the server keeps its DDS threads; the server's loop on the last CPU).
Both on the loopback interface only.

ddsperf reports percentiles per second; its p50 and p99 here are the count-weighted means of those. Ours are
over every sample of the run. Usage: bench/dds_round_trip.py BUILD_BIN_DIR [SECONDS] [OUT.md]
"""
import json
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
XML = os.path.join(ROOT, "config", "dds", "cyclonedds-loopback.xml")
SESSION = os.path.join(ROOT, "config", "sessions", "vishard3", "dds-coupling.yaml")
STATE_BYTES = 712
# Placement: hapticd puts its loop on the last CPU and its DDS threads on the others (dds.cpu: auto); the
# engine and both ddsperf processes run on CPU 0, with the server's DDS threads.
PIN = ["taskset", "-c", "0"] if (os.cpu_count() or 1) >= 2 else []


def run_hapticd(bin_dir, rate, seconds, domain):
    text = open(SESSION).read().replace("rate_hz: 2000", f"rate_hz: {rate}")
    text = text.replace("../../urdf/", os.path.join(ROOT, "config", "urdf") + "/")
    with tempfile.TemporaryDirectory() as tmp:
        session = os.path.join(tmp, "session.yaml")
        stats = os.path.join(tmp, "stats.json")
        open(session, "w").write(text)
        server = subprocess.Popen([os.path.join(bin_dir, "hapticd"), "--config", session, "--duration", str(seconds + 1.5),
                                   "--dds-domain", str(domain), "--stats-json", stats, "--log-level", "warn"])
        time.sleep(0.3)
        engine = subprocess.Popen(PIN + [os.path.join(bin_dir, "hapticd-scene-engine"), "--domain", str(domain),
                                   "--duration", str(seconds + 3)], stdout=subprocess.DEVNULL)
        server.wait(timeout=seconds + 30)
        engine.wait(timeout=30)
        rt = json.load(open(stats))["dds_round_trip_us"]
        return rt["count"], rt["p50"], rt["p99"]


def run_ddsperf(rate, seconds, domain):
    env = dict(os.environ, CYCLONEDDS_URI="file://" + XML)
    pong = subprocess.Popen(PIN + ["ddsperf", "-i", str(domain), "-D", str(seconds + 3), "pong"], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(0.3)
    ping = subprocess.run(PIN + ["ddsperf", "-i", str(domain), "-D", str(seconds), "ping", f"{rate}Hz", "size", str(STATE_BYTES)], env=env, capture_output=True, text=True, timeout=seconds + 30)
    pong.wait(timeout=30)
    total = p50 = p99 = 0.0
    for line in ping.stdout.splitlines():
        m = re.search(r"50% ([0-9.]+)us .* 99% ([0-9.]+)us .* cnt (\d+)", line)
        if m:
            n = float(m.group(3))
            total += n
            p50 += n * float(m.group(1))
            p99 += n * float(m.group(2))
    if total == 0:
        raise RuntimeError("ddsperf reported nothing:\n" + ping.stdout + ping.stderr)
    return int(total), p50 / total, p99 / total


def main():
    bin_dir = sys.argv[1]
    seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 10.0
    out = sys.argv[3] if len(sys.argv) > 3 else None
    rows = []
    for i, rate in enumerate((1000, 2000)):
        n, p50, p99 = run_hapticd(bin_dir, rate, seconds, 90 + 2 * i)
        dn, dp50, dp99 = run_ddsperf(rate, seconds, 91 + 2 * i)
        rows.append((rate, n, p50, p99, dn, dp50, dp99))
    lines = ["| rate | hapticd samples | hapticd p50 [us] | hapticd p99 [us] | ddsperf samples | ddsperf p50 [us] | "
             "ddsperf p99 [us] | p50 ratio | p99 ratio |", "|---|---|---|---|---|---|---|---|---|"]
    for rate, n, p50, p99, dn, dp50, dp99 in rows:
        lines.append(f"| {rate} Hz | {n} | {p50:.1f} | {p99:.1f} | {dn} | {dp50:.1f} | {dp99:.1f} | "
                     f"{p50 / dp50:.2f} | {p99 / dp99:.2f} |")
    text = "\n".join(lines)
    print(text)
    if out:
        open(out, "w").write(text + "\n")


if __name__ == "__main__":
    main()
