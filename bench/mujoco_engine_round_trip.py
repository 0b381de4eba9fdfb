#!/usr/bin/env python3
"""The MuJoCo engine's time per state for each shipped scene, and its round trip against the scene engine's, side by
side in one run (docs/engines.md, "Physics engines").

For each scene of config/scenes/ (its own session: the simulated ViSHaRD3 at 1 kHz, the ViSHaRD10 at 2 kHz, the
bimanual pair at 1 kHz as one group) and for the reference - the C++ scene engine (hapticd-scene-engine: a wall, a
cube and a sphere computed by hand) on config/sessions/vishard3/dds-coupling.yaml at 1 kHz - alternately and
--repeat times: hapticd (the state published every cycle, loopback only, a DDS domain of its own) and the engine
answering every state with a coupling command, while the simulated operator moves the hand into the scene's objects
(hapticctl operator move) so that contacts happen. The server measures each round trip (state written -> command
accepted by the gate) and counts how many cycles after its state each command was applied; the MuJoCo engine
reports its own time per state (stepping the world and sending the command). Engines on CPU 0, the server's loop on
the last CPU, as in bench/dds_round_trip.py. The table gives the medians over the runs.
Usage: bench/mujoco_engine_round_trip.py BUILD_DIR [--seconds S] [--repeat R] [--scenes table-blocks,...]"""
import argparse
import os
import re
import subprocess
import tempfile
import time
from statistics import median

from round_trip_stats import round_trip_of

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = os.path.join(ROOT, "config", "scenes")
PIN = ["taskset", "-c", "0"] if (os.cpu_count() or 1) >= 2 else []
DOMAIN = 97
# Each scene's device (or group) and the operator's moves that bring the hand into its objects.
RUNS = {
    "scene-engine": ("vishard3", None, [(0.04, 0, 0), (-0.04, 0, 0)]),
    "table-blocks": ("vishard3", None, [(0.045, 0, 0), (-0.045, 0, -0.025), (0, 0.05, 0), (0, -0.05, 0.025)]),
    "peg-in-hole": ("vishard3", None, [(0.03, 0, 0), (0, 0, -0.035), (0, 0, 0.035), (-0.03, 0, 0)]),
    "door-drawer": ("vishard3", None, [(0.07, 0, 0), (-0.07, 0, 0), (-0.08, 0, -0.02), (0.08, 0, 0.02)]),
    "vishard10-workspace": ("vishard10", None, [(0, 0, -0.08), (0, 0, 0.08)]),
    "bimanual-box": ("left", "hands", [(0.01, 0, 0), (0, 0, 0.05)]),
}


def run(build, scene, seconds, work):
    bin_dir = os.path.join(build, "bin")
    stats = os.path.join(work, "stats.json")
    device, group, moves = RUNS[scene]
    session = (os.path.join(ROOT, "config", "sessions", "vishard3", "dds-coupling.yaml") if scene == "scene-engine"
               else os.path.join(SCENES, scene + ".yaml"))
    rate = ["--set", "server.rate_hz=1000"] if scene == "scene-engine" else []
    server = subprocess.Popen(
        [os.path.join(bin_dir, "hapticd"), "--config", session, "--dds-domain", str(DOMAIN), "--duration",
         str(seconds + 2.5), "--stats-json", stats, "--log-level", "warn"] + rate)
    time.sleep(0.5)
    log = os.path.join(work, "engine.log")
    duration = str(seconds + 4)
    if scene == "scene-engine":
        command = [os.path.join(bin_dir, "hapticd-scene-engine"), "--domain", str(DOMAIN), "--duration", duration]
    else:
        command = [os.path.join(bin_dir, "hapticd-mujoco-engine"), os.path.join(SCENES, scene + ".xml"),
                   "--domain", str(DOMAIN), "--duration", duration, "--wait", "3"]
        command += ["--group", group] if group else ["--device", device]
    with open(log, "w") as out:
        engine = subprocess.Popen(PIN + command, stdout=out, stderr=subprocess.STDOUT)
        time.sleep(1.5)
        step = max(0.3, (seconds - 1.0) / max(1, len(moves)))
        for dx, dy, dz in moves:
            for d in ([device] if not group else ["left", "right"]):
                sign = -1.0 if d == "right" else 1.0
                subprocess.run([os.path.join(bin_dir, "hapticctl"), "--domain", str(DOMAIN), "--timeout", "2",
                                "operator", d, "move", str(sign * dx), str(dy), str(dz), str(step * 0.6)],
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            time.sleep(step)
        server.wait(timeout=seconds + 30)
        engine.terminate()
        engine.wait(timeout=30)
    result = round_trip_of(stats)
    with open(log) as f:
        text = f.read()
    m = re.search(r"time per state p50 ([0-9.]+) us, p99 ([0-9.]+) us", text)
    result["engine_p50"] = float(m.group(1)) if m else float("nan")
    result["engine_p99"] = float(m.group(2)) if m else float("nan")
    result["unstable"] = text.count("reset an unstable world")
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build", help="the build directory (build/default)")
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--scenes", default=",".join(RUNS))
    args = parser.parse_args()
    scenes = args.scenes.split(",")
    results = {s: [] for s in scenes}
    with tempfile.TemporaryDirectory() as work:
        for r in range(args.repeat):
            for scene in scenes:
                results[scene].append(run(args.build, scene, args.seconds, work))
                m = results[scene][-1]
                print(f"run {r + 1} {scene:20}: round trip p50 {m['p50']:.1f} us, p99 {m['p99']:.1f} us, "
                      f"{m['next_cycle']:.1f} % applied the next cycle; engine per state p50 {m['engine_p50']:.1f} us,"
                      f" p99 {m['engine_p99']:.1f} us; {m['unstable']} unstable", flush=True)
    print("\n| scene | engine per state p50 [us] | p99 [us] | round trip p50 [us] | p99 [us] | applied the next cycle |"
          " p50 / scene engine |")
    print("|---|---|---|---|---|---|---|")
    med = {s: {k: median(run[k] for run in runs) for k in runs[0]} for s, runs in results.items()}
    for scene, m in med.items():
        ratio = m["p50"] / med["scene-engine"]["p50"] if "scene-engine" in med else float("nan")
        engine = "-" if scene == "scene-engine" else f"{m['engine_p50']:.1f}"
        engine99 = "-" if scene == "scene-engine" else f"{m['engine_p99']:.1f}"
        print(f"| {scene} | {engine} | {engine99} | {m['p50']:.1f} | {m['p99']:.1f} | {m['next_cycle']:.1f} % | "
              f"{ratio:.2f}x |")
    print(f"\n({args.repeat} runs of {args.seconds} s each per scene, medians)")


if __name__ == "__main__":
    main()
