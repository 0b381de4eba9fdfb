#pragma once
// RAII ownership of a Cyclone DDS entity handle: dds_delete on destruction (which deletes its children too).
#include <dds/dds.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "hapticd/export.hpp"

namespace hapticd::dds {

// A Cyclone call that failed: the message names what was tried and why; code() is Cyclone's return code
// (DDS_RETCODE_NOT_ALLOWED_BY_SECURITY: DDS Security's permissions refused it).
class HAPTICD_API Error : public std::runtime_error {
 public:
  Error(const char* what, dds_return_t code)
      : std::runtime_error(std::string(what) + ": " + dds_strretcode(code)), code_(code) {}
  [[nodiscard]] dds_return_t code() const noexcept { return code_; }

 private:
  dds_return_t code_;
};

// Throws Error naming `what` when a Cyclone call returned a negative (error) value.
inline dds_entity_t check(dds_entity_t result, const char* what) {
  if (result < 0) throw Error(what, result);
  return result;
}

class Entity {
 public:
  Entity() = default;
  explicit Entity(dds_entity_t handle) : handle_(handle) {}
  Entity(Entity&& other) noexcept : handle_(std::exchange(other.handle_, 0)) {}
  Entity& operator=(Entity&& other) noexcept {
    if (this != &other) {
      reset();
      handle_ = std::exchange(other.handle_, 0);
    }
    return *this;
  }
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;
  ~Entity() { reset(); }

  void reset() noexcept {
    if (handle_ > 0) (void)dds_delete(handle_);
    handle_ = 0;
  }
  [[nodiscard]] dds_entity_t get() const noexcept { return handle_; }
  explicit operator bool() const noexcept { return handle_ > 0; }

 private:
  dds_entity_t handle_ = 0;
};

// A listener (callbacks on Cyclone's threads), deleted with dds_delete_listener.
struct ListenerDeleter {
  void operator()(dds_listener_t* l) const noexcept { dds_delete_listener(l); }
};
using Listener = std::unique_ptr<dds_listener_t, ListenerDeleter>;

}  // namespace hapticd::dds
