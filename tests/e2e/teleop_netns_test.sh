#!/usr/bin/env bash
# Teleoperation across machines (docs/teleoperation.md): the master server and the remote server in two network
# namespaces that reach each other only through a third, where hapticd-link-relay delays and drops their UDP
# datagrams (this machine's kernel has no netem): 192.0.2.1 (master) - 192.0.2.2 | relay | 192.0.2.129 - 192.0.2.130
# (remote), two veth pairs, created and removed here. Each server's Cyclone DDS names the relay as its peer and
# advertises the relay's address facing the other side. The master's simulated operator reaches 5 cm ahead; the
# remote meets its wall 3 cm ahead; with 40 ms round trip and 5 % loss each way the master feels the wall through
# the link and both ports stay passive (the time-domain passivity controllers). Then the relay stops: the remote
# stops (link lost), the master's force fades. With DOF 6, the ViSHaRD6 pair in six degrees of freedom
# (master6.yaml, remote6.yaml) through 200 ms round trip: the operator also turns the handle 0.15 rad, tilting the
# remote's plate against its wall - the master feels its torque. Each side's measured one-way delays within 2 ms of
# what the relay held that direction's datagrams (it measures that: the delay asked, 20 or 100 ms and up to 2 ms of
# jitter, plus its own lateness). Skipped (exit 77) where namespaces cannot be made.
# Usage: teleop_netns_test.sh BIN_DIR SOURCE_DIR WORK_DIR [DOF]    (DOF: 3, the default, or 6)
set -uo pipefail
bin=$1 src=$2 work=$3 dof=${4:-3}
if [ "$dof" = 6 ]; then
  sessions=(master6.yaml remote6.yaml) delay_ms=100 relay_s=9 run_s=13 domain=174  # ports 50910-50919
else
  sessions=(master.yaml remote.yaml) delay_ms=20 relay_s=7 run_s=10 domain=157  # ports 46660-46669
fi
ports=$((7400 + 250 * domain + 10))-$((7400 + 250 * domain + 19))
rm -rf "$work"; mkdir -p "$work"
skip() { echo "SKIP: $*"; exit 77; }
fail() {
  echo "FAIL: $*"
  for f in master.log remote.log relay.log; do [ -f "$work/$f" ] && { echo "--- $f"; tail -12 "$work/$f"; }; done
  exit 1
}
[ "$(id -u)" -eq 0 ] || skip "network namespaces need root"
command -v ip > /dev/null || skip "no ip (iproute2)"
source "$src/tests/e2e/link_namespaces.sh"
trap link_namespaces_down EXIT
link_namespaces_up "t$$" || skip "$link_namespaces_error"
# No route between the two sides: only the relay joins them.
ip netns exec "$ns_m" ping -c 1 -W 1 192.0.2.130 > /dev/null 2>&1 && fail "the master reaches the remote without the relay"

# The domain's unicast ports: 7400 + 250 * domain + 10 + 2 i and + 11 + 2 i for participant indices 0-4.
link_cyclone_xml "$if_m" 192.0.2.2 192.0.2.129 > "$work/master.xml"
link_cyclone_xml "$if_r" 192.0.2.129 192.0.2.2 > "$work/remote.xml"

ip netns exec "$ns_x" "$bin/hapticd-link-relay" --route 192.0.2.2=192.0.2.130 --route 192.0.2.129=192.0.2.1 \
  --ports "$ports" --delay-ms "$delay_ms" --jitter-ms 2 --loss 0.05 --seed 3 --duration "$relay_s" \
  > "$work/relay.log" 2>&1 &
relay=$!
sleep 0.5
grep -q "2 route(s), 10 port(s) each" "$work/relay.log" || fail "the relay did not start: $(cat "$work/relay.log")"
source "$src/tests/e2e/session_copy.sh"  # loose_watchdogs: why, there
common=(--dds-domain "$domain" --set server.realtime_priority=0 --set server.lock_memory=false
  --set teleoperation.link_timeout_s=0.5 --log-level info)
