#!/usr/bin/env python3
"""The DDS round trip, side by side with ddsperf, in one run (docs/dds-interface.md).

For each loop rate (1 kHz, 2 kHz): hapticd with the simulated ViSHaRD3 publishing its state every cycle and the
example scene engine (a separate process) answering every state with a coupling command; the server measures
state written -> command accepted (validated and handed to the loop), and how many cycles after the state's
the loop applied the command. Then ddsperf ping/pong (two processes) at the same rate with the same payload
size (the state's, 712 bytes), the same Cyclone configuration (config/dds/cyclonedds-loopback.xml) and the
same triggering (listeners: ddsperf's default, and what the server's command path and the client library's
state path use) and the same placement (the engine and both ddsperf processes on CPU 0, where the server keeps
its DDS threads; the server's loop on the last CPU). Both on the loopback interface only.

ddsperf's ping prints half the round trip as its latency (a one-way estimate). The script does not take that on
trust: it first runs ddsperf with its ping's source timestamps moved 1 ms into the past (the
ddsperf_timestamp_shift.so preload, built next to the programs) and sees how far the printed p50 moves - by 0.5
ms for half round trips, by 1 ms for whole ones - and scales ddsperf's figures to whole round trips accordingly.
Each pair runs twice: as the machine is (idle CPUs sleep), and with CPU 0 kept out of its idle state by a busy
loop in the idle scheduling class (both sides then start their round trips on an awake CPU; leaving the idle
state costs tens of microseconds in virtual machines). ddsperf reports percentiles per second; its p50 and p99
here are the count-weighted means of those. Ours are over every sample of the run (the server's histogram:
percentiles within 1.6 %, never below). Each pair runs --repeat times, alternating, and the table gives the
medians over the runs. Usage: bench/dds_round_trip.py BUILD_BIN_DIR [--seconds S] [--repeat R] [--out OUT.md]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from statistics import median

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
        report = json.load(open(stats))
        rt = report["dds_round_trip_us"]
        applied = report["dds_applied_after_cycles"]
        next_cycle = 100.0 * applied[1] / max(1, sum(applied))
        return rt["count"], rt["p50"], rt["p99"], next_cycle


def run_ddsperf(rate, seconds, domain, preload=None, shift_ns=0):
    """ddsperf ping/pong; returns (samples, p50, p99) as ddsperf prints them."""
    env = dict(os.environ, CYCLONEDDS_URI="file://" + XML)
    pong = subprocess.Popen(PIN + ["ddsperf", "-i", str(domain), "-D", str(seconds + 3), "pong"], env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    time.sleep(0.3)
    ping_env = dict(env)
    if preload:
        ping_env.update(LD_PRELOAD=preload, HAPTICD_DDSPERF_SHIFT_NS=str(shift_ns))
    ping = subprocess.run(PIN + ["ddsperf", "-i", str(domain), "-D", str(seconds), "ping", f"{rate}Hz", "size", str(STATE_BYTES)],
                          env=ping_env, capture_output=True, text=True, timeout=seconds + 30)
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


def ddsperf_round_trip_factor(bin_dir, domain):
    """What ddsperf's printed latency is: 2 if half the round trip, 1 if the round trip (checked, not assumed)."""
    preload = os.path.join(bin_dir, "ddsperf_timestamp_shift.so")
    if not os.path.exists(preload):
        raise RuntimeError(f"{preload} is missing: build the default preset first (scripts/build.sh)")
    shift_us = 1000.0
    _, plain, _ = run_ddsperf(1000, 3, domain)
    _, shifted, _ = run_ddsperf(1000, 3, domain + 1, preload, int(shift_us * 1000))
    moved = (shifted - plain) / shift_us
    for factor in (2, 1):
        if abs(moved - 1.0 / factor) < 0.1:
            print(f"ddsperf check: ping timestamps 1 ms older moved its p50 from {plain:.1f} to {shifted:.1f} us "
                  f"({moved:.3f} of the shift): its figures are {'half round trips' if factor == 2 else 'round trips'}")
            return factor
    raise RuntimeError(f"ddsperf's p50 moved by {moved:.3f} of a 1 ms timestamp shift: neither a round trip nor half of one")


def keep_awake(cpu):
    """A busy loop in the idle scheduling class on `cpu`: it runs only when nothing else wants the CPU and keeps
    the CPU out of its idle state, so no wake-up pays for leaving it (large in virtual machines)."""
    return subprocess.Popen(["taskset", "-c", str(cpu), "chrt", "-i", "0", "sh", "-c", "while :; do :; done"])


def main():
    parser = argparse.ArgumentParser(description="The DDS round trip, side by side with ddsperf.")
    parser.add_argument("bin_dir", help="the build's program directory (build/default/bin)")
    parser.add_argument("--seconds", type=float, default=5.0, help="length of each run")
    parser.add_argument("--repeat", type=int, default=3, help="runs of each pair, alternating hapticd and ddsperf")
    parser.add_argument("--out", help="write the table (markdown) here too")
    args = parser.parse_args()
    factor = ddsperf_round_trip_factor(args.bin_dir, 88)
    conditions = [("idle CPUs sleep", False)] + ([("CPU 0 kept awake", True)] if PIN else [])
    lines = ["| CPUs | rate | hapticd samples | hapticd p50 [us] | hapticd p99 [us] | applied next cycle | ddsperf samples | "
             "ddsperf p50 [us] | ddsperf p99 [us] | p50 ratio | p99 ratio | p50 ratio per run |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    domain = 90
    for name, awake in conditions:
        for rate in (1000, 2000):
            ours, theirs = [], []
            spinner = keep_awake(0) if awake else None
            try:
                for _ in range(args.repeat):
                    ours.append(run_hapticd(args.bin_dir, rate, args.seconds, domain))
                    n, p50, p99 = run_ddsperf(rate, args.seconds, domain + 1)
                    theirs.append((n, factor * p50, factor * p99))
                    domain += 2
            finally:
                if spinner:
                    spinner.kill()
                    spinner.wait()
            p50, p99 = median(r[1] for r in ours), median(r[2] for r in ours)
            dp50, dp99 = median(r[1] for r in theirs), median(r[2] for r in theirs)
            per_run = ", ".join(f"{a[1] / b[1]:.2f}" for a, b in zip(ours, theirs))
            lines.append(f"| {name} | {rate} Hz | {sum(r[0] for r in ours)} | {p50:.1f} | {p99:.1f} | "
                         f"{median(r[3] for r in ours):.2f} % | {sum(r[0] for r in theirs)} | {dp50:.1f} | {dp99:.1f} | "
                         f"{p50 / dp50:.2f} | {p99 / dp99:.2f} | {per_run} |")
            print(lines[-1], flush=True)
    text = "\n".join(lines)
    text += (f"\n\nRound trips in microseconds, medians over {args.repeat} runs of {args.seconds:g} s each (samples: all runs); "
             f"ddsperf's printed figures x{factor}{' (it prints half round trips)' if factor == 2 else ''}. "
             "Target: p50 ratio at most 1.3.")
    print("\n" + text)
    if args.out:
        open(args.out, "w").write(text + "\n")


if __name__ == "__main__":
    main()
