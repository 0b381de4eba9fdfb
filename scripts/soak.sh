#!/usr/bin/env bash
# A soak of the served product under every kind of client at once (docs/safety.md, "Soak"): for MINUTES minutes,
#   - a server on loopback (the shipped dds-coupling session: the simulated ViSHaRD3 at 2 kHz, the operator's hand
#     pushing back and forth through the engine's scene) with its engine socket, its live view and a recording;
#   - a DDS engine on it (hapticd-scene-engine, which claims the device and answers every state);
#   - four engine-socket clients watching the device's states (Python websockets) and a live-view viewer subscribed
#     to every channel (Foxglove's protocol);
#   - a teleoperation pair (the shipped master and remote sessions) in two network namespaces joined only through
#     hapticd-link-relay (20 ms each way, 5 % loss), as tests/e2e/teleop_netns_test.sh builds them (root; skipped
#     without namespaces, and said so).
# Every 30 s it samples each server's resident memory; at the end it prints the figures, checks that the main
# server's memory after the first minute grew by less than MAX_GROWTH_MB, that the recording holds every cycle the
# server ran (its cycle column has no gap and as many rows as the log's cycles) and that every client ran to the
# end. Loopback and the namespaces' 192.0.2.0/24 only; every process bounded by `timeout`.
# Usage: scripts/soak.sh [--minutes M] [--out DIR] [--bin DIR] [--max-growth-mb MB]   (default 10, build/soak,
#        build/ci/bin or build/default/bin, 8)
set -uo pipefail
cd "$(dirname "$0")/.."
src=$PWD minutes=10 out=build/soak bin= max_growth=8
while [ $# -gt 0 ]; do
  case $1 in
    --minutes) minutes=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --max-growth-mb) max_growth=$2; shift 2 ;;
    *) echo "usage: scripts/soak.sh [--minutes M] [--out DIR] [--bin DIR] [--max-growth-mb MB]" >&2; exit 2 ;;
  esac
done
[ -n "$bin" ] || for b in build/ci/bin build/default/bin; do [ -x "$b/hapticd" ] && { bin=$b; break; }; done
[ -x "$bin/hapticd" ] || { echo "soak: no hapticd in ${bin:-build/ci/bin or build/default/bin}" >&2; exit 2; }
bin=$(cd "$bin" && pwd)
seconds=$((minutes * 60))
rm -rf "$out"; mkdir -p "$out"; out=$(cd "$out" && pwd)
py=python3
python3 -c "import websockets, h5py" 2> /dev/null || py=/usr/bin/python3
fail() { echo "soak: FAIL: $*"; exit 1; }
source "$src/tests/e2e/session_copy.sh"  # loose_watchdogs: a shared machine runs a loop late now and then
pids=()
source "$src/tests/e2e/link_namespaces.sh"  # the teleoperation pair's hosts
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null; done
  link_namespaces_down
}
trap cleanup EXIT

# The main server.
domain=171
p=devices.vishard3.device.parameters
timeout $((seconds + 60)) "$bin/hapticd" --config "$src/config/sessions/vishard3/dds-coupling.yaml" \
  --dds-domain "$domain" --duration "$seconds" --log-level info --record "$out/soak.h5" \
  --set server.realtime_priority=0 --set server.lock_memory=false --set engine_socket.port=0 \
  --set live_view.port=0 --set "$p.operator_force=sine" --set "$p.operator_force_n=[12, 6, 0]" \
  --set "$p.operator_force_frequency_hz=0.3" $(loose_watchdogs vishard3) > "$out/server.log" 2>&1 &
server=$!
pids+=("$server")
# The processes whose memory is sampled: the hapticd under each `timeout` (and `ip netns exec`).
child_of() { for _ in $(seq 50); do c=$(pgrep -P "$1" -n) && { echo "$c"; return; }; sleep 0.1; done; echo "$1"; }
socket= view=
for _ in $(seq 150); do
  socket=$(sed -n 's/.*engine socket on \(ws:[^ ]*\) .*/\1/p' "$out/server.log")
  view=$(sed -n 's/.*live view on \(ws:[^ ]*\)\b.*/\1/p' "$out/server.log" | head -n 1)
  [ -n "$socket" ] && [ -n "$view" ] && break
  sleep 0.1