p=devices.master.device.parameters
turn=()
[ "$dof" = 6 ] && turn=(--set "$p.operator_rotation=step" --set "$p.operator_rotation_rad=[0, 0, 0.15]"
  --set "$p.operator_rotation_start_s=3.0")
ip netns exec "$ns_r" timeout 40 "$bin/hapticd" --config "$src/config/sessions/teleoperation/${sessions[1]}" \
  --duration "$run_s" --set "dds.cyclone_config=$work/remote.xml" "${common[@]}" $(loose_watchdogs remote) \
  > "$work/remote.log" 2>&1 &
remote=$!
ip netns exec "$ns_m" timeout 40 "$bin/hapticd" --config "$src/config/sessions/teleoperation/${sessions[0]}" \
  --duration "$run_s" --set "dds.cyclone_config=$work/master.xml" "${common[@]}" $(loose_watchdogs master) \
  --set "$p.operator_motion=step" --set "$p.operator_motion_m=[0.05, 0, 0]" --set "$p.operator_motion_start_s=1.5" \
  "${turn[@]}" > "$work/master.log" 2>&1 &
master=$!
wait "$relay"
grep -q "192.0.2.2 -> 192.0.2.130: relayed [1-9][0-9]*, dropped [1-9]" "$work/relay.log" ||
  fail "the relay relayed nothing, or dropped nothing, towards the remote"
wait "$master" || fail "the master server exited with $?"
wait "$remote"
code=$?
[ "$code" = 3 ] || fail "the remote server exited with $code, not 3 (a device fault: its stop when the link was lost)"

# summary LOG: the link's end-of-session line, as "sent taken rejected lost stops lowest largest"
summary() {
  sed -n 's/.*teleoperation link to .*: packets sent \([0-9]*\), taken \([0-9]*\), rejected \([0-9]*\); lost \([0-9]*\) times, \([0-9]*\) stops; energy in .* lowest observed \([-0-9.]*\) J; largest force \([0-9.]*\) N/\1 \2 \3 \4 \5 \6 \7/p' "$work/$1"
}
read -r m_sent m_taken m_rejected m_lost m_stops m_lowest m_force <<< "$(summary master.log)"
read -r r_sent r_taken r_rejected r_lost r_stops r_lowest r_force <<< "$(summary remote.log)"
[ -n "${m_force:-}" ] && [ -n "${r_force:-}" ] || fail "no link summary: $(grep -h teleoperation "$work"/*.log)"
echo "master: sent $m_sent, taken $m_taken, lowest observed $m_lowest J, largest force $m_force N, lost $m_lost, stops $m_stops"
echo "remote: sent $r_sent, taken $r_taken, lowest observed $r_lowest J, largest force $r_force N, lost $r_lost, stops $r_stops"
# Through the relay: most packets arrived (5 % loss each way, and the link ran for most of the relay's 7 or 9 s).
[ "$m_taken" -gt 3000 ] && [ "$r_taken" -gt 3000 ] || fail "too few packets through the relay: $m_taken, $r_taken"
[ "$m_rejected" -eq 0 ] && [ "$r_rejected" -eq 0 ] || fail "packets rejected: $m_rejected, $r_rejected"
# The master felt the remote's wall (the operator's arm pushes it 2 cm past the wall: several newtons).
awk -v f="$m_force" 'BEGIN { exit !(f > 3.0) }' || fail "the master felt no wall: largest force $m_force N"
# Six degrees of freedom: the master felt the tilted plate's torque through the link.
if [ "$dof" = 6 ]; then
  torque=$(sed -n 's/.*master: teleoperation link in rotation: largest torque \([0-9.]*\) N m.*/\1/p' "$work/master.log")
  [ -n "$torque" ] || fail "no rotation line in the master's log"
  echo "master: largest torque $torque N m"
  awk -v t="$torque" 'BEGIN { exit !(t > 0.05) }' || fail "the master felt no torque: $torque N m"
