# Sourced by the real-time end-to-end scripts. session_copy SESSION SOURCE_DIR OUT writes a copy of a shipped
# single-device session that runs from any folder (the robot model and friction file paths made absolute) with the loop watchdogs
# loosened: these tests test the tools and the DDS path, not the machine. A shared CI virtual machine runs the
# loop late now and then - a few milliseconds often, and in bursts the whole machine for over 0.1 s (two
# tests of one CI run tripped in the same instant, one with 60 overruns in a row at SCHED_FIFO, the other with a
# 0.1 s stall) - which trips the defaults (10 overruns in a row, a 20 ms stall; docs/safety.md). Loosened, not
# off: a loop that falls behind for a whole second (2000 periods at 2 kHz) or sleeps a second still stops the
# device. The watchdogs themselves are tested in lockstep (safety_test) and by hardening_test.sh's 1.5 s stop.
# loose_watchdogs DEVICE prints the same loosening as --set arguments, for a shipped session run where it lies.
session_copy() {
  sed -e "s%\.\./\.\./\(urdf\|friction\)/%$2/config/\1/%g" \
      -e 's|^  - name: \(.*\)$|  - name: \1\n    safety: {max_consecutive_overruns: 2000, max_stall_s: 1.0}|' "$1" > "$3"
}
loose_watchdogs() {
  echo "--set devices.$1.safety.max_consecutive_overruns=2000 --set devices.$1.safety.max_stall_s=1.0"
}
# freeze_beyond_claim_hold PID LOG DEVICE: waits (20 s at most) until the engine PID says in LOG that it claimed
# DEVICE, stops it (SIGSTOP) for 2.5 s - beyond its command writer's 0.5 s lease and a 0.5 s claim hold
# (dds.claim_hold_s=0.5): the server ends the claim - resumes it, and waits (10 s at most) for it to say it claimed
# again. Returns 1 with the reason on standard output when a step did not happen.
freeze_beyond_claim_hold() {
  local pid=$1 log=$2 device=$3
  for _ in $(seq 200); do grep -q "claimed '$device'" "$log" && break; sleep 0.1; done
  grep -q "claimed '$device'" "$log" || { echo "the engine did not claim"; return 1; }
  sleep 0.5
  kill -STOP "$pid"
  sleep 2.5
  kill -CONT "$pid"
  for _ in $(seq 100); do grep -q "claimed '$device' again" "$log" && break; sleep 0.1; done
  grep -q "the server ended the claim of '$device'" "$log" || { echo "the claim's loss was not told"; return 1; }
  grep -q "claimed '$device' again" "$log" || { echo "the engine did not claim again"; return 1; }
}
# socket_url LOG: waits (10 s at most) until the server's LOG says where its engine socket is (a port of 0: the
# system's choice) and prints its URL; prints nothing when it does not say so in time.
socket_url() {
  local url=
  for _ in $(seq 100); do
    url=$(sed -n 's/.*engine socket on \(ws:[^ ]*\) .*/\1/p' "$1")
    [ -n "$url" ] && break
    sleep 0.1
  done
  echo "$url"
}