done
[ -n "$socket" ] && [ -n "$view" ] || fail "the server did not say where its socket and live view are: $(tail -5 "$out/server.log")"
view=${view%%[ ,;]*}

timeout $((seconds + 30)) "$bin/hapticd-scene-engine" --domain "$domain" --device vishard3 --wait 30 \
  --duration $((seconds - 5)) > "$out/engine.log" 2>&1 &
engine=$!
pids+=("$engine")

# Four socket watchers and a live-view viewer, one Python process.
timeout $((seconds + 30)) "$py" - "$socket" "$view" $((seconds - 10)) > "$out/clients.log" 2>&1 << 'PY' &
import asyncio, json, sys
import websockets

async def watcher(url, k, seconds):
    states = 0
    async with websockets.connect(url, max_queue=64) as ws:
        json.loads(await ws.recv())
        await ws.send(json.dumps({"subscribe": ["vishard3"]}))
        loop = asyncio.get_running_loop()
        end = loop.time() + seconds
        while loop.time() < end:
            m = json.loads(await asyncio.wait_for(ws.recv(), timeout=5))
            states += "devices" in m
    print(f"socket watcher {k}: {states} states to the end", flush=True)

async def viewer(url, seconds):
    messages = 0
    async with websockets.connect(url, subprotocols=["foxglove.websocket.v1"], max_size=2**24) as ws:
        subscribed = False
        loop = asyncio.get_running_loop()
        end = loop.time() + seconds
        while loop.time() < end:
            m = await asyncio.wait_for(ws.recv(), timeout=5)
            if isinstance(m, str):
                op = json.loads(m)
                if op.get("op") == "advertise" and not subscribed:
                    subs = [{"id": i, "channelId": c["id"]} for i, c in enumerate(op["channels"])]
                    await ws.send(json.dumps({"op": "subscribe", "subscriptions": subs}))
                    subscribed = True
            else:
                messages += 1
    print(f"live-view viewer: {messages} messages to the end", flush=True)

async def main(socket, view, seconds):
    await asyncio.gather(*(watcher(socket, k, seconds) for k in range(4)), viewer(view, seconds))

asyncio.run(main(sys.argv[1], sys.argv[2], float(sys.argv[3])))
PY
clients=$!
pids+=("$clients")

# The teleoperation pair through the relay, in namespaces.
teleop=skipped
if [ "$(id -u)" -eq 0 ] && command -v ip > /dev/null && link_namespaces_up "s$$"; then
  link_cyclone_xml "$if_m" 192.0.2.2 192.0.2.129 > "$out/master.xml"
  link_cyclone_xml "$if_r" 192.0.2.129 192.0.2.2 > "$out/remote.xml"
  ip netns exec "$ns_x" timeout $((seconds + 60)) "$bin/hapticd-link-relay" --route 192.0.2.2=192.0.2.130 \
    --route 192.0.2.129=192.0.2.1 --ports 46660-46669 --delay-ms 20 --jitter-ms 2 --loss 0.05 --seed 3 \
    --duration $((seconds + 20)) > "$out/relay.log" 2>&1 &
  pids+=($!)
  common=(--dds-domain 157 --duration "$seconds" --set server.realtime_priority=0 --set server.lock_memory=false
    --log-level info)
  mp=devices.master.device.parameters
  ip netns exec "$ns_r" timeout $((seconds + 60)) "$bin/hapticd" --config "$src/config/sessions/teleoperation/remote.yaml" \
    --set "dds.cyclone_config=$out/remote.xml" "${common[@]}" $(loose_watchdogs remote) > "$out/remote.log" 2>&1 &
  remote=$!
  pids+=("$remote")
  ip netns exec "$ns_m" timeout $((seconds + 60)) "$bin/hapticd" --config "$src/config/sessions/teleoperation/master.yaml" \
    --set "dds.cyclone_config=$out/master.xml" "${common[@]}" $(loose_watchdogs master) \
    --set "$mp.operator_motion=sine" --set "$mp.operator_motion_m=[0.05, 0, 0]" \
    --set "$mp.operator_motion_frequency_hz=0.2" > "$out/master.log" 2>&1 &
  master=$!
  pids+=("$master")
  teleop=running
