#!/usr/bin/env bash
# DDS Security for hapticd (docs/deployment.md, "A secure lab network"): creates, with openssl, a certificate
# authority, one identity per role and the signed governance and permissions documents, and a Cyclone
# configuration per identity that turns on authentication, access control and encryption.
#   scripts/make-security.sh OUT_DIR [DOMAIN_SPEC] [ENGINE=DEVICES ...] [teleop:NAME=OWN,PEER ...]
#     DOMAIN_SPEC: e.g. 0 or 0-230 (default 0-230); ENGINE=DEVICES: an engine identity and the devices (or groups)
#     it may command, comma-separated, * for all (default: engine=*); teleop:NAME=OWN,PEER: the identity of a
#     teleoperation side's server whose device is OWN and whose peer's is PEER (docs/teleoperation.md)
# Identities: server (the hapticd server: every topic but the teleoperation link's), one per engine (writes
# requests and commands in its devices' partitions only - hapticd.<device>, docs/dds-interface.md -, its world in
# the default partition, the haptic scene's requests there too when it may command every device, and reads the
# server's topics), one per teleoperation side (a server's topics, and the link's packets written only in its own
# device's partition hapticd.teleop.OWN and read only from its peer's, so no other identity can speak for either
# side), watcher (may only watch: reads the server's topics, writes nothing). The governance
# document requires authentication for joining, encrypts discovery, liveliness and every topic's payload, and
# checks read and write access on every topic. Keys are EC P-256; certificates valid for 365 days.
# OUT_DIR/<identity>/cyclonedds.xml is what `dds.cyclone_config` (server) or HAPTICD_DDS_CONFIG (clients) takes;
# it keeps the loopback-only network (edit its Interfaces and Peers for a lab network).
set -euo pipefail
set -f  # the topic and partition patterns (hapticd_*, *) are not file names
out=${1:?usage: make-security.sh OUT_DIR [DOMAIN_SPEC] [ENGINE=DEVICES ...]}
domains=${2:-0-230}
shift $(($# < 2 ? $# : 2))
engines=() sides=()
for a in "$@"; do
  case $a in
    teleop:*=*,*) sides+=("${a#teleop:}") ;;
    teleop:*) echo "make-security: '$a': a teleoperation side is teleop:NAME=OWN_DEVICE,PEER_DEVICE" >&2; exit 2 ;;
    *=*) engines+=("$a") ;;
    *) echo "make-security: '$a': an engine is NAME=DEVICES" >&2; exit 2 ;;
  esac
