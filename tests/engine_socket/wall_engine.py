"""A rendering engine in Python on hapticd's engine socket (WebSocket/JSON, docs/engine-socket.md), with the
`websockets` package: the wall of wall_engine.mjs (2 cm ahead of the start, through the server's virtual
coupling), each state answered with the proxy. The Python client of tests/e2e/engine_socket_test.sh.

    python3 wall_engine.py URL DEVICE DURATION_S
"""
import asyncio
import json
import sys

import websockets


async def run(url: str, device: str, duration: float) -> int:
    client = "python-wall-engine"
    async with websockets.connect(url, max_queue=4) as ws:
        inventory = json.loads(await ws.recv())
        if device not in [d["device_id"] for d in inventory["devices"]]:
            print(f"no device '{device}' in the inventory", file=sys.stderr)
            return 2
        await ws.send(json.dumps({"session": {"configure": {"profile": {"name": client}}}, "subscribe": [device],
                                  "request": {"id": 1, "kind": "claim", "device": device}}))
        start_x = wall_x = None
        answered = 0
        last_x = 0.0
        loop = asyncio.get_running_loop()
        end = loop.time() + duration
        while loop.time() < end:
            try:
                m = json.loads(await asyncio.wait_for(ws.recv(), timeout=max(0.01, end - loop.time())))
            except asyncio.TimeoutError:
                break
            if "reply" in m:
                if not m["reply"]["accepted"]:
                    print(f"cannot claim '{device}': {m['reply']['message']}", file=sys.stderr)
                    return 3
                print(f"claimed '{device}'; a wall 2 cm ahead", flush=True)
                continue
            if "devices" not in m:
                continue
            s = m["devices"][0]["state"]
            x = s["cursor_position"]["x"]
            if start_x is None:
                start_x, wall_x = x, x + 0.02
            last_x = x
            position = dict(s["cursor_position"], x=min(x, wall_x))
            await ws.send(json.dumps({"devices": [{"device_id": device, "state_serial": s["serial"], "commands": {
                "set_coupling": {"position": position, "orientation": s["orientation"]}}}]}))
            answered += 1
        print(f"answered {answered} states; handle {last_x - start_x:.4f} m past the start, the wall at 0.0200 m")
    return 0


if __name__ == "__main__":
    sys.exit(asyncio.run(run(sys.argv[1], sys.argv[2], float(sys.argv[3]))))
