#!/usr/bin/env bash
# Across machines (docs/deployment.md): the server and an engine in two network namespaces joined by a veth pair
# (192.0.2.1 and 192.0.2.2, the documentation range), created and removed here. The server gets its network from
# the session file (--set dds.network=...), the engine and hapticctl from HAPTICD_DDS_NETWORK. The engine claims
# the device and answers every state with a coupling command; the server measures the round trip across the
# pair. Then the same with packet loss injected by Cyclone itself (Internal/Test/XmitLossiness: each side drops
# that share of the packets it sends), 5 % and 20 %: what loss does to the round trip, to how stale the applied
# engine input is, and to the fade (deadline misses). And once with DDS Security (scripts/make-security.sh) across
# the pair. Skipped (exit 77) where namespaces cannot be made.
# Usage: lan_test.sh BIN_DIR SOURCE_DIR WORK_DIR
set -uo pipefail
bin=$1 src=$2 work=$3
rm -rf "$work"; mkdir -p "$work"
skip() { echo "SKIP: $*"; exit 77; }
[ "$(id -u)" -eq 0 ] || skip "network namespaces need root"
command -v ip > /dev/null || skip "no ip (iproute2)"
ns_srv="hapticd-lan-srv-$$" ns_eng="hapticd-lan-eng-$$" if_srv="hds$$" if_eng="hde$$"
cleanup() {
  ip netns pids "$ns_srv" 2> /dev/null | xargs -r kill 2> /dev/null
  ip netns pids "$ns_eng" 2> /dev/null | xargs -r kill 2> /dev/null
  ip netns del "$ns_srv" 2> /dev/null
  ip netns del "$ns_eng" 2> /dev/null
}
trap cleanup EXIT
ip netns add "$ns_srv" 2> "$work/netns.err" || skip "cannot create a network namespace: $(cat "$work/netns.err")"
ip netns add "$ns_eng" || skip "cannot create a second network namespace"
ip link add "$if_srv" netns "$ns_srv" type veth peer name "$if_eng" netns "$ns_eng" 2> "$work/veth.err" ||
  skip "cannot create a veth pair: $(cat "$work/veth.err")"
ip -n "$ns_srv" addr add 192.0.2.1/24 dev "$if_srv"
ip -n "$ns_eng" addr add 192.0.2.2/24 dev "$if_eng"
for n in "$ns_srv" "$ns_eng"; do ip -n "$n" link set lo up; done
ip -n "$ns_srv" link set "$if_srv" up
ip -n "$ns_eng" link set "$if_eng" up

