#pragma once
// A domain participant on hapticd's Cyclone configuration. Unless told otherwise every participant uses the
// built-in loopback-only configuration (config/dds/cyclonedds-loopback.xml, compiled in): the loopback
// interface, multicast off, unicast discovery to 127.0.0.1. The domain is created once per process and id
// with that configuration and shared by the participants on it (the server and a client in one test process).
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

#include "hapticd/dds/entity.hpp"

namespace hapticd::dds {

// The built-in configuration (XML text).
[[nodiscard]] std::string_view loopback_config_xml() noexcept;

struct ParticipantOptions {
  int domain_id = 0;
  std::filesystem::path cyclone_config;  // empty: the built-in loopback configuration
};

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
