#!/usr/bin/env bash
# A rendering engine in plain C on the C API (examples/c_api/wall_engine.c, hapticd-c-wall-engine) against the
# server over DDS on loopback (domain DOMAIN): it claims the simulated ViSHaRD3 of the shipped dds-coupling
# session. Stopped (SIGSTOP) beyond the server's claim hold (0.5 s), it loses its claim: resumed, its claim-lost
# callback tells it and it claims again. Then the simulated operator pushes 15 N into its wall 2 cm ahead, and the
# handle comes to rest at the wall (through the 3000 N/m coupling about 5 mm past it); then SIGTERM ends the
# engine (a stop: it releases, exit 0) and SIGINT the server. No step waits on a fixed duration of the other's
# (the engine's and server's --duration only bound a run that went wrong); the timeline goes to timeline.log.
# Usage: c_api_engine_test.sh BIN_DIR SOURCE_DIR WORK_DIR DOMAIN
set -u
bin=$1 src=$2 work=$3 domain=$4
rm -rf "$work"; mkdir -p "$work"; cd "$work"
source "$src/tests/e2e/session_copy.sh"
t0=$(date +%s.%N)
mark() { awk -v now="$(date +%s.%N)" -v t0="$t0" -v what="$*" 'BEGIN { printf "%.2f s: %s\n", now - t0, what }' >> timeline.log; }
fail() {
  mark "FAIL: $*"; echo "FAIL: $*"; echo "--- timeline"; cat timeline.log; echo "--- engine"; cat engine.log
  echo "--- server"; tail -20 server.log; exit 1
}
timeout 100 "$bin/hapticd" --config "$src/config/sessions/vishard3/dds-coupling.yaml" --dds-domain "$domain" \
  --duration 90 --log-level info --set server.realtime_priority=0 --set server.lock_memory=false \
  --set dds.claim_hold_s=0.5 $(loose_watchdogs vishard3) > server.log 2>&1 &
server=$!
"$bin/hapticd-c-wall-engine" --domain "$domain" --device vishard3 --duration 60 > engine.log 2>&1 &
engine=$!  # the engine itself (not under timeout: it is stopped and resumed; its --duration bounds it)
mark "started the server and the engine"
trap 'kill -CONT $engine 2> /dev/null; kill $server $engine 2> /dev/null' EXIT
why=$(freeze_beyond_claim_hold "$engine" engine.log vishard3) || fail "$why"
mark "the engine claimed again"
echo "ok: the C engine was told of its lost claim and claimed again"
timeout 20 "$bin/hapticctl" --domain "$domain" --timeout 5 operator vishard3 push 15 0 0 0.2 > push.log 2>&1 ||
  fail "the operator's push: $(cat push.log)"
mark "the push was taken"
sleep 2  # the handle comes to rest at the wall
kill -TERM "$engine"
wait "$engine" || fail "the C engine exited with $?"
mark "the engine ended"
past=$(sed -n 's/.*handle \([-0-9.]*\) m past the start.*/\1/p' engine.log)
grep "answered" engine.log
awk -v x="$past" 'BEGIN { exit !(x > 0.015 && x < 0.03) }' || fail "the wall did not hold: $past m"
echo "ok: the C engine's wall holds the 15 N push ($past m past the start)"
kill -INT "$server"
wait "$server" || fail "the server exited with $?"
trap - EXIT
echo "2 passed, 0 failed"