session=$src/config/sessions/vishard3/dds-coupling.yaml
source "$src/tests/e2e/session_copy.sh"  # loose_watchdogs: why, there
fail() { echo "FAIL: $*"; exit 1; }
# A Cyclone configuration as the network settings give it, plus the loss (per mille of sent packets).
lossy_xml() {  # interface peer per_mille
  cat << XML
<CycloneDDS xmlns="https://cdds.io/config"><Domain Id="any">
  <General><Interfaces><NetworkInterface name="$1" multicast="false"/></Interfaces><AllowMulticast>false</AllowMulticast></General>
  <Discovery><ParticipantIndex>auto</ParticipantIndex><Peers><Peer address="$2"/></Peers></Discovery>
  <Internal><Test><XmitLossiness>$3</XmitLossiness></Test></Internal>
</Domain></CycloneDDS>
XML
}
# run NAME PER_MILLE|secure: 5 s of the server in its namespace and the scene engine in the other, on DDS domain 99.
run() {
  local name=$1 loss=$2 server_net engine_env
  # hapticctl, which only drives the simulated operator, joins without loss (with the engine's identity when
  # secure): the loss is the server's and the engine's, and a lossy tool could miss discovery within its timeout.
  local ctl_env=(HAPTICD_DDS_NETWORK="interfaces=$if_eng;peers=192.0.2.1")
  if [ "$loss" = secure ]; then  # DDS Security's identities, their configurations moved onto the pair
    bash "$src/scripts/make-security.sh" "$work/security" 99 engine=vishard3 > /dev/null || fail "make-security.sh"
    for who in server:$if_srv:192.0.2.2 engine:$if_eng:192.0.2.1; do
      IFS=: read -r id iface peer <<< "$who"
      sed -e "s|<NetworkInterface address=\"127.0.0.1\"|<NetworkInterface name=\"$iface\"|" \
        -e "s|<Peer address=\"127.0.0.1\"/>|<Peer address=\"$peer\"/>|" "$work/security/$id/cyclonedds.xml" \
        > "$work/security/$id/lan.xml"
    done
    server_net=(--set "dds.cyclone_config=$work/security/server/lan.xml")
    engine_env=(HAPTICD_DDS_CONFIG="$work/security/engine/lan.xml")
    ctl_env=("${engine_env[@]}")
    loss=0
  elif [ "$loss" -eq 0 ]; then
    server_net=(--set "dds.network={interfaces: [$if_srv], peers: [192.0.2.2]}")
    engine_env=(HAPTICD_DDS_NETWORK="interfaces=$if_eng;peers=192.0.2.1")
  else
    lossy_xml "$if_srv" 192.0.2.2 "$loss" > "$work/srv-$name.xml"
    lossy_xml "$if_eng" 192.0.2.1 "$loss" > "$work/eng-$name.xml"
    server_net=(--set "dds.cyclone_config=$work/srv-$name.xml")
    engine_env=(HAPTICD_DDS_CONFIG="$work/eng-$name.xml")
  fi
  ip netns exec "$ns_srv" "$bin/hapticd" --config "$session" --dds-domain 99 --duration 9 \
    --stats-json "$work/stats-$name.json" --set server.realtime_priority=0 --set server.lock_memory=false \
    $(loose_watchdogs vishard3) "${server_net[@]}" > "$work/server-$name.log" 2>&1 &
  local server=$!
  ip netns exec "$ns_eng" env "${engine_env[@]}" timeout 30 "$bin/hapticd-scene-engine" --domain 99 --wait 10 \
    --duration 11 > "$work/engine-$name.log" 2>&1 &
  local engine=$!
  sleep 2
  ip netns exec "$ns_eng" env "${ctl_env[@]}" timeout 12 "$bin/hapticctl" --domain 99 --timeout 8 \
    operator vishard3 push 12 0 0 0.5 > "$work/push-$name.log" 2>&1 || fail "$name: hapticctl across the pair: $(cat "$work/push-$name.log")"
  wait "$server" || fail "$name: the server: $(tail -5 "$work/server-$name.log")"
  wait "$engine"
  grep -q '"fault": "none"' "$work/stats-$name.json" || fail "$name: the device faulted"
  python3 - "$work/stats-$name.json" "$name" "$loss" << 'PY'
import json, sys
s = json.load(open(sys.argv[1])); name, loss = sys.argv[2], int(sys.argv[3]) / 10
rt, applied, cycles = s["dds_round_trip_us"], s["dds_applied_after_cycles"], s["cycles"]
answered = rt["count"]
late = sum(applied[2:]) / max(1, sum(applied))
print(f"| {name} | {loss:.0f} % | {answered / cycles * 100:.1f} % | {rt['p50']:.0f} | {rt['p99']:.0f} | "
      f"{100 * applied[1] / max(1, sum(applied)):.1f} % | {100 * late:.2f} % | {s['dds']['deadline_misses']} |")
open(sys.argv[1] + ".row", "w").write(f"{answered} {cycles} {s['dds']['deadline_misses']} {s['dds']['commands_rejected']}\n")
PY
}

echo "| run | loss each way | cycles answered | round trip p50 [us] | p99 [us] | applied next cycle | applied later | deadline misses (fades) |"
echo "|---|---|---|---|---|---|---|---|"
run clean 0 || exit 1
grep -q "DDS interface on domain 99 (interfaces $if_srv; peers 192.0.2.2; multicast off)" "$work/server-clean.log" ||
  fail "the server did not report its network: $(grep 'DDS interface' "$work/server-clean.log")"
read -r answered cycles misses rejected < "$work/stats-clean.json.row"
# Across the pair without loss: the engine answered nearly every state of the ~5 s it ran, none rejected, no fade.
[ "$answered" -gt $((cycles / 2)) ] || fail "clean: only $answered of $cycles cycles answered"
[ "$misses" -eq 0 ] && [ "$rejected" -eq 0 ] || fail "clean: $misses deadline misses, $rejected rejected"
grep -q "accepted" "$work/push-clean.log" || fail "clean: the operator request was not accepted"
run secure secure || exit 1
read -r answered_secure cycles_secure misses_secure rejected_secure < "$work/stats-secure.json.row"
[ "$answered_secure" -gt $((cycles_secure / 2)) ] || fail "secure: only $answered_secure of $cycles_secure cycles answered"
run loss-5 50 || exit 1
run loss-20 200 || exit 1
read -r answered20 cycles20 misses20 rejected20 < "$work/stats-loss-20.json.row"
# Compared as shares of each run's cycles: the runs' lengths differ by the time discovery and the claim take, so
# counts alone do not compare (a long lossy run once answered more cycles than a short clean one). 20 % loss each
# way answers about 60 % of the cycles against 99.5 % (docs/deployment.md); 90 % of the clean share is a wide margin.
[ $((answered20 * cycles * 10)) -lt $((answered * cycles20 * 9)) ] ||
  fail "20 % loss answered nearly as large a share of cycles as none ($answered20 of $cycles20 vs $answered of $cycles)"
# Loss removes round trips but never 100 in a row: no deadline is missed, nothing fades, nothing is rejected.
for run in secure loss-5 loss-20; do
  read -r a c m r < "$work/stats-$run.json.row"
  [ "$m" -eq 0 ] && [ "$r" -eq 0 ] || fail "$run: $m deadline misses, $r rejected"
done
echo "4 passed, 0 failed"