fi

# Resident memory every 30 s (kB): the main server, and the teleoperation servers when they run.
rss() { awk '/^VmRSS:/ { print $2 }' "/proc/$1/status" 2> /dev/null || echo 0; }
server_pid=$(child_of "$server")
master_pid=$([ "$teleop" = running ] && child_of "$master" || echo 0)
remote_pid=$([ "$teleop" = running ] && child_of "$remote" || echo 0)
echo "t_s server_kb master_kb remote_kb" > "$out/rss.txt"
for ((t = 0; t <= seconds - 5; t += 30)); do
  echo "$t $(rss "$server_pid") $(rss "$master_pid") $(rss "$remote_pid")" >> "$out/rss.txt"
  sleep 30
done
wait "$server"; code=$?
wait "$clients" || fail "the socket clients or the viewer did not run to the end: $(tail -5 "$out/clients.log")"
wait "$engine"
[ "$teleop" = running ] && { wait "$master"; wait "$remote"; }

cat "$out/rss.txt"
[ "$code" = 0 ] || fail "the server exited with $code: $(grep -h 'FAULT\|error' "$out/server.log" | head -5)"
cat "$out/clients.log"
grep -c "to the end" "$out/clients.log" | grep -qx 5 || fail "not every client ran to the end"
# Memory: from the sample at 60 s to the last.
# (A run shorter than two minutes compares from its first sample.)
read -r first last < <(awk 'NR == 2 { s = $2 } NR > 1 && $1 >= 60 { if (!f) f = $2; l = $2 } NR > 1 { e = $2 }
  END { if (!f) { f = s; l = e } print f + 0, l + 0 }' "$out/rss.txt")
growth=$(awk -v a="$first" -v b="$last" 'BEGIN { printf "%.1f", (b - a) / 1024 }')
echo "soak: the server's resident memory $((first / 1024)) MB at 60 s, $((last / 1024)) MB at the end: ${growth} MB more"
# The recording: a row for every cycle the server ran (the periods the loop skipped after an overrun have none: the
# log counts them), in order, every dataset as long, nothing dropped.
cycles=$(sed -n 's/.*\] \([0-9]*\) cycles in .* loop time.*/\1/p' "$out/server.log" | tail -n 1)
skipped=$(sed -n 's/.* cycles in .*, \([0-9]*\) skipped.*/\1/p' "$out/server.log" | tail -n 1)
"$py" - "$out/soak.h5" "${cycles:-0}" "${skipped:-0}" << 'PY' || fail "the recording is not whole"
import sys
import h5py
import numpy as np
with h5py.File(sys.argv[1], "r") as f:
    c = f["devices/vishard3/cycle"][:].astype(np.int64)
    rows = {name: f["devices/vishard3/" + name].shape[0] for name in ("time_s", "handle/pose", "wrench/operator")}
steps = np.diff(c)
missing = int((steps - 1).sum())
print(f"soak: recording {len(c)} rows, periods {c[0]}..{c[-1]}, {missing} periods without a row; the log counts "
      f"{sys.argv[2]} cycles and {sys.argv[3]} skipped periods")
assert all(r == len(c) for r in rows.values()), rows
assert len(c) == int(sys.argv[2]), "rows differ from the cycles the server ran"
assert (steps >= 1).all(), "the rows are not in order"
assert missing == int(sys.argv[3]), "periods without a row that the loop did not skip: records lost"
PY
grep -h "dropped" "$out/server.log" | tail -n 2
if [ "$teleop" = running ]; then
  grep -h "teleoperation link to\|teleoperation link's peer" "$out/master.log" "$out/remote.log"
  grep -h "relayed" "$out/relay.log"
else
  echo "soak: the teleoperation pair was skipped (no root or no network namespaces here)"
fi
awk -v g="$growth" -v m="$max_growth" 'BEGIN { exit !(g < m) }' || fail "the server's memory grew ${growth} MB (limit $max_growth)"
echo "soak: PASS ($minutes min)"
