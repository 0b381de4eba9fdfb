"""A rendering engine in Python that owns the session's haptic scene over the engine socket (docs/haptic-scene.md,
"Engines edit the scene"; the `websockets` package): a table under the hand and a block on it, 3 cm ahead. The
server renders both at loop rate; the engine runs the block's physics at its own frame rate (60 Hz) from what the
hand does to it - each frame it asks for the contacts, pushes the block with the hand's force against the table's
Coulomb friction, and moves it in the scene. So the hand pushes the block across the table and feels it resist.

    python3 block_pusher.py URL [SECONDS]      (URL: the engine socket, e.g. ws://127.0.0.1:8767/)

With config/sessions/vishard3/socket-scene.yaml running and the simulated operator's hand moving forward (its
target at 1.5 cm/s: docs/haptic-scene.md, "A block pushed across a table"), the hand meets the block and pushes it,
with the force of the block's friction while it slides. Prints the block's position and the hand's mean push
once a second and, at the end, how far the block went ("block moved 29.6 mm in 6.0 s").
"""
import asyncio
import json
import math
import signal
import sys

import websockets

FRAME_HZ = 60.0
MASS_KG = 1.0
FRICTION = 0.3  # the block on the table: Coulomb, static and sliding alike
GRAVITY = 9.81
HALF = 0.02  # the block's half edge [m]: it stands higher than the hand


async def run(url: str, seconds: float) -> int:
    async with websockets.connect(url, max_queue=16) as ws:
        json.loads(await ws.recv())  # the inventory
        await ws.send(json.dumps({"session": {"configure": {"profile": {"name": "block-pusher"}}}}))
        answers: asyncio.Queue = asyncio.Queue()
        first_state = asyncio.get_running_loop().create_future()

        async def read():
            async for text in ws:
                m = json.loads(text)
                if "devices" in m and not first_state.done():
                    first_state.set_result(m["devices"][0]["state"]["cursor_position"])
                elif "scene_reply" in m:
                    await answers.put(m["scene_reply"])

        reader = asyncio.create_task(read())
        next_id = 0

        async def scene(op, **fields):
            nonlocal next_id
            next_id += 1
            await ws.send(json.dumps({"scene": {"id": next_id, "op": op, **fields}}))
            if op == "move":
                return None  # answered only when refused
            while True:
                r = await asyncio.wait_for(answers.get(), 5)
                if r["id"] == next_id:
                    if not r["accepted"]:
                        raise RuntimeError(f"{op}: {r['message']}")
                    return r

        hand = await asyncio.wait_for(first_state, 5)
        await scene("claim")
        # The world frame of the session: the table's top 2.5 cm under the hand's start, the block 3 cm ahead on it.
        top = hand["z"] - 0.025
        await scene("add", object={"name": "table", "shape": "box", "size": [0.4, 0.4, 0.02],
                                   "position": [hand["x"] + 0.1, hand["y"], top - 0.01],
                                   "material": {"stiffness": 3000, "damping": 5}})
        block = [hand["x"] + 0.03 + HALF, hand["y"], top + HALF]
        await scene("add", object={"name": "block", "shape": "box", "size": [2 * HALF] * 3, "position": block,
                                   "moving": True, "material": {"stiffness": 2500, "damping": 5}})
        start = list(block)
        velocity = [0.0, 0.0]
        dt = 1.0 / FRAME_HZ
        loop = asyncio.get_running_loop()
        began = loop.time()
        stop = asyncio.Event()
        for s in (signal.SIGINT, signal.SIGTERM):
            loop.add_signal_handler(s, stop.set)
        frame = 0
        pushed = [0.0, 0.0]  # the push summed over the second so far (its mean is printed)
        while not stop.is_set() and loop.time() - began < seconds:
            # The hand's push on the block (its horizontal part: the table carries the rest).
            push = [0.0, 0.0]
            for c in (await scene("contacts"))["contacts"]:
                if c["object"] == "block":
                    push[0] += c["force"]["x"]
                    push[1] += c["force"]["y"]
            # Coulomb friction: the block sticks while the push is within it, else slides against it.
            limit = FRICTION * MASS_KG * GRAVITY
            speed = math.hypot(*velocity)
            if speed < 1e-4 and math.hypot(*push) <= limit:
                velocity = [0.0, 0.0]
            else:
                direction = [v / speed for v in velocity] if speed >= 1e-4 else [p / math.hypot(*push) for p in push]
                for k in range(2):
                    velocity[k] += (push[k] - limit * direction[k]) / MASS_KG * dt
                if sum(v * d for v, d in zip(velocity, direction)) < 0.0:  # friction stops it, never reverses it
                    velocity = [0.0, 0.0]
            block[0] += velocity[0] * dt
            block[1] += velocity[1] * dt
            pushed = [pushed[0] + push[0], pushed[1] + push[1]]
            await scene("move", name="block", position={"x": block[0], "y": block[1], "z": block[2]})
            frame += 1
            if frame % int(FRAME_HZ) == 0:  # the second's mean push: a frame's own moves with the hand's sway
                print(f"block at {1000 * (block[0] - start[0]):+.1f} {1000 * (block[1] - start[1]):+.1f} mm, "
                      f"pushed with {pushed[0] / FRAME_HZ:.2f} {pushed[1] / FRAME_HZ:.2f} N", flush=True)
                pushed = [0.0, 0.0]
            await asyncio.sleep(max(0.0, began + frame * dt - loop.time()))
        moved = math.hypot(block[0] - start[0], block[1] - start[1])
        print(f"block moved {1000 * moved:.1f} mm in {loop.time() - began:.1f} s", flush=True)
        await scene("remove", name="block")  # the scene as the engine found it
        await scene("remove", name="table")
        await scene("release")
        await ws.close()
        await reader
    return 0


if __name__ == "__main__":
    sys.exit(asyncio.run(run(sys.argv[1], float(sys.argv[2]) if len(sys.argv) > 2 else 1e9)))
