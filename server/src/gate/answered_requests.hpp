#pragma once
// The replies to the newest requests, so that a request sent again is answered again and applied once: requests
// are idempotent by (requester's peer, client id, request id, target). A client sends a request again
// when no reply came in time - the first may have reached the server before discovery let it know the requester,
// or the reply may have been written before the client's reply reader was matched. Fixed capacity (the oldest
// reply is forgotten first): a client that invents ids creates no server state beyond it.
#include <array>
#include <cstddef>
#include <optional>

#include "gate/peer.hpp"
#include "hapticd_msg.h"

namespace hapticd::server {

class AnsweredRequests {
 public:
  static constexpr std::size_t kCapacity = 256;

  // The reply given to this request before, if it is still remembered.
  [[nodiscard]] const hapticd_msg_ControlReply* find(const PeerId& requester,
                                                     const hapticd_msg_ControlRequest& request) const noexcept;
  // Remembers the reply to a request (replacing the oldest once full).
  void remember(const PeerId& requester, const hapticd_msg_ControlReply& reply) noexcept;
  [[nodiscard]] std::size_t size() const noexcept { return size_; }

 private:
  struct Entry {
    PeerId requester;
    hapticd_msg_ControlReply reply;  // carries the client id, the request id and the target
  };
  std::array<Entry, kCapacity> entries_{};
  std::size_t next_ = 0, size_ = 0;
};

}  // namespace hapticd::server
