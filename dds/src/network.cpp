#include "hapticd/dds/network.hpp"

#include <stdexcept>

namespace hapticd::dds {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view s, char separator) {
  std::vector<std::string_view> parts;
  for (;;) {
    const std::size_t at = s.find(separator);
    parts.push_back(trim(s.substr(0, at)));
    if (at == std::string_view::npos) return parts;
    s.remove_prefix(at + 1);
  }
}

// Interface names, addresses and host names: letters, digits and . - _ : % only (nothing that means something
// in XML).
void check_name(const std::string& name, const char* what) {
  if (name.empty()) throw std::invalid_argument(std::string("an empty ") + what);
  if (name.size() > 253)
    throw std::invalid_argument(std::string(what) + " '" + name.substr(0, 40) + "...' is too long");
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' ||
                    c == '-' || c == '_' || c == ':' || c == '%';
    if (!ok)
      throw std::invalid_argument(std::string(what) + " '" + name +
                                  "' has a character other than letters, digits, . - _ : %");
  }
}

// An IPv4 or IPv6 address (digits, dots, colons) rather than an interface name.
bool looks_like_address(const std::string& s) {
  bool digit = false;
  for (const char c : s) {
    if (c >= '0' && c <= '9')
      digit = true;
    else if (c != '.' && c != ':' && !(c >= 'a' && c <= 'f') && !(c >= 'A' && c <= 'F'))
      return false;
  }
  return digit && (s.find('.') != std::string::npos || s.find(':') != std::string::npos);
}

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

}  // namespace

NetworkSettings parse_network(std::string_view spec) {
  NetworkSettings n;
  bool interfaces = false;
  for (std::string_view part : split(spec, ';')) {
    if (part.empty()) continue;
    const std::size_t eq = part.find('=');
    if (eq == std::string_view::npos)
      throw std::invalid_argument("'" + std::string(part) + "': expected key=value (interfaces, peers, multicast)");
    const std::string_view key = trim(part.substr(0, eq));
    const std::string_view value = trim(part.substr(eq + 1));
    if (key == "interfaces" || key == "peers") {
      std::vector<std::string>& list = key == "interfaces" ? n.interfaces : n.peers;
      for (std::string_view item : split(value, ','))
        if (!item.empty()) list.emplace_back(item);
      interfaces = interfaces || key == "interfaces";
    } else if (key == "multicast") {
      if (value == "true" || value == "on")
        n.multicast = true;
      else if (value == "false" || value == "off")
        n.multicast = false;
      else
        throw std::invalid_argument("multicast: expected true or false, got '" + std::string(value) + "'");
    } else {
      throw std::invalid_argument("unknown key '" + std::string(key) + "' (interfaces, peers, multicast)");
    }
  }
  if (!interfaces) throw std::invalid_argument("no interfaces= (the network interfaces by name or address)");
  validate(n);
  return n;
}

void validate(const NetworkSettings& n) {
  if (n.interfaces.empty()) throw std::invalid_argument("no network interface given");
  for (const auto& i : n.interfaces) check_name(i, "interface");
  for (const auto& p : n.peers) check_name(p, "peer");
  if (!n.multicast && n.peers.empty())
    throw std::invalid_argument("multicast off and no peers: nothing could be discovered (give peers or multicast)");
}

std::string cyclone_xml(const NetworkSettings& n) {
  validate(n);
  std::string x =
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<CycloneDDS xmlns=\"https://cdds.io/config\">\n"
      "  <Domain Id=\"any\">\n    <General>\n      <Interfaces>\n";
  const std::string multicast = n.multicast ? "true" : "false";
  for (const auto& i : n.interfaces)
    x += "        <NetworkInterface " + std::string(looks_like_address(i) ? "address" : "name") + "=\"" + i +
         "\" multicast=\"" + multicast + "\"/>\n";
  x += "      </Interfaces>\n      <AllowMulticast>" + multicast + "</AllowMulticast>\n    </General>\n";
  x += "    <Discovery>\n";
  if (!n.peers.empty()) {
    x +=
        "      <ParticipantIndex>auto</ParticipantIndex>\n      <MaxAutoParticipantIndex>60</MaxAutoParticipantIndex>\n"
        "      <Peers>\n";
    for (const auto& p : n.peers) x += "        <Peer address=\"" + p + "\"/>\n";
    x += "      </Peers>\n";
  }
  x += "    </Discovery>\n  </Domain>\n</CycloneDDS>\n";
  return x;
}

std::string describe(const NetworkSettings& n) {
  return "interfaces " + joined(n.interfaces) + "; peers " + (n.peers.empty() ? "none" : joined(n.peers)) +
         "; multicast " + (n.multicast ? "on" : "off");
}

}  // namespace hapticd::dds
