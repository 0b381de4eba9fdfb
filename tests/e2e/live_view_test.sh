#!/usr/bin/env bash
# The live view end to end: hapticd serves the demo's simulated ViSHaRD3 (DDS off) with its live view on a free
# port of 127.0.0.1; Foxglove's own protocol client (tests/live_view/live_view_client.mjs, @foxglove/ws-protocol
# from npm under Debian's nodejs, installed by scripts/install-deps.sh) connects, subscribes and checks channels
# and contents. Then: the listening socket is on loopback only, the server counts the refused viewers and the
# bad requests, a port in use and a bad address are clear errors before any device is powered.
# Usage: live_view_test.sh HAPTICD SOURCE_DIR WORK_DIR
set -u
hapticd=$1; src=$2; work=$3
rm -rf "$work"; mkdir -p "$work"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }

client_dir="$src/tests/live_view"
if [ ! -d "$client_dir/node_modules/@foxglove/ws-protocol" ] || ! command -v node > /dev/null; then
  echo "FAIL: the test client needs node and tests/live_view/node_modules: run scripts/install-deps.sh"
  exit 1
fi

session="$src/config/sessions/demo.yaml"
source "$src/tests/e2e/session_copy.sh"  # loose_watchdogs: why, there
links=$(grep -o '<link name="[^"]*"' "$src/config/urdf/vishard3.urdf" | sed 's/<link name="//; s/"//' | paste -sd, -)
dof=$(grep -cE '<joint [^>]*type="(revolute|continuous|prismatic)"' "$src/config/urdf/vishard3.urdf")
max_clients=2

timeout 60 "$hapticd" --config "$session" --set dds.enabled=false --duration 25 --live-view 0 \
  --set live_view.max_clients=$max_clients $(loose_watchdogs vishard3) > "$work/server.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null' EXIT
url=
for _ in $(seq 1 150); do  # at most 15 s for the session to start
  url=$(grep -o 'live view on ws://[^ ]*' "$work/server.log" | sed 's/live view on //')
  [ -n "$url" ] && break
  kill -0 $server 2>/dev/null || break
  sleep 0.1
done
if [ -z "$url" ]; then
  fail "no live view announced"; cat "$work/server.log"; exit 1
fi
pass "hapticd announced $url"
port=${url##*:}

# Bound to loopback only.
if command -v ss > /dev/null; then
  listening=$(ss -ltnH "sport = :$port" | awk '{print $4}')
  [ "$listening" = "127.0.0.1:$port" ] && pass "listening on $listening only" || fail "listening on '$listening'"
fi

if (cd "$client_dir" && timeout 40 node live_view_client.mjs "$url" vishard3 "$links" "$dof" $max_clients 30) \
  > "$work/client.log" 2>&1; then
  pass "$(tail -1 "$work/client.log")"
else
  fail "the Foxglove client's checks:"; cat "$work/client.log"
fi

kill -INT $server
wait $server; rc=$?
trap - EXIT
[ "$rc" -eq 0 ] && pass "hapticd ended cleanly" || { fail "hapticd exited $rc"; tail -20 "$work/server.log"; }
summary=$(grep -o 'live view: .*' "$work/server.log" | tail -1)
# The client was refused twice (no subprotocol; one viewer too many) and sent two bad requests.
[[ "$summary" =~ ([0-9]+)\ refused.*\ ([0-9]+)\ bad\ requests ]] && [ "${BASH_REMATCH[1]}" -ge 2 ] &&
  [ "${BASH_REMATCH[2]}" -ge 2 ] && pass "the server counted: $summary" || fail "the server's count: '$summary'"

# A port in use, an address that is not one: clear errors, nothing powered.
python3 -c 'import socket,time; s=socket.socket(); s.bind(("127.0.0.1",0)); s.listen(); print(s.getsockname()[1], flush=True); time.sleep(20)' \
  > "$work/busy_port" &
holder=$!
for _ in $(seq 1 50); do [ -s "$work/busy_port" ] && break; sleep 0.1; done
busy=$(cat "$work/busy_port")
out=$(timeout 30 "$hapticd" --config "$session" --set dds.enabled=false --duration 1 --live-view "$busy" 2>&1); rc=$?
kill $holder 2>/dev/null
[ "$rc" -ne 0 ] && [[ "$out" == *"live view: cannot listen on 127.0.0.1:$busy"*"no device was powered"* ]] &&
  pass "a port in use: $(echo "$out" | grep -o 'live view: cannot.*' | head -1)" || fail "port in use: rc=$rc $out"
out=$(timeout 30 "$hapticd" --check-config "$session" --set live_view.address=localhost 2>&1); rc=$?
[ "$rc" -eq 2 ] && [[ "$out" == *"live_view.address"*"not an IP address"* ]] && pass "a bad address: $out" ||
  fail "bad address: rc=$rc $out"

[ "$failures" -eq 0 ] && echo "live view: all checks passed" || echo "live view: $failures failure(s)"
[ "$failures" -eq 0 ]
