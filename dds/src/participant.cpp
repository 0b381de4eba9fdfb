#include "hapticd/dds/participant.hpp"

#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

namespace hapticd::dds {
namespace {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read the Cyclone DDS configuration " + path.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// One domain entity per id and process, created with our configuration before any participant exists on it
// (a participant created first would make Cyclone create the domain from CYCLONEDDS_URI instead).
std::shared_ptr<Entity> shared_domain(int id, const std::filesystem::path& config_file) {
  static std::mutex mutex;
  static std::map<int, std::weak_ptr<Entity>> domains;
  std::lock_guard lock(mutex);
  if (auto existing = domains[id].lock()) return existing;
  const std::string config = config_file.empty() ? std::string(loopback_config_xml()) : read_file(config_file);
  auto domain = std::make_shared<Entity>(
      check(dds_create_domain(static_cast<dds_domainid_t>(id), config.c_str()), "cannot create the DDS domain"));
  domains[id] = domain;
  return domain;
}

}  // namespace

Participant::Participant(const ParticipantOptions& options)
    : domain_(shared_domain(options.domain_id, options.cyclone_config)),
      participant_(check(dds_create_participant(static_cast<dds_domainid_t>(options.domain_id), nullptr, nullptr),
                         "cannot create the DDS participant")),
      domain_id_(options.domain_id) {}

Participant::~Participant() {
  participant_.reset();  // before the domain it lives in
}

}  // namespace hapticd::dds
