#!/usr/bin/env bash
# The haptic scene in the browser (docs/haptic-scene.md, "In the browser"): the page the engine socket serves at
# /scene.html (tools/engine_socket/scene.html), in headless chromium (tests/engine_socket/browser_page.mjs).
# 1. It draws a scene it does not own: config/sessions/vishard3/socket-scene.yaml with the desk scene file
#    (config/haptic-scenes/desk.yaml: six shapes and a 5120-triangle mesh) - every object, the mesh's triangles
#    (every 2nd: at most 4000 drawn) and the device's proxy, 30 drawings a second.
# 2. It is an engine: on a person's click it claims the scene, puts a table and a block by the hand and runs the
#    block's physics at 60 Hz from the contacts - with the simulated operator's hand moving forward at 1.5 cm/s from
#    6 s, the hand meets the block and pushes it across the table, with the force of the block's friction
#    (1 kg x 0.3 x 9.81 m/s^2 = 2.94 N) while it slides.
# Usage: scene_browser_test.sh BIN_DIR SOURCE_DIR WORK_DIR
set -u
bin=$1 src=$2 work=$3
here=$src/tests/engine_socket
rm -rf "$work"; mkdir -p "$work"; cd "$work"
source "$src/tests/e2e/session_copy.sh"
server=
fail() { echo "FAIL: $*"; for f in look.log push.log; do echo "--- $f"; cat "$f" 2> /dev/null; done; echo "--- server"; tail -20 server.log; exit 1; }
trap '[ -n "$server" ] && kill $server 2> /dev/null' EXIT
serve() {  # serve SECONDS EXTRA...: the session in the background, its socket's URL in $url
  local seconds=$1; shift
  timeout $((seconds + 30)) "$bin/hapticd" --config "$src/config/sessions/vishard3/socket-scene.yaml" \
    --duration "$seconds" --log-level info --set server.realtime_priority=0 --set server.lock_memory=false \
    --set engine_socket.port=0 $(loose_watchdogs vishard3) "$@" > server.log 2>&1 &
  server=$!
  url=$(socket_url server.log)
  [ -n "$url" ] || fail "the server did not say where its engine socket is"
}
stop_server() {
  kill -INT "$server"
  wait "$server" || fail "the server exited with $?"
  server=
}

# 1. The page looks at the desk scene.
serve 12 --set scene.parameters.file="$src/config/haptic-scenes/desk.yaml"
timeout 40 node "$here/browser_page.mjs" "${url/ws:/http:}/scene.html?device=vishard3" scene 4 --look > look.log 2>&1 ||
  fail "the page in chromium: $(cat look.log)"
python3 - "$(tail -1 look.log)" << 'PY' || fail "the page's drawing: $(tail -1 look.log)"
import json, sys
s = json.loads(sys.argv[1])
names = sorted(o["name"] for o in s["objects"])
print(f"the page drew {s['drawings']} times: {', '.join(names)}; {s['meshTriangles']} mesh triangles; "
      f"{s['painted']} faces painted; proxies {[p['device'] for p in s['proxies']]}")
assert names == ["ball", "desk", "pebble", "plate", "post", "rail", "wall"], names
pebble = next(o for o in s["objects"] if o["name"] == "pebble")
assert pebble["shape"] == "mesh" and pebble["triangles"] == 5120 and s["meshTriangles"] == 2560, pebble
assert [p["device"] for p in s["proxies"]] == ["vishard3"], s["proxies"]
assert s["painted"] > 2560, "the mesh's triangles were not painted"
assert s["drawings"] > 40, "fewer than 10 drawings a second"  # 30 a second asked, in at least 4 s
assert not s["claimed"] and not s["errors"] and not s["refused"], s
PY
echo "ok: the page draws a scene it does not own: every object, the mesh and the proxy"
stop_server

# 2. The page pushes a block about by its own physics.
serve 24 --set devices.vishard3.device.parameters.operator_motion=ramp \
  --set "devices.vishard3.device.parameters.operator_motion_m=[0.015,0,0]" \
  --set devices.vishard3.device.parameters.operator_motion_start_s=6.0
timeout 60 node "$here/browser_page.mjs" "${url/ws:/http:}/scene.html?device=vishard3" scene 14 claimed.flag \
  > push.log 2>&1 || fail "the page in chromium: $(cat push.log)"
python3 - "$(tail -1 push.log)" << 'PY' || fail "the page's block: $(tail -1 push.log)"
import json, sys
s = json.loads(sys.argv[1])
pushes = s.get("pushes", [])
print(f"the page ran {s['frames']} frames; the block moved {s['moved_mm']:.1f} mm; a second's mean push "
      + ", ".join(f"{p['push_n']:.2f} N at {p['moved_mm']:.1f} mm" for p in pushes))
assert s["claimed"] and not s["errors"] and not s["refused"], s
assert s["frames"] > 50 * 14 * 0.8, "the engine ran fewer than 40 frames a second"
assert 15 < s["moved_mm"] < 200, "the block was not pushed across the table"
assert len(pushes) > 10 and pushes[0]["moved_mm"] < 0.5, "the block moved while the hand was at rest"
# While it slides (it went on by more than 5 mm in a second), the hand pushes with the block's friction.
sliding = [b["push_n"] for a, b in zip(pushes, pushes[1:]) if b["moved_mm"] - a["moved_mm"] > 5]
assert sliding and 2.5 < sliding[-1] < 3.4, f"the sliding block was pushed with {sliding} N"
names = sorted(o["name"] for o in s["objects"])
assert names == ["block", "table"] and s["painted"] > 12, names
PY
echo "ok: on a person's click the page pushes a block across the table by its own physics"
stop_server
trap - EXIT
echo "2 passed, 0 failed"
