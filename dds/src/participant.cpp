#include "hapticd/dds/participant.hpp"

#include <cstdlib>
#include <map>
#include <mutex>

#include "hapticd/input_file.hpp"

namespace hapticd::dds {
namespace {

// A regular file of at most 1 MiB (a /dev/zero or a named pipe there is refused, never read: hapticd/input_file.hpp).
std::string read_file(const std::filesystem::path& path) {
  return read_input_file(path, "Cyclone DDS configuration", 1024u * 1024u);
}

const char* environment(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0' ? v : nullptr;
}

// The Cyclone configuration (XML text) for the options: file, settings, environment, loopback.
std::string configuration(const ParticipantOptions& o) {
  if (!o.cyclone_config.empty()) return read_file(o.cyclone_config);
  if (o.network) return cyclone_xml(*o.network);
  if (const char* file = environment(kConfigVariable)) return read_file(file);
  if (const char* spec = environment(kNetworkVariable)) {
    try {
      return cyclone_xml(parse_network(spec));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string(kNetworkVariable) + ": " + e.what());
    }
  }
  return std::string(loopback_config_xml());
}

// One domain entity per id and process, created with our configuration before any participant exists on it
// (a participant created first would make Cyclone create the domain from CYCLONEDDS_URI instead).
std::shared_ptr<Entity> shared_domain(const ParticipantOptions& options) {
  static std::mutex mutex;
  static std::map<int, std::weak_ptr<Entity>> domains;
  const int id = options.domain_id;
  std::lock_guard lock(mutex);
  if (auto existing = domains[id].lock()) return existing;
  const std::string config = configuration(options);
  auto domain = std::make_shared<Entity>(
      check(dds_create_domain(static_cast<dds_domainid_t>(id), config.c_str()), "cannot create the DDS domain"));
  domains[id] = domain;
  return domain;
}

}  // namespace

std::string describe_network(const ParticipantOptions& o) {
  if (!o.cyclone_config.empty()) return "Cyclone configuration " + o.cyclone_config.string();
  if (o.network) return describe(*o.network);
  if (const char* file = environment(kConfigVariable))
    return std::string("Cyclone configuration ") + file + " (" + kConfigVariable + ")";
  if (const char* spec = environment(kNetworkVariable))
    return describe(parse_network(spec)) + " (" + kNetworkVariable + ")";
  return "loopback only";
}

Participant::Participant(const ParticipantOptions& options)
    : domain_(shared_domain(options)),
      participant_(check(dds_create_participant(static_cast<dds_domainid_t>(options.domain_id), nullptr, nullptr),
                         "cannot create the DDS participant")),
      domain_id_(options.domain_id) {}

Participant::~Participant() {
  participant_.reset();  // before the domain it lives in
}

}  // namespace hapticd::dds
