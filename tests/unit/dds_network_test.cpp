// Where the DDS interface talks (hapticd/dds/network.hpp): the network settings from a spec string (the
// environment's HAPTICD_DDS_NETWORK, the clients' option) and from the session file's dds.network, and the Cyclone
// configuration made of them.
#include <gtest/gtest.h>

#include <stdexcept>

#include "hapticd/dds/network.hpp"
#include "hapticd/dds/participant.hpp"
#include "hapticd/server/session.hpp"
#include "support/test_paths.hpp"

namespace hapticd::dds {
namespace {

TEST(DdsNetwork, ASpecNamesInterfacesPeersAndMulticast) {
  const NetworkSettings n = parse_network(" interfaces = eth1, 192.0.2.1 ; peers=192.0.2.2,lab-pc;multicast=false");
  EXPECT_EQ(n.interfaces, (std::vector<std::string>{"eth1", "192.0.2.1"}));
  EXPECT_EQ(n.peers, (std::vector<std::string>{"192.0.2.2", "lab-pc"}));
  EXPECT_FALSE(n.multicast);
  EXPECT_TRUE(parse_network("interfaces=eth0;multicast=on").multicast);  // multicast: peers not needed
  EXPECT_EQ(describe(n), "interfaces eth1,192.0.2.1; peers 192.0.2.2,lab-pc; multicast off");
}

TEST(DdsNetwork, BadSpecsAreRefusedWithWhatIsWrong) {
  const auto error = [](const char* spec) {
    try {
      (void)parse_network(spec);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(error("peers=192.0.2.2").find("no interfaces="), std::string::npos);
  EXPECT_NE(error("interfaces=eth0;pears=192.0.2.2").find("unknown key 'pears'"), std::string::npos);
  EXPECT_NE(error("interfaces=eth0;peers=192.0.2.2;multicast=maybe").find("expected true or false"), std::string::npos);
  EXPECT_NE(error("interfaces=eth0").find("nothing could be discovered"), std::string::npos);
  EXPECT_NE(error("interfaces=eth0\"/><x;peers=a").find("has a character other than"), std::string::npos);
  EXPECT_NE(error("interfaces eth0").find("expected key=value"), std::string::npos);
}

TEST(DdsNetwork, TheCycloneConfigurationBindsTheInterfacesAndDiscoversThePeers) {
  const std::string x = cyclone_xml(parse_network("interfaces=eth1,192.0.2.1;peers=192.0.2.2"));
  EXPECT_NE(x.find("<NetworkInterface name=\"eth1\" multicast=\"false\"/>"), std::string::npos) << x;
  EXPECT_NE(x.find("<NetworkInterface address=\"192.0.2.1\" multicast=\"false\"/>"), std::string::npos) << x;
  EXPECT_NE(x.find("<AllowMulticast>false</AllowMulticast>"), std::string::npos);
  EXPECT_NE(x.find("<Peer address=\"192.0.2.2\"/>"), std::string::npos);
  EXPECT_NE(x.find("<ParticipantIndex>auto</ParticipantIndex>"), std::string::npos);
  const std::string m = cyclone_xml(parse_network("interfaces=eth1;multicast=true"));
  EXPECT_NE(m.find("<AllowMulticast>true</AllowMulticast>"), std::string::npos);
  EXPECT_EQ(m.find("<Peer "), std::string::npos);
}

TEST(DdsNetwork, ParticipantsSayWhereTheyTalk) {
  EXPECT_EQ(describe_network(ParticipantOptions{7, {}, std::nullopt}), "loopback only");
  EXPECT_EQ(describe_network(ParticipantOptions{7, {}, parse_network("interfaces=eth1;peers=192.0.2.2")}),
            "interfaces eth1; peers 192.0.2.2; multicast off");
}

TEST(DdsNetwork, TheSessionFilesNetworkIsCheckedWithFileLineAndKey) {
  const std::string head =
      "server: {rate_hz: 1000}\n"
      "devices:\n"
      "  - name: d\n"
      "    device: {plugin: test_mass_spring}\n"
      "    controller: {plugin: test_pd}\n"
      "dds:\n"
      "  domain_id: 3\n";
  const auto error = [&](const std::string& network) {
    try {
      (void)server::Session::from_yaml(head + network, {{}, {hapticd::test::plugin_dir()}}, "lab.yaml");
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error("  network: {interfaces: [eth1], peers: [192.0.2.2]}\n"), "accepted");
  const std::string typo = error("  network: {interfaces: [eth1], pears: [192.0.2.2]}\n");
  EXPECT_NE(typo.find("lab.yaml:8"), std::string::npos) << typo;
  EXPECT_NE(typo.find("dds.network"), std::string::npos) << typo;
  EXPECT_NE(typo.find("did you mean 'peers'"), std::string::npos) << typo;
  EXPECT_NE(error("  network: {interfaces: [eth1]}\n").find("nothing could be discovered"), std::string::npos);
  EXPECT_NE(error("  network: {interfaces: eth1, peers: [a]}\n").find("dds.network.interfaces"), std::string::npos);
  const std::string both = error("  cyclone_config: " + hapticd::test::source_dir() +
                                 "/config/dds/cyclonedds-loopback.xml\n  network: {interfaces: [eth1], peers: [a]}\n");
  EXPECT_NE(both.find("not both"), std::string::npos) << both;
}

}  // namespace
}  // namespace hapticd::dds
