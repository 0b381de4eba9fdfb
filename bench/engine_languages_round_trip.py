#!/usr/bin/env python3
"""The round trip of a C, a C# (Mono) and a WebSocket (Node, the engine socket) engine against the C++ engine's,
side by side in one run (docs/engine-socket.md, docs/engines.md).

For each engine, alternately and --repeat times: hapticd with the simulated ViSHaRD3 coupled to an engine
(config/sessions/vishard3/dds-coupling.yaml at 1 kHz: the state published every cycle, loopback only, a DDS domain
of its own, an engine socket on a free loopback port) and one engine answering every state with a coupling
command: the C++ scene engine (hapticd-scene-engine: the client library's state callback), the C wall engine
(hapticd-c-wall-engine: the C API's callback), the C# wall engine of tests/csharp (clients/csharp's Engine helper
on Mono) or the Node wall engine of tests/engine_socket (ws, over the engine socket). The server measures each
round trip (state written -> command accepted by the gate) and counts how many cycles after its state each command
was applied. Engines run on CPU 0, the server's loop on the last CPU, as in bench/dds_round_trip.py.
The table gives the medians over the runs and each engine's ratio to C++.
Usage: bench/engine_languages_round_trip.py BUILD_DIR [--seconds S] [--repeat R] [--engines c++,c,c#,websocket]"""
import argparse
import os
import shutil
import socket
import subprocess
import tempfile
import time
from statistics import median

from round_trip_stats import round_trip_of

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SESSION = os.path.join(ROOT, "config", "sessions", "vishard3", "dds-coupling.yaml")
PIN = ["taskset", "-c", "0"] if (os.cpu_count() or 1) >= 2 else []
DOMAIN = 96
TARGET = {"c": 1.1, "c#": 1.3, "websocket": 2.0}  # p50 within this factor of C++ (docs/engine-socket.md)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def build_csharp(build, work):
    """The C# wall engine (tests/csharp) against clients/csharp, with Debian's Mono."""
    sources = [os.path.join(ROOT, "clients", "csharp", "Hapticd", f) for f in ("Client.cs", "Engine.cs", "Native.cs")]
    subprocess.run(["mcs", "-unsafe", "-target:library", "-out:" + os.path.join(work, "Hapticd.dll")] + sources,
                   check=True, stdout=subprocess.DEVNULL)
    subprocess.run(["mcs", "-unsafe", "-r:" + os.path.join(work, "Hapticd.dll"), "-out:" + os.path.join(work, "cs.exe"),
                    os.path.join(ROOT, "tests", "csharp", "CSharpClientTest.cs")], check=True, stdout=subprocess.DEVNULL)


def run(build, engine, seconds, work):
    bin_dir = os.path.join(build, "bin")
    port = free_port()
    stats = os.path.join(work, "stats.json")
    server = subprocess.Popen(
        [os.path.join(bin_dir, "hapticd"), "--config", SESSION, "--dds-domain", str(DOMAIN), "--duration",
         str(seconds + 2.5), "--stats-json", stats, "--log-level", "warn", "--set", "server.rate_hz=1000",
         "--set", f"engine_socket.port={port}"])
    time.sleep(0.5)
    env = dict(os.environ)
    duration = str(seconds + 4)
    if engine == "c++":
        command = [os.path.join(bin_dir, "hapticd-scene-engine"), "--domain", str(DOMAIN), "--duration", duration]
    elif engine == "c":
        command = [os.path.join(bin_dir, "hapticd-c-wall-engine"), "--domain", str(DOMAIN), "--device", "vishard3",
                   "--duration", duration]
    elif engine == "c#":
        env["LD_LIBRARY_PATH"] = os.path.join(build, "lib")
        env["MONO_PATH"] = work
        command = ["mono", os.path.join(work, "cs.exe"), "engine", str(DOMAIN), "vishard3", duration, "0"]
    else:
        command = ["node", os.path.join(ROOT, "tests", "engine_socket", "wall_engine.mjs"), f"ws://127.0.0.1:{port}",
                   "vishard3", duration]
    engine_process = subprocess.Popen(PIN + command, stdout=subprocess.DEVNULL, env=env)  # answers until the end
    server.wait(timeout=seconds + 30)
    engine_process.kill()
    engine_process.wait(timeout=30)
    return round_trip_of(stats)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", help="the build directory (build/default)")
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--engines", default="c++,c,c#,websocket")
    args = parser.parse_args()
    engines = args.engines.split(",")
    if "c#" in engines and not (shutil.which("mcs") and shutil.which("mono")):
        print("no Mono (mono-mcs, mono-runtime): the C# engine is left out")
        engines.remove("c#")
    results = {e: [] for e in engines}
    with tempfile.TemporaryDirectory() as work:
        if "c#" in engines:
            build_csharp(args.build, work)
        for r in range(args.repeat):
            for engine in engines:
                results[engine].append(run(args.build, engine, args.seconds, work))
                m = results[engine][-1]
                print(f"run {r + 1} {engine:9}: round trip p50 {m['p50']:.1f} us, p99 {m['p99']:.1f} us, "
                      f"{m['count']} answered, {m['next_cycle']:.1f} % applied the next cycle", flush=True)
    print("\n| engine | round trip p50 [us] | p99 [us] | states answered | applied the next cycle | p50 / C++ | target |")
    print("|---|---|---|---|---|---|---|")
    med = {e: {k: median(run[k] for run in runs) for k in runs[0]} for e, runs in results.items()}
    for engine, m in med.items():
        ratio = m["p50"] / med["c++"]["p50"] if "c++" in med else float("nan")
        target = f"<= {TARGET[engine]}x" if engine in TARGET else "-"
        print(f"| {engine} | {m['p50']:.1f} | {m['p99']:.1f} | {m['count']:.0f} | {m['next_cycle']:.1f} % | "
              f"{ratio:.2f}x | {target} |")
    print(f"\n({args.repeat} runs of {args.seconds} s each per engine, medians; the loop at 1 kHz)")


if __name__ == "__main__":
    main()
