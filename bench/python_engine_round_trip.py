#!/usr/bin/env python3
"""The round trip of a Python engine against the C++ scene engine's, side by side in one run (docs/python.md).

For each engine, alternately and --repeat times: hapticd with the simulated ViSHaRD3 coupled over DDS
(config/sessions/vishard3/dds-coupling.yaml: the state published every cycle at 2 kHz, loopback only, a domain of
its own) and one engine answering every state with a coupling command - the C++ example scene engine
(hapticd-scene-engine: the client library's state callback on Cyclone's receive thread) or the Python wall engine
(examples/python/wall_engine.py: hapticd.run_engine, the client library's engine helper calling a Python
function per state on the receive thread, holding the GIL for the call). The server
measures each round trip (state written -> command accepted) and counts how many cycles after its state each
command was applied. Both engines run on CPU 0, the server's loop on the last CPU, as in bench/dds_round_trip.py.
The table gives the medians over the runs and the ratio Python / C++.
Usage: bench/python_engine_round_trip.py BUILD_DIR [--seconds S] [--repeat R]"""
import argparse
import os
import subprocess
import tempfile
import time
from statistics import median

from round_trip_stats import round_trip_of

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SESSION = os.path.join(ROOT, "config", "sessions", "vishard3", "dds-coupling.yaml")
PIN = ["taskset", "-c", "0"] if (os.cpu_count() or 1) >= 2 else []
DOMAIN = 95


def run(build, engine, seconds):
    bin_dir = os.path.join(build, "bin")
    with tempfile.TemporaryDirectory() as tmp:
        stats = os.path.join(tmp, "stats.json")
        server = subprocess.Popen(
            [os.path.join(bin_dir, "hapticd"), "--config", SESSION, "--dds-domain", str(DOMAIN), "--duration",
             str(seconds + 1.5), "--stats-json", stats, "--log-level", "warn"])
        time.sleep(0.3)
        if engine == "c++":
            command = [os.path.join(bin_dir, "hapticd-scene-engine"), "--domain", str(DOMAIN), "--duration",
                       str(seconds + 3)]
        else:
            # the interpreter the package is built for, whatever python3 runs this script
            command = [os.path.join(bin_dir, "hapticd-python"), os.path.join(ROOT, "examples", "python",
                       "wall_engine.py"), "--domain", str(DOMAIN), "--duration", str(seconds + 3)]
        engine_process = subprocess.Popen(PIN + command, stdout=subprocess.DEVNULL)  # both answer until the end
        server.wait(timeout=seconds + 30)
        engine_process.wait(timeout=30)
        return round_trip_of(stats)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", help="the build directory (build/default)")
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    results = {"c++": [], "python": []}
    for r in range(args.repeat):
        for engine in results:
            results[engine].append(run(args.build, engine, args.seconds))
            m = results[engine][-1]
            print(f"run {r + 1} {engine:6}: round trip p50 {m['p50']:.1f} us, p99 {m['p99']:.1f} us, "
                  f"{m['count']} answered, {m['next_cycle']:.1f} % applied the next cycle", flush=True)
    print(f"\n| engine | round trip p50 [us] | p99 [us] | states answered | applied the next cycle |")
    print("|---|---|---|---|---|")
    med = {}
    for engine, runs in results.items():
        med[engine] = {k: median(run[k] for run in runs) for k in runs[0]}
        m = med[engine]
        print(f"| {engine} | {m['p50']:.1f} | {m['p99']:.1f} | {m['count']:.0f} | {m['next_cycle']:.1f} % |")
    print(f"\nPython / C++: p50 {med['python']['p50'] / med['c++']['p50']:.2f}x, "
          f"p99 {med['python']['p99'] / med['c++']['p99']:.2f}x ({args.repeat} runs of {args.seconds} s each, medians)")


if __name__ == "__main__":
    main()
