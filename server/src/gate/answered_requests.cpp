#include "gate/answered_requests.hpp"

#include "hapticd/dds/conversion.hpp"

namespace hapticd::server {

const hapticd_msg_ControlReply* AnsweredRequests::find(const PeerId& requester,
                                                       const hapticd_msg_ControlRequest& request) const noexcept {
  for (std::size_t k = 0; k < size_; ++k) {
    const Entry& e = entries_[k];
    if (e.reply.request_id == request.request_id && e.requester == requester &&
        dds::text_of(e.reply.client) == dds::text_of(request.client) &&
        dds::text_of(e.reply.device) == dds::text_of(request.device))
      return &e.reply;
  }
  return nullptr;
}

void AnsweredRequests::remember(const PeerId& requester, const hapticd_msg_ControlReply& reply) noexcept {
  entries_[next_] = Entry{requester, reply};
  next_ = (next_ + 1) % kCapacity;
  if (size_ < kCapacity) ++size_;
}

}  // namespace hapticd::server
