#!/usr/bin/env python3
"""The loop's timing under a flood of junk packets, against the same run without it (docs/measurements.md).

The hardening issue's attack: UDP datagrams with an RTPS header and junk after it, at 10 000 per second, to the
server's Cyclone DDS ports on 127.0.0.1 (every unicast port of participant indices 0..9 on the domain). Before,
Cyclone wrote one warning per packet (67 MB of log in 20 s) and the loop's overruns, the engine's deadline misses
and the round trip's maximum went up. Each condition runs hapticd (config/sessions/vishard3/dds-coupling.yaml, real
time) with the example scene engine answering every state; the flooded run sends for the whole session but its
first and last second. Runs alternate (--repeat times each); the table gives every run and the log's size.
Loopback only: no packet is sent anywhere but 127.0.0.1. Usage: bench/junk_flood.py BUILD_BIN_DIR [--seconds S]
[--rate R] [--repeat N] [--domain D]
"""
import argparse
import json
import os
import random
import socket
import subprocess
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SESSION = os.path.join(ROOT, "config", "sessions", "vishard3", "dds-coupling.yaml")


def flood(domain, rate, seconds, stop):
    """Sends junk RTPS datagrams to the domain's unicast ports on 127.0.0.1; returns how many were sent."""
    base = 7400 + 250 * domain
    ports = [base + 10 + 2 * i + k for i in range(10) for k in (0, 1)]
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    rng = random.Random(17)
    # A well-formed RTPS header (version 2.1, a vendor id, a GUID prefix), then junk submessages: what Cyclone
    # parses far enough to warn about (a wrong version is dropped silently).
    junk = [b"RTPS\x02\x01\x01\x10" + bytes(rng.getrandbits(8) for _ in range(12 + rng.randint(16, 200)))
            for _ in range(64)]
    sent, start = 0, time.monotonic()
    while not stop.is_set() and time.monotonic() - start < seconds:
        due = int((time.monotonic() - start) * rate)
        while sent < due:
            try:
                sock.sendto(junk[sent % len(junk)], ("127.0.0.1", ports[sent % len(ports)]))
            except OSError:
                pass
            sent += 1
        time.sleep(0.002)
    return sent


def run(bin_dir, seconds, rate, domain, flooded):
    with tempfile.TemporaryDirectory() as tmp:
        session = os.path.join(tmp, "session.yaml")
        stats = os.path.join(tmp, "stats.json")
        log = os.path.join(tmp, "server.log")
        text = open(SESSION).read().replace("../../urdf/", os.path.join(ROOT, "config", "urdf") + "/")
        open(session, "w").write(text)
        with open(log, "wb") as out:
            everywhere = {"preexec_fn": lambda: os.sched_setaffinity(0, range(os.cpu_count() or 1))}
            server = subprocess.Popen([os.path.join(bin_dir, "hapticd"), "--config", session, "--duration", str(seconds),
                                       "--dds-domain", str(domain), "--stats-json", stats], stdout=out, stderr=out,
                                      **everywhere)
            time.sleep(0.3)
            engine = subprocess.Popen([os.path.join(bin_dir, "hapticd-scene-engine"), "--domain", str(domain),
                                       "--duration", str(seconds + 3)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                      **everywhere)
            sent = 0
            if flooded:
                time.sleep(1.0)
                stop = threading.Event()
                result = []
                sender = threading.Thread(target=lambda: result.append(flood(domain, rate, seconds - 2.0, stop)))
                sender.start()
                sender.join()
                sent = result[0]
            server.wait(timeout=seconds + 60)
            engine.wait(timeout=30)
        report = json.load(open(stats))
        return {
            "flooded": flooded,
            "sent": sent,
            "log_bytes": os.path.getsize(log),
            "overruns": report["overruns"],
            "cycles": report["cycles"],
            "latency_p99": report["wakeup_latency_us"]["p99"],
            "latency_max": report["wakeup_latency_us"]["max"],
            "rt_p50": report.get("dds_round_trip_us", {}).get("p50", float("nan")),
            "rt_max": report.get("dds_round_trip_us", {}).get("max", float("nan")),
            "deadline_misses": report["dds"]["deadline_misses"],
            "log_suppressed": report["dds"]["log_suppressed"],
            "exit": server.returncode,
            "faults": ", ".join(f"{e['fault']} at {e['time_s']:.2f} s" for d in report["devices"] for e in d["safety_events"] if e["event"] == "fault")
                      or "-",
        }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("bin_dir")
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--rate", type=float, default=10000.0)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--domain", type=int, default=88)
    parser.add_argument("--flood-cpu", type=int, default=-1,
                        help="pin the sender to this CPU (-1: wherever the scheduler puts it, as an attacker would)")
    args = parser.parse_args()
    if args.flood_cpu >= 0:  # the sender thread inherits it; the server and engine are started with their own
        os.sched_setaffinity(0, {args.flood_cpu})
    rows = []
    for _ in range(args.repeat):
        for flooded in (False, True):
            rows.append(run(args.bin_dir, args.seconds, args.rate, args.domain, flooded))
    print(f"{args.seconds:g} s sessions, junk at {args.rate:g} datagrams/s in the flooded runs, sender on "
          f"{'CPU ' + str(args.flood_cpu) if args.flood_cpu >= 0 else 'any CPU'} (`bench/junk_flood.py {args.bin_dir} "
          f"--seconds {args.seconds:g} --repeat {args.repeat} --flood-cpu {args.flood_cpu}`)\n")
    print("| run | datagrams | log | overruns | wake-up p99 / max [us] | round trip p50 / max [us] | deadline misses | "
          "Cyclone lines suppressed | faults | exit |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {'flood' if r['flooded'] else 'quiet'} | {r['sent']} | {r['log_bytes'] / 1024:.1f} kB | "
              f"{r['overruns']} of {r['cycles']} | {r['latency_p99']:.1f} / {r['latency_max']:.1f} | "
              f"{r['rt_p50']:.1f} / {r['rt_max']:.1f} | {r['deadline_misses']} | {r['log_suppressed']} | {r['faults']} | {r['exit']} |")


if __name__ == "__main__":
    main()
