"""Engines editing the session's haptic scene over the engine socket (docs/haptic-scene.md, "Engines edit the
scene"), as a Python engine would (websockets): tests/e2e/scene_socket_test.sh runs it against
config/sessions/vishard3/socket-scene.yaml. Each check prints "ok: ..." or raises.

  scene_client.py URL
"""
import asyncio
import json
import sys

import websockets

TIMEOUT = 5.0


class Client:
    """A connection whose messages a background task reads as they come (a client that stops reading while states
    wait is disconnected): the newest state is kept, answers and errors are queued."""

    def __init__(self, ws):
        self.ws = ws
        self.next_id = 0
        self.state = None
        self.answers = asyncio.Queue()
        self.reader = asyncio.create_task(self.read())

    @classmethod
    async def connect(cls, url, name):
        ws = await websockets.connect(url)
        json.loads(await asyncio.wait_for(ws.recv(), TIMEOUT))  # the inventory
        await ws.send(json.dumps({"session": {"configure": {"profile": {"name": name}}}}))
        return cls(ws)

    async def read(self):
        try:
            async for text in self.ws:
                m = json.loads(text)
                if "devices" in m:
                    self.state = m["devices"][0]["state"]
                else:
                    await self.answers.put(m)
        except websockets.ConnectionClosed:
            pass

    async def close(self):
        await self.ws.close()
        await self.reader

    async def next_answer(self, key, wanted=None, timeout=TIMEOUT):
        """The next message with `key` (and, when given, that id); None when none comes within timeout."""
        deadline = asyncio.get_running_loop().time() + timeout
        while True:
            left = deadline - asyncio.get_running_loop().time()
            if left <= 0:
                return None
            try:
                m = await asyncio.wait_for(self.answers.get(), left)
            except asyncio.TimeoutError:
                return None
            if key in m and (wanted is None or m[key].get("id") == wanted):
                return m[key]

    async def scene(self, op, **fields):
        """Sends a scene edit and returns its reply (a move that went through has none: None then)."""
        self.next_id += 1
        await self.ws.send(json.dumps({"scene": {"id": self.next_id, "op": op, **fields}}))
        return await self.reply(self.next_id, wait=op != "move")

    async def reply(self, wanted, wait=True):
        r = await self.next_answer("scene_reply", wanted, TIMEOUT if wait else 0.2)
        if r is None and wait:
            raise AssertionError(f"no answer to scene edit {wanted}")
        return r

    async def raw(self, text):
        """Sends a message as it is and returns the first error it gets."""
        await self.ws.send(text)
        e = await self.next_answer("error")
        if e is None:
            raise AssertionError("no error for " + text)
        return e

    async def newest_state(self, seconds):
        """The newest state after `seconds`."""
        await asyncio.sleep(seconds)
        return self.state

    async def operator(self, name, *values):
        self.next_id += 1
        await self.ws.send(json.dumps({"request": {"id": self.next_id, "kind": "operator", "device": "vishard3",
                                                   "name": name, "values": list(values)}}))
        r = await self.next_answer("reply", self.next_id)
        assert r is not None and r["accepted"], r


def sheet_mesh(x, y, z, n=40, size=0.2):
    """A flat sheet in the plane at x (world) about (y, z), facing -x: (n + 1)^2 vertices, 2 n^2 triangles,
    flattened."""
    vertices = []
    for i in range(n + 1):
        for j in range(n + 1):
            vertices += [round(c, 7) for c in (x, y - size / 2 + size * i / n, z - size / 2 + size * j / n)]
    triangles = []
    for i in range(n):
        for j in range(n):
            a = i * (n + 1) + j
            b, c = a + 1, a + n + 1
            triangles += [a, b, c, b, c + 1, c]
    return vertices, triangles


async def upload(client, name, vertices, triangles, per_part=600):
    """Uploads a mesh in parts of at most per_part numbers of each list (a part's message must stay within the
    socket's 16 KB: 600 coordinates of up to 11 characters and 600 indices of up to 5); the last part's reply."""
    v = [vertices[k:k + per_part] for k in range(0, len(vertices), per_part)]
    t = [triangles[k:k + per_part] for k in range(0, len(triangles), per_part)]
    parts = max(len(v), len(t))
    r = None
    for k in range(parts):
        r = await client.scene("upload", upload=name, part=k, parts=parts, vertices=v[k] if k < len(v) else [],
                               triangles=t[k] if k < len(t) else [])
        if not r["accepted"]:
            return r
    return r


def check(condition, what, detail=""):
    if not condition:
        raise AssertionError(f"{what}: {detail}")
    print("ok:", what, flush=True)


