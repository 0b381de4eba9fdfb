#!/usr/bin/env bash
# Free-space drag with the haptic scene in the server, whatever the engine's frame rate (issue 64's table again,
# with the scene; docs/haptic-scene.md, "Measured"). In real time: the simulated operator's hand sweeps 6 cm in
# 0.3 s (a sine of 3 cm at 1.67 Hz along x) through free space on config/sessions/vishard3/socket-scene.yaml, while
# a Python engine on the engine socket (websockets) owns the scene - a table under the hand's path and a block
# beyond its reach, both at least 8 mm from the proxy's path - and, at its frame rate, moves the block (its own
# physics: the block glides 2 cm to and fro) and asks for the contacts, as a VR application does each frame. The
# force on the hand is the scene's (the recording's wrench/environment); the table gives its p50/p99/max over the
# run, the frames the engine sent and the contacts it got back (none: the hand touches nothing).
# Usage: scripts/measure-scene-drag.sh [SECONDS_PER_ROW] [OUT_DIR]     (BUILD=build/ci to use another build)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-4}
out=${2:-build/scene-drag}
build=${BUILD:-build/default}
hapticd=$build/bin/hapticd
python=/usr/bin/python3 # Debian's: websockets and h5py
mkdir -p "$out"
[ -x "$hapticd" ] || bash scripts/build.sh default > /dev/null
port=$((20000 + RANDOM % 20000))

engine() { # RATE_HZ SECONDS ROW BLOCK_DX
  "$python" - "ws://127.0.0.1:$port/" "$1" "$2" "$out/engine-$3.json" "$4" <<'PY'
import asyncio, json, math, sys, time
import websockets

url, rate, seconds, report, block_dx = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4], float(sys.argv[5])

async def main():
    for _ in range(100):  # the server is starting
        try:
            ws = await websockets.connect(url)
            break
        except OSError:
            await asyncio.sleep(0.05)
    json.loads(await ws.recv())  # the inventory
    await ws.send(json.dumps({"session": {"configure": {"profile": {"name": "drag-engine"}}}}))
    answers = asyncio.Queue()
    start_state = asyncio.get_running_loop().create_future()

    async def read():
        async for text in ws:
            m = json.loads(text)
            if "devices" in m and not start_state.done():
                start_state.set_result(m["devices"][0]["state"]["cursor_position"])
            if "scene_reply" in m or "error" in m:
                await answers.put(m)
    reader = asyncio.create_task(read())
    next_id = 0

    async def ask(op, **fields):
        nonlocal next_id
        next_id += 1
        await ws.send(json.dumps({"scene": {"id": next_id, "op": op, **fields}}))
        if op == "move":
            return None
        while True:
            m = await asyncio.wait_for(answers.get(), 5)
            if m.get("scene_reply", {}).get("id") == next_id:
                if not m["scene_reply"]["accepted"]:
                    raise SystemExit(f"{op} refused: {m['scene_reply']['message']}")
                return m["scene_reply"]

    # Placed from where the handle is (world frame): it sweeps x within about +-4 cm of its start and dips 3 mm;
    # the proxy's radius is 5 mm. The table's top 13 mm under the start, the block's near face 6.5 cm ahead.
    c = await asyncio.wait_for(start_state, 5)
    x0, y0, z0 = c["x"], c["y"], c["z"]
    await ask("claim")
    await ask("add", object={"name": "table", "shape": "box", "size": [0.3, 0.3, 0.02],
                             "position": [x0, y0, z0 - 0.023], "material": {"stiffness": 3000}})
    await ask("add", object={"name": "block", "shape": "box", "size": [0.03, 0.03, 0.03], "moving": True,
                             "position": [x0 + block_dx, y0, z0], "material": {"stiffness": 3000}})
    frames = contacts = 0
    start = time.monotonic()
    while (now := time.monotonic() - start) < seconds:
        y = y0 + 0.01 * math.sin(2 * math.pi * 0.5 * now)
        await ask("move", name="block", position=[x0 + block_dx, y, z0], orientation=[1, 0, 0, 0])
        contacts += len((await ask("contacts"))["contacts"])
        frames += 1
        await asyncio.sleep(max(0.0, (frames / rate) - (time.monotonic() - start)))
    json.dump({"rate_hz": rate, "frames": frames, "seconds": seconds, "contacts": contacts}, open(report, "w"))
    await ws.close()
    await reader

asyncio.run(main())
PY
}

# The last row is the control: the block within the hand's reach, so the same measurement sees a force.
for row in none 24 30 45 60 72 90 120 144 240 control; do
  rate=$row block_dx=0.08
  [ "$row" != control ] || rate=90 block_dx=0.04
  echo "== $row" >&2
  args=(--config config/sessions/vishard3/socket-scene.yaml --duration "$((seconds + 2))" --log-level warn
    --set dds.enabled=false --set "engine_socket.port=$port" --record "$out/drag-$row.h5"
    --set devices.vishard3.device.parameters.operator_motion=sine
    --set "devices.vishard3.device.parameters.operator_motion_m=[0.044,0,0]"
    --set devices.vishard3.device.parameters.operator_motion_frequency_hz=1.667
    --set devices.vishard3.device.parameters.operator_motion_start_s=1.0)
  "$hapticd" "${args[@]}" &
  server=$!
  if [ "$row" != none ]; then engine "$rate" "$seconds" "$row" "$block_dx" || { kill "$server"; exit 1; }; fi
  wait "$server"
done

"$python" - "$out" <<'PY'
import json, os, platform, sys
import h5py, numpy as np
out = sys.argv[1]
print(f"Free-space drag with the scene, this machine ({platform.processor() or platform.machine()}, {os.cpu_count()} cores): "
      "the force on the hand while it sweeps 6 cm in 0.3 s, from 1 s after the start")
print()
print("| engine's frame rate | frames sent | contacts answered | force on the hand p50 / p99 / max (N) | hand's travel (mm), peak speed (m/s) |")
print("|---|---|---|---|---|")
for row in ["none", "24", "30", "45", "60", "72", "90", "120", "144", "240", "control"]:
    with h5py.File(f"{out}/drag-{row}.h5") as f:
        d = f["devices/vishard3"]
        t = d["time_s"][:]
        force = np.linalg.norm(d["wrench/environment"][:, :3], axis=1)
        x = d["handle/pose"][:, 0]
    keep = t > t[0] + 1.0
    f = force[keep]
    travel = (x[keep].max() - x[keep].min()) * 1000
    speed = np.abs(np.gradient(x[keep], t[keep])).max()
    if row == "none":
        frames = contacts = "-"
    else:
        e = json.load(open(f"{out}/engine-{row}.json"))
        frames, contacts = f"{e['frames']} in {e['seconds']:.0f} s", str(e["contacts"])
    name = "90, the block in reach (control)" if row == "control" else row
    print(f"| {name} | {frames} | {contacts} | {np.percentile(f, 50):.2f} / {np.percentile(f, 99):.2f} / {f.max():.2f} | {travel:.0f}, {speed:.2f} |")
PY