fi
# Both ports passive: the energy observed never below zero (up to rounding).
awk -v a="$m_lowest" -v b="$r_lowest" 'BEGIN { exit !(a > -1e-6 && b > -1e-6) }' ||
  fail "a port was active: lowest observed $m_lowest J, $r_lowest J"
# The relay stopped (at 7 or 9 s): the remote stopped (link lost), the master's force faded out.
grep -q "teleoperation link lost (no packet from 'master' .*): the remote stops" "$work/remote.log" ||
  fail "the remote did not stop when the link was lost"
grep -q "device 'remote' fault emergency_stop" "$work/remote.log" || fail "the remote's stop is not its safe mode"
grep -q "teleoperation link lost (no packet from 'remote' .*): the force fades out" "$work/master.log" ||
  fail "the master did not fade its force when the link was lost"
grep -q "device 'master': ok" "$work/master.log" || fail "the master faulted: $(grep -h FAULT "$work/master.log")"
# Both sides measured the link's delay from the packets' times alone (no common clock assumed; here one host's):
# each one-way mean within 2 ms of what the relay held that direction's datagrams on average (its delay and up to 2 ms
# of jitter - 21 or 101 ms asked on average - and its lateness, as it measured them; the sides add their own: a packet
# waits for the link's next state to be taken), and the two sides' readings of each other's clock (their link
# clocks: from each server's start) opposite within 2 ms.
held() {
  sed -n "s/.*$1 -> $2: relayed .*; held \([0-9.]*\) ms on average/\1/p" "$work/relay.log"
}
to_remote=$(held 192.0.2.2 192.0.2.130) to_master=$(held 192.0.2.129 192.0.2.1)
[ -n "$to_remote" ] && [ -n "$to_master" ] || fail "no hold in the relay's report"
echo "relay held: towards the remote $to_remote ms, towards the master $to_master ms (asked: $((delay_ms + 1)) ms on average)"
delay() {
  sed -n "s/.*teleoperation link's delay, measured: one-way to this side \([0-9.]*\) ms, from it \([0-9.]*\) ms (means); round trip \([0-9.]*\) ms .*; the peer's clock \([-+0-9.]*\) ms from this one's; \([0-9]*\) exchanges, \([0-9]*\) refused/\1 \2 \3 \4 \5 \6/p" "$work/$1"
}
read -r m_in m_out m_rtt m_offset m_exchanges m_refused <<< "$(delay master.log)"
read -r r_in r_out r_rtt r_offset r_exchanges r_refused <<< "$(delay remote.log)"
[ -n "${m_refused:-}" ] && [ -n "${r_refused:-}" ] || fail "no delay line: $(grep -h "link's delay" "$work"/*.log)"
echo "master measured: to it $m_in ms, from it $m_out ms, round trip $m_rtt ms, the remote's clock $m_offset ms ($m_exchanges exchanges)"
echo "remote measured: to it $r_in ms, from it $r_out ms, round trip $r_rtt ms, the master's clock $r_offset ms ($r_exchanges exchanges)"
for pair in "$m_in $to_master" "$m_out $to_remote" "$r_in $to_remote" "$r_out $to_master"; do
  read -r d e <<< "$pair"
  awk -v d="$d" -v e="$e" 'BEGIN { exit !(d > e - 2.0 && d < e + 2.0) }' ||
    fail "a measured one-way delay of $d ms: the relay held that direction's datagrams $e ms"
done
awk -v a="$m_offset" -v b="$r_offset" 'BEGIN { exit !(a + b > -2.0 && a + b < 2.0) }' ||
  fail "the sides' clock offsets disagree: the master reads the remote's at $m_offset ms, the remote the master's at $r_offset ms"
[ "$m_refused" -eq 0 ] && [ "$r_refused" -eq 0 ] && [ "$m_exchanges" -gt 3000 ] && [ "$r_exchanges" -gt 3000 ] ||
  fail "delay exchanges: $m_exchanges and $r_exchanges taken, $m_refused and $r_refused refused"
echo "PASS: teleoperation ($dof degrees of freedom) across namespaces through the relay ($((2 * delay_ms)) ms round trip, 5 % loss each way)"
