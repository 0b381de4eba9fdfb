#pragma once
// A domain participant on hapticd's Cyclone configuration. Unless told otherwise every participant uses the
// built-in loopback-only configuration (config/dds/cyclonedds-loopback.xml, compiled in): the loopback
// interface, multicast off, unicast discovery to 127.0.0.1. Told otherwise, in this order: a Cyclone XML file,
// network settings (network.hpp), the environment's HAPTICD_DDS_CONFIG (a file), then HAPTICD_DDS_NETWORK
// (settings). The domain is created once per process and id with the configuration of the first participant on
// it and shared by the others (the server and a client in one test process).
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "hapticd/dds/entity.hpp"
#include "hapticd/dds/network.hpp"

namespace hapticd::dds {

// The built-in configuration (XML text).
[[nodiscard]] std::string_view loopback_config_xml() noexcept;

struct ParticipantOptions {
  int domain_id = 0;
  std::filesystem::path cyclone_config;    // a Cyclone XML file
  std::optional<NetworkSettings> network;  // else these settings; neither: the environment, else loopback only
};

// Where a participant with these options talks: "loopback only", the file, or the settings (for logs). Throws
// std::invalid_argument for a malformed HAPTICD_DDS_NETWORK.
[[nodiscard]] std::string describe_network(const ParticipantOptions& options);

class Participant {
 public:
  explicit Participant(const ParticipantOptions& options = {});
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  [[nodiscard]] dds_entity_t get() const noexcept { return participant_.get(); }
  [[nodiscard]] int domain_id() const noexcept { return domain_id_; }

 private:
  std::shared_ptr<Entity> domain_;  // shared with the other participants of this process on the same id
  Entity participant_;
  int domain_id_ = 0;
};

}  // namespace hapticd::dds