async def main(url):
    owner = await Client.connect(url, "scene-owner")
    intruder = await Client.connect(url, "intruder")
    start = (await owner.newest_state(0.5))["cursor_position"]
    x0 = start["x"]

    # Edits before a claim are refused; the owner claims; a second claim is refused.
    r = await owner.scene("add", object={"name": "wall", "shape": "plane"})
    check(not r["accepted"] and "claim the scene first" in r["message"], "an edit before the claim is refused", r)
    r = await owner.scene("claim")
    check(r["accepted"], "the owner claims the scene", r)
    r = await intruder.scene("claim")
    check(not r["accepted"] and "scene-owner" in r["message"], "a second claim is refused, naming the owner", r)

    # A wall 2 cm ahead of the handle (its plane lies the proxy's radius further); the operator pushes 15 N into it.
    wall = {"name": "wall", "shape": "plane", "position": [x0 + 0.025, 0, 0], "normal": [-1, 0, 0],
            "material": {"stiffness": 3000, "damping": 10}}
    r = await owner.scene("add", object=wall)
    check(r["accepted"], "the owner adds a wall", r)
    r = await intruder.scene("add", object=dict(wall, name="wall2"))
    check(not r["accepted"] and "claimed by 'scene-owner'" in r["message"], "the intruder's add is refused", r)
    r = await intruder.scene("remove", name="wall")
    check(not r["accepted"], "the intruder's removal is refused", r)
    await owner.operator("push", 15.0, 0.0, 0.0, 0.2)
    x = (await owner.newest_state(1.5))["cursor_position"]["x"] - x0
    check(0.015 < x < 0.03, "the wall holds the 15 N push", f"{x * 1000:.1f} mm past the start")
    print(f"   the handle rests {x * 1000:.1f} mm past its start, the wall's surface at 20 mm", flush=True)

    # Two-way: what the hand does to the wall, as the engine asks at its frame rate (anyone may ask).
    felt = -owner.state["environment_force"]["x"]
    r = await intruder.scene("contacts")
    on_wall = [c for c in r["contacts"] if c["object"] == "wall" and c["device"] == "vishard3"]
    check(r["accepted"] and len(on_wall) == 1, "the hand's contact with the wall is reported", r)
    push = on_wall[0]["force"]
    check(abs(push["x"] - felt) < 0.1 * felt + 0.2 and abs(push["y"]) < 0.05 and abs(push["z"]) < 0.05,
          "the wall is pushed with the force the hand feels, reversed", f"{push} against {felt:.2f} N felt")
    print(f"   the hand pushes the wall with {push['x']:.2f} N; it feels {felt:.2f} N", flush=True)

    # A mesh uploaded in parts: a flat sheet 1 mm behind the wall's plane (felt once the wall is gone, below).
    vertices, triangles = sheet_mesh(x0 + 0.026, start["y"], start["z"])
    r = await upload(owner, "sheet", vertices, triangles)
    check(r["accepted"] and "finished: 1681 vertices, 3200 triangles" in r["message"],
          "a mesh of 3200 triangles is uploaded in parts", r)
    r = await intruder.scene("upload", upload="mine", part=0, parts=1, vertices=[0, 0, 0], triangles=[])
    check(not r["accepted"] and "claimed by 'scene-owner'" in r["message"], "the intruder's upload is refused", r)
    r = await owner.scene("upload", upload="stray", part=1, parts=3, vertices=[0, 0, 0], triangles=[])
    check(not r["accepted"] and "out of order" in r["message"], "a part out of order is refused", r)
    await owner.ws.send('{"scene": {"id": 9100, "op": "upload", "upload": "inf", "part": 0, "parts": 1, '
                        '"vertices": [0, 0, 1e999], "triangles": []}}')
    r = await owner.reply(9100)
    check(not r["accepted"] and "not finite" in r["message"], "an infinite vertex is refused", r)
    r = await upload(owner, "broken", [0, 0, 0, 0.01, 0, 0, 0, 0.01, 0], [0, 1, 7])
    check(r["accepted"], "a mesh naming a vertex it lacks is uploaded", r)
    r = await owner.scene("add", object={"name": "broken", "shape": "mesh", "upload": "broken"})
    check(not r["accepted"] and "mesh 'broken'" in r["message"] and "vertex 7" in r["message"],
          "its add is refused, naming the object and the vertex", r)
    r = await owner.scene("add", object={"name": "ghost", "shape": "mesh", "upload": "ghost"})
    check(not r["accepted"] and "no finished upload 'ghost'" in r["message"], "an add of no upload is refused", r)
    r = await owner.scene("add", object={"name": "sheet", "shape": "mesh", "upload": "sheet",
                                         "material": {"stiffness": 3000, "damping": 10}})
    check(r["accepted"], "the uploaded sheet is added", r)
    r = await owner.scene("list")
    sheet = [o for o in r["objects"] if o["name"] == "sheet"]
    check(len(sheet) == 1 and sheet[0]["shape"] == "mesh" and sheet[0]["triangles"] == 3200,
          "the list shows the sheet's 3200 triangles", r["objects"])

    # Drawn for anyone (the browser's scene page draws from this): the objects with their sizes and the proxies;
    # a mesh's triangles in pages, every corner where it was uploaded (to 0.1 mm).
    r = await intruder.scene("draw")
    drawn = {o["name"]: o for o in r["drawing"]["objects"]}
    proxies = r["drawing"]["proxies"]
    check(r["accepted"] and drawn["wall"]["shape"] == "plane" and drawn["sheet"]["triangles"] == 3200 and
          "corners_0_1mm" in drawn["sheet"] and drawn["sheet"]["corners_0_1mm"] == [] and
          [p["device"] for p in proxies] == ["vishard3"] and abs(proxies[0]["radius"] - 0.005) < 1e-9,
          "anyone draws the scene: its objects, no triangles, and the proxy", r)
    pages, corners, first = 0, [], 0
    while True:
        r = await intruder.scene("draw", name="sheet", max_triangles=5000, first=first)
        c = r["drawing"]["objects"][0]["corners_0_1mm"] if r["accepted"] else []
        if not c:
            break
        pages, corners, first = pages + 1, corners + c, first + len(c) // 9
    uploaded = sorted(tuple(sorted(tuple(round(vertices[3 * v + k] * 1e4) for k in range(3))
                                   for v in triangles[3 * t:3 * t + 3])) for t in range(len(triangles) // 3))
    got = sorted(tuple(sorted(tuple(corners[9 * t + 3 * i:9 * t + 3 * i + 3]) for i in range(3)))
                 for t in range(len(corners) // 9))
    # (float corners: a coordinate may round to the next tenth of a millimetre, the same for every vertex)
    same = len(got) == len(uploaded) and all(abs(a - b) <= 1 for g, u in zip(got, uploaded)
                                              for gc, uc in zip(g, u) for a, b in zip(gc, uc))
    check(pages == 8 and same, "the sheet is drawn in 8 pages of 400 triangles, as uploaded",
          f"{pages} pages, {len(got)} triangles")
    r = await intruder.scene("draw", name="sheet", max_triangles=1000)
    check(r["accepted"] and r["drawing"]["objects"][0]["drawn"] == 800 and r["drawing"]["proxies"] == [],
          "drawn with at most 1000 of its triangles: every 4th", r["message"])
    r = await intruder.scene("draw", name="ghost")
    check(not r["accepted"] and "no object named 'ghost'" in r["message"], "drawing no object is refused", r)
    await intruder.ws.send('{"scene": {"id": 9200, "op": "draw", "name": "sheet", "max_triangles": 1e9}}')
    e = await intruder.next_answer("error")
    check(e is not None and "max_triangles" in e["message"], "a drawing of a billion triangles is malformed", e)

    # Bad edits: each refused with its reason, the wall still there.
    bad = [
        ("add", {"object": {"name": "ball", "shape": "sphere", "radius": -1}}, "object.radius: must be positive"),
        ("add", {"object": {"name": "rock", "shape": "mesh", "file": "/etc/passwd"}}, "not read"),
        ("add", {"object": {"name": "wall", "shape": "sphere", "radius": 0.01}}, "is taken"),
        ("add", {"object": {"name": "ball", "shape": "sphere", "radius": 0.01, "material": "unobtainium"}},
         "no material 'unobtainium'"),
        ("material", {"name": "wall", "material": {"stiffness": -5}}, "must be positive"),
        ("move", {"name": "wall", "position": {"x": 0, "y": 0, "z": 0}}, "was not made a moving object"),
        ("remove", {"name": "ghost"}, "no object named 'ghost'"),
    ]
    for op, fields, says in bad:
        r = await owner.scene(op, **fields)
        check(r is not None and not r["accepted"] and says in r["message"], f"{op} refused: {says}", r)
    x = (await owner.newest_state(0.5))["cursor_position"]["x"] - x0
    check(0.015 < x < 0.03, "the wall still holds after the refused edits", f"{x * 1000:.1f} mm")

    # Malformed scene messages: refused as malformed, nothing applied (each from a connection of its own: a client
    # is told of its first malformed message, then of every 100th).
    for text, says in [('{"scene": {"id": 1}}', "scene: needs op"),
                       ('{"scene": {"id": 1, "op": "explode"}}', "unknown op"),
                       ('{"scene": {"id": 1, "op": "add"}}', "add needs the object"),
                       ('{"scene": {"id": 1, "op": "move", "name": "wall"}}', "move needs a position"),
                       ('{"scene": {"id": 1, "op": "remove"}}', "needs the object's name")]:
        sender = await Client.connect(url, "malformed")
        e = await sender.raw(text)
        await sender.close()
        check(e["code"] == "malformed" and says in e["message"], f"malformed: {says}", e)

    # A moving block: added, moved at 60 Hz (no answers to moves that went through), a NaN-free pose only.
    r = await owner.scene("add", object={"name": "block", "shape": "box", "size": [0.02, 0.02, 0.02],
                                         "position": [x0, 0.1, 0], "moving": True})
    check(r["accepted"], "a moving block is added", r)
    for k in range(30):
        r = await owner.scene("move", name="block", position={"x": x0, "y": 0.1 + 0.001 * k, "z": 0})
        assert r is None, r
        await asyncio.sleep(1 / 60)
    check(True, "30 moves at 60 Hz went through unanswered")
    # (written by hand: Python's json writes an infinity as Infinity, which is not JSON)
    await owner.ws.send('{"scene": {"id": 9000, "op": "move", "name": "block", "position": {"x": 1e999, "y": 0, "z": 0}}}')
    r = await owner.reply(9000)
    check(r is not None and not r["accepted"] and "is not a pose" in r["message"], "an infinite pose is refused", r)
    r = await owner.scene("move", name="block", position={"x": 0, "y": 0, "z": 0},
                          orientation={"w": 0, "x": 0, "y": 0, "z": 0})
    check(r is not None and not r["accepted"] and "is not a pose" in r["message"], "a zero quaternion is refused", r)

    # A flood of adds: beyond 50 remakes a second, refused as rate-limited; the loop runs on (states keep coming).
    refused = accepted = 0
    for k in range(120):
        r = await owner.scene("add", object={"name": f"pebble{k}", "shape": "sphere", "radius": 0.002,
                                             "position": [x0 - 0.05, 0.2, 0.01 * k]})
        if r["accepted"]:
            accepted += 1
        elif "a second" in r["message"]:
            refused += 1
    check(refused > 0 and accepted >= 50, "a flood of adds is rate-limited",
          f"{accepted} accepted, {refused} refused")
    serial = owner.state["serial"]
    later = (await owner.newest_state(0.5))["serial"]
    check(later - serial > 500, "states keep coming after the flood", f"{later - serial} in 0.5 s")

    # The list, seen by anyone.
    r = await intruder.scene("list")
    names = [o["name"] for o in r["objects"]]
    check(r["accepted"] and "wall" in names and "block" in names, "anyone lists the objects", r["message"])

    # A material changed in place, then the wall removed: the push carries the handle on past it.
    # (The simulated arm's joint friction may hold the handle where it is: the wall's force tells the stiffness.)
    hard = -(await owner.newest_state(0.2))["environment_force"]["x"]
    r = await owner.scene("material", name="wall", material={"stiffness": 1500})
    check(r["accepted"], "the wall's material is changed", r)
    soft = -(await owner.newest_state(0.5))["environment_force"]["x"]
    check(hard > 3 and soft < 0.75 * hard, "the half as stiff wall pushes back less", f"{hard:.2f} -> {soft:.2f} N")
    r = await owner.scene("remove", name="wall")
    check(r["accepted"], "the wall is removed", r)
    r = await owner.scene("contacts")
    check(not any(c["object"] == "wall" for c in r["contacts"]), "a removed object has no contacts", r)
    x = (await owner.newest_state(1.0))["cursor_position"]["x"] - x0
    check(0.018 < x < 0.03, "the uploaded sheet holds the push once the wall is gone", f"{x * 1000:.1f} mm")
    r = await owner.scene("contacts")
    check(any(c["object"] == "sheet" and c["force"]["x"] > 2.0 for c in r["contacts"]),
          "the hand pushes the sheet", r["contacts"])
    r = await owner.scene("remove", name="sheet")
    check(r["accepted"], "the sheet is removed", r)
    x_free = (await owner.newest_state(1.0))["cursor_position"]["x"] - x0
    check(x_free > 0.035, "without the wall the push carries the handle past it", f"{x_free * 1000:.1f} mm")
    await owner.operator("release")

    # The owner leaves with an upload finished and not added: its claim ends, the intruder may claim, and the
    # upload went with the claim.
    r = await upload(owner, "leftover", *sheet_mesh(x0 + 0.1, start["y"], start["z"], n=2))
    check(r["accepted"], "an upload is left unadded", r)
    await owner.close()
    for _ in range(50):
        r = await intruder.scene("claim")
        if r["accepted"]:
            break
        await asyncio.sleep(0.1)
    check(r["accepted"], "the scene's claim ends with its owner's connection", r)
    r = await intruder.scene("add", object={"name": "leftover", "shape": "mesh", "upload": "leftover"})
    check(not r["accepted"] and "no finished upload" in r["message"], "the last owner's upload ended with its claim",
          r)
    await intruder.close()


if __name__ == "__main__":
    asyncio.run(main(sys.argv[1]))
