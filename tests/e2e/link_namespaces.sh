# Sourced by tests/e2e/teleop_netns_test.sh and scripts/soak.sh: a teleoperation pair's two hosts on one machine -
# three network namespaces, the master's (192.0.2.1) and the remote's (192.0.2.130) joined only through a third's
# two veth pairs (192.0.2.2 | 192.0.2.129), where hapticd-link-relay runs; and each side's Cyclone DDS
# configuration, which names the relay as its peer and advertises the relay's address facing the other side.
# Needs root and iproute2.

# link_namespaces_up TAG: creates them (names and interfaces carry TAG: unique per process); sets ns_m, ns_r,
# ns_x and if_m, if_r (the sides' interfaces). Returns 1 with link_namespaces_error set when one cannot be made.
link_namespaces_up() {
  local tag=$1
  ns_m="hapticd-m-$tag" ns_r="hapticd-r-$tag" ns_x="hapticd-x-$tag" if_m="lm$tag" if_r="lr$tag"
  link_namespaces_error=
  ip netns add "$ns_m" 2> /tmp/hapticd-netns.$$ || { link_namespaces_error="cannot create a network namespace: $(cat /tmp/hapticd-netns.$$)"; rm -f /tmp/hapticd-netns.$$; return 1; }
  rm -f /tmp/hapticd-netns.$$
  ip netns add "$ns_r" || { link_namespaces_error="cannot create a second network namespace"; return 1; }
  ip netns add "$ns_x" || { link_namespaces_error="cannot create a third network namespace"; return 1; }
  ip link add "$if_m" netns "$ns_m" type veth peer name "lxm$tag" netns "$ns_x" 2> /dev/null ||
    { link_namespaces_error="cannot create a veth pair"; return 1; }
  ip link add "$if_r" netns "$ns_r" type veth peer name "lxr$tag" netns "$ns_x" ||
    { link_namespaces_error="cannot create a second veth pair"; return 1; }
  ip -n "$ns_m" addr add 192.0.2.1/25 dev "$if_m"
  ip -n "$ns_x" addr add 192.0.2.2/25 dev "lxm$tag"
  ip -n "$ns_x" addr add 192.0.2.129/25 dev "lxr$tag"
  ip -n "$ns_r" addr add 192.0.2.130/25 dev "$if_r"
  local n
  for n in "$ns_m" "$ns_r" "$ns_x"; do ip -n "$n" link set lo up; done
  ip -n "$ns_m" link set "$if_m" up
  ip -n "$ns_r" link set "$if_r" up
  ip -n "$ns_x" link set "lxm$tag" up
  ip -n "$ns_x" link set "lxr$tag" up
}

# link_namespaces_down: ends what runs in them and removes them (veth pairs go with their namespaces).
link_namespaces_down() {
  local n
  for n in "${ns_m:-}" "${ns_r:-}" "${ns_x:-}"; do
    [ -n "$n" ] && ip netns pids "$n" 2> /dev/null | xargs -r kill 2> /dev/null
  done
  sleep 0.2
  for n in "${ns_m:-}" "${ns_r:-}" "${ns_x:-}"; do [ -n "$n" ] && ip netns del "$n" 2> /dev/null; done
  return 0
}

# link_cyclone_xml INTERFACE RELAY_HERE RELAY_THERE: a side's Cyclone configuration.
link_cyclone_xml() {
  cat << XML
<CycloneDDS xmlns="https://cdds.io/config"><Domain Id="any">
  <General><Interfaces><NetworkInterface name="$1" multicast="false"/></Interfaces><AllowMulticast>false</AllowMulticast>
    <ExternalNetworkAddress>$3</ExternalNetworkAddress></General>
  <Discovery><ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>4</MaxAutoParticipantIndex>
    <Peers><Peer address="$2"/></Peers></Discovery>
</Domain></CycloneDDS>
XML
}