done
[ ${#engines[@]} -eq 0 ] && [ ${#sides[@]} -eq 0 ] && engines=("engine=*")
command -v openssl > /dev/null || { echo "make-security: openssl is needed" >&2; exit 1; }
mkdir -p "$out"
out=$(cd "$out" && pwd)
plugins=/usr/lib/x86_64-linux-gnu/libddsc0debian
[ -e "$plugins/libdds_security_auth.so" ] || plugins=$(dirname "$(find /usr/lib -name 'libdds_security_auth.so' | head -1)")

lo=${domains%-*} hi=${domains#*-}
domain_xml="<id_range><min>$lo</min><max>$hi</max></id_range>"
[ "$lo" = "$hi" ] && domain_xml="<id>$lo</id>"

# ---- certificate authority (identities and permissions are signed by the same CA here) ----
if [ ! -f "$out/ca.pem" ]; then
  openssl ecparam -name prime256v1 -genkey -noout -out "$out/ca_key.pem" 2> /dev/null
  openssl req -x509 -new -key "$out/ca_key.pem" -days 365 -subj "/C=DE/O=hapticd lab/CN=hapticd CA" \
    -out "$out/ca.pem" 2> /dev/null
fi

# ---- governance: who may join, what is protected ----
cat > "$out/governance.xml" << XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains>$domain_xml</domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
        <topic_rule>
          <topic_expression>*</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>NONE</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
XML
openssl smime -sign -in "$out/governance.xml" -text -out "$out/governance.p7s" -signer "$out/ca.pem" \
  -inkey "$out/ca_key.pem" 2> /dev/null

# ---- one identity per role, and what it may publish and subscribe ----
# The server's topics: every one but the teleoperation link's (hapticd_teleop), which only the sides' identities
# may write, each in its own device's partition.
server_topics="hapticd_description hapticd_state hapticd_reply hapticd_event hapticd_telemetry hapticd_fault_report"
server_topics="$server_topics hapticd_group_description hapticd_group_state hapticd_plugin_api_version"
server_topics="$server_topics hapticd_plugin_catalog hapticd_world hapticd_command hapticd_group_command hapticd_request"
server_topics="$server_topics hapticd_scene_request hapticd_scene_mesh_part hapticd_scene_reply"
# A ros2 section's topics and services (docs/ros2.md): ROS 2's DDS names, under its default namespace.
server_topics="$server_topics rt/hapticd/* rt/tf rq/hapticd/* rr/hapticd/*"
engine_publish="hapticd_command hapticd_group_command hapticd_request"
reads="hapticd_description hapticd_state hapticd_reply hapticd_event hapticd_telemetry hapticd_fault_report hapticd_group_description hapticd_group_state hapticd_scene_reply"
reads="$reads rt/hapticd/* rt/tf"  # and a ros2 section's published topics
topics_xml() { set -f; for t in $1; do printf '<topic>%s</topic>' "$t"; done; set +f; }  # (no globbing: rt/hapticd/*)
partitions_xml() { for p in $1; do printf '<partition>%s</partition>' "$p"; done; }
grant() {  # name publish-topics subscribe-topics [publish-partitions [server]]  (a client's subscriptions: the
  # default partition; a server's: its publishing partitions)
  local name=$1 subject="/C=DE/O=hapticd lab/CN=$1" kind=${5:-client}
  local publish="" subscribe="" partitions=""
  [ -n "${4:-}" ] && partitions="<partitions>$(partitions_xml "$4")</partitions>"
  [ -n "$2" ] && publish="<publish><topics>$(topics_xml "$2")</topics>$partitions</publish>"
  # An engine's world for the live view (hapticd_world) is written in the default partition, and so are the
  # session's haptic scene's requests (one scene per server, keyless: docs/haptic-scene.md) - by an engine that may
  # command every device only: every device of the session feels the scene.
  local own="hapticd_world"
  case " ${4:-} " in *" hapticd.* "*) own="$own hapticd_scene_request hapticd_scene_mesh_part" ;; esac
  [ "$kind" != server ] && [ -n "$2" ] && publish="$publish<publish><topics>$(topics_xml "$own")</topics></publish>"
  [ -n "$3" ] && subscribe="<subscribe><topics>$(topics_xml "$3")</topics>$partitions</subscribe>"
  [ "$kind" != server ] && subscribe="<subscribe><topics>$(topics_xml "$3")</topics></subscribe>"
  [ -z "$3" ] && subscribe=""
  cat << XML
    <grant name="$name">
      <subject_name>$(echo "$subject" | sed 's|^/||; s|/|,|g')</subject_name>
      <validity><not_before>2020-01-01T00:00:00</not_before><not_after>2040-01-01T00:00:00</not_after></validity>
      <allow_rule><domains>$domain_xml</domains>$publish$subscribe</allow_rule>
      <default>DENY</default>
    </grant>
XML
}
{
  echo '<?xml version="1.0" encoding="UTF-8"?>'
  echo '<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">'
  echo '  <permissions>'
  grant server "$server_topics" "$server_topics" "*" server
  for e in "${engines[@]}"; do
    devices=${e#*=} parts=""
    for d in ${devices//,/ }; do parts="$parts hapticd.$d"; done
    grant "${e%%=*}" "$engine_publish" "$reads" "$parts"
  done
  grant watcher "" "$reads"
  for t in "${sides[@]}"; do
    name=${t%%=*} pair=${t#*=}
    own=${pair%%,*} peer=${pair#*,}
    grant "$name" "$server_topics" "$server_topics" "*" server |
      sed "s|</allow_rule>|<publish><topics><topic>hapticd_teleop</topic></topics><partitions><partition>hapticd.teleop.$own</partition></partitions></publish><subscribe><topics><topic>hapticd_teleop</topic></topics><partitions><partition>hapticd.teleop.$peer</partition></partitions></subscribe></allow_rule>|"
  done
  echo '  </permissions>'
  echo '</dds>'
} > "$out/permissions.xml"
openssl smime -sign -in "$out/permissions.xml" -text -out "$out/permissions.p7s" -signer "$out/ca.pem" \
  -inkey "$out/ca_key.pem" 2> /dev/null

identities=(server watcher)
for e in "${engines[@]}"; do identities+=("${e%%=*}"); done
for t in "${sides[@]}"; do identities+=("${t%%=*}"); done
for name in "${identities[@]}"; do
  dir="$out/$name"
  mkdir -p "$dir"
  openssl ecparam -name prime256v1 -genkey -noout -out "$dir/key.pem" 2> /dev/null
  openssl req -new -key "$dir/key.pem" -subj "/C=DE/O=hapticd lab/CN=$name" -out "$dir/request.csr" 2> /dev/null
  openssl x509 -req -in "$dir/request.csr" -CA "$out/ca.pem" -CAkey "$out/ca_key.pem" -CAcreateserial -days 365 \
    -out "$dir/certificate.pem" 2> /dev/null
  rm -f "$dir/request.csr"
  cat > "$dir/cyclonedds.xml" << XML
<?xml version="1.0" encoding="UTF-8"?>
<!-- hapticd's loopback-only configuration with DDS Security as identity '$name' (scripts/make-security.sh). -->
<CycloneDDS xmlns="https://cdds.io/config">
  <Domain Id="any">
    <General>
      <Interfaces><NetworkInterface address="127.0.0.1" multicast="false"/></Interfaces>
      <AllowMulticast>false</AllowMulticast>
      <DontRoute>true</DontRoute>
    </General>
    <Discovery>
      <ParticipantIndex>auto</ParticipantIndex>
      <MaxAutoParticipantIndex>60</MaxAutoParticipantIndex>
      <Peers><Peer address="127.0.0.1"/></Peers>
    </Discovery>
    <Security>
      <Authentication>
        <Library path="$plugins/libdds_security_auth.so" initFunction="init_authentication" finalizeFunction="finalize_authentication"/>
        <IdentityCA>file:$out/ca.pem</IdentityCA>
        <IdentityCertificate>file:$dir/certificate.pem</IdentityCertificate>
        <PrivateKey>file:$dir/key.pem</PrivateKey>
      </Authentication>
      <AccessControl>
        <Library path="$plugins/libdds_security_ac.so" initFunction="init_access_control" finalizeFunction="finalize_access_control"/>
        <PermissionsCA>file:$out/ca.pem</PermissionsCA>
        <Governance>file:$out/governance.p7s</Governance>
        <Permissions>file:$out/permissions.p7s</Permissions>
      </AccessControl>
      <Cryptographic>
        <Library path="$plugins/libdds_security_crypto.so" initFunction="init_crypto" finalizeFunction="finalize_crypto"/>
      </Cryptographic>
    </Security>
  </Domain>
</CycloneDDS>
XML
done
set +f
chmod 600 "$out"/ca_key.pem "$out"/*/key.pem
echo "make-security: CA, governance, permissions and identities ${identities[*]} in $out"
