#!/usr/bin/env bash
# Teleoperation on one machine, in one command (docs/teleoperation.md, "Try it"): the master's server and the remote's
# server in two network namespaces joined only through a third, where hapticd-link-relay delays and drops their
# datagrams; the master's simulated operator reaches 5 cm ahead and pushes, the remote meets its wall 3 cm ahead.
# While it runs, hapticctl reaches each side (the script shows both devices, and prints the commands to watch them);
# at the end, both servers' reports. The namespaces (addresses from 192.0.2.0/24) are removed at the end. Needs root
# (network namespaces) and iproute2.
#   sudo scripts/teleop-demo.sh [--delay-ms 20] [--loss 0.05] [--seconds 15] [--bin DIR] [--out DIR]
#     --delay-ms: one way, each direction (the round trip is twice that); --loss: each way, 0..0.9;
#     --bin: the programs (default: build/default/bin, else build/ci/bin, else those on PATH)
set -uo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
delay=20 loss=0.05 seconds=15 bin="" out=""
while [ $# -gt 0 ]; do
  case $1 in
    --delay-ms) delay=$2; shift 2 ;;
    --loss) loss=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h | --help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "teleop-demo: unknown option '$1' (--help)" >&2; exit 2 ;;
  esac
done
[ "$(id -u)" -eq 0 ] || { echo "teleop-demo: the two sides run in network namespaces, which need root: sudo $0" >&2; exit 2; }
command -v ip > /dev/null || { echo "teleop-demo: needs ip (iproute2)" >&2; exit 2; }
if [ -z "$bin" ]; then
  for b in "$src/build/default/bin" "$src/build/ci/bin"; do [ -x "$b/hapticd" ] && { bin=$b; break; }; done
  [ -n "$bin" ] || bin=$(dirname "$(command -v hapticd || echo /nonexistent/hapticd)")
fi
[ -x "$bin/hapticd" ] || { echo "teleop-demo: no hapticd in ${bin} (build first: ./scripts/test.sh, or --bin DIR)" >&2; exit 2; }
out=${out:-$(mktemp -d "${TMPDIR:-/tmp}/hapticd-teleop-demo.XXXXXX")}
mkdir -p "$out"
source "$src/tests/e2e/link_namespaces.sh"
trap link_namespaces_down EXIT
link_namespaces_up "d$$" || { echo "teleop-demo: $link_namespaces_error" >&2; exit 1; }

domain=157  # the unicast ports of participant indices 0-4 on this domain: 46660-46669 (7400 + 250 * 157 + 10 ..)
link_cyclone_xml "$if_m" 192.0.2.2 192.0.2.129 > "$out/master.xml"
link_cyclone_xml "$if_r" 192.0.2.129 192.0.2.2 > "$out/remote.xml"
# A client on a side (hapticctl) talks to that side's server only: its own address as its peer, nothing advertised.
# The server advertises the relay's address facing the other side (so the other side's packets go through the
# relay); on the server's own side that address is made local, so the side's clients reach their server directly.
ip -n "$ns_m" addr add 192.0.2.129/32 dev lo
ip -n "$ns_r" addr add 192.0.2.2/32 dev lo
client_xml() {  # INTERFACE SERVER_ADDRESS
  cat << XML
<CycloneDDS xmlns="https://cdds.io/config"><Domain Id="any">
  <General><Interfaces><NetworkInterface name="$1" multicast="false"/></Interfaces><AllowMulticast>false</AllowMulticast></General>
  <Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>9</MaxAutoParticipantIndex>
    <Peers><Peer address="$2"/></Peers></Discovery>
</Domain></CycloneDDS>
XML
}
client_xml "$if_m" 192.0.2.1 > "$out/master-client.xml"
client_xml "$if_r" 192.0.2.130 > "$out/remote-client.xml"
ip netns exec "$ns_x" "$bin/hapticd-link-relay" --route 192.0.2.2=192.0.2.130 --route 192.0.2.129=192.0.2.1 \
  --ports 46660-46669 --delay-ms "$delay" --jitter-ms 1 --loss "$loss" --seed 3 --duration $((seconds + 6)) \
  > "$out/relay.log" 2>&1 &
sleep 0.5
common=(--dds-domain "$domain" --duration "$seconds" --busy-machine --set server.realtime_priority=0
  --set server.lock_memory=false --log-level info)
p=devices.master.device.parameters
ip netns exec "$ns_r" "$bin/hapticd" --config "$src/config/sessions/teleoperation/remote.yaml" \
  --set "dds.cyclone_config=$out/remote.xml" "${common[@]}" > "$out/remote.log" 2>&1 &
remote=$!
ip netns exec "$ns_m" "$bin/hapticd" --config "$src/config/sessions/teleoperation/master.yaml" \
  --set "dds.cyclone_config=$out/master.xml" "${common[@]}" --set "$p.operator_motion=step" \
  --set "$p.operator_motion_m=[0.05, 0, 0]" --set "$p.operator_motion_start_s=2" > "$out/master.log" 2>&1 &
master=$!
echo "teleop-demo: master and remote servers running for $seconds s, $delay ms each way, loss $loss each way; logs in $out"
ctl() {  # SIDE ARGS...: hapticctl in that side's namespace, with its Cyclone configuration
  local side=$1 ns; shift
  ns=$([ "$side" = master ] && echo "$ns_m" || echo "$ns_r")
  ip netns exec "$ns" "$bin/hapticctl" --domain "$domain" --cyclone-config "$out/$side-client.xml" --timeout 5 "$@"
}
sleep 3
echo "--- hapticctl on the master's side:"; ctl master list
echo "--- hapticctl on the remote's side:"; ctl remote list
echo "--- to watch a side while it runs (another shell):"
echo "sudo ip netns exec $ns_m $bin/hapticctl --domain $domain --cyclone-config $out/master-client.xml watch master"
echo "sudo ip netns exec $ns_r $bin/hapticctl --domain $domain --cyclone-config $out/remote-client.xml watch remote"
sleep 3
echo "--- the operator pushes 10 N harder into the wall for 3 s (hapticctl operator, the master's side):"
ctl master operator master push 10 0 0 0.5
sleep 3
ctl master operator master release > /dev/null
wait "$master"; master_code=$?
wait "$remote"; remote_code=$?
for side in master remote; do
  echo "--- the $side's report:"
  grep -E "teleoperation link|device '$side'" "$out/$side.log" | sed 's/^\[[^]]*\] \[[a-z]*\] //'
done
grep -E "relayed" "$out/relay.log" | sed 's/^/--- relay: /'
[ "$master_code" -eq 0 ] && [ "$remote_code" -eq 0 ] || { echo "teleop-demo: the servers exited with $master_code (master), $remote_code (remote)"; exit 1; }
