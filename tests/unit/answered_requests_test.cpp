// The gate's memory of answered requests (gate/answered_requests): a request is recognised by requester,
// client id, request id and target; the memory is bounded, the oldest forgotten first.
#include "gate/answered_requests.hpp"

#include <gtest/gtest.h>

#include "hapticd/dds/conversion.hpp"

namespace hapticd::server {
namespace {

PeerId peer(unsigned char k) {
  std::array<unsigned char, 16> guid{};
  guid[0] = k;
  return PeerId::dds_participant(guid);
}
hapticd_msg_ControlRequest request(std::uint64_t id, const char* client = "c", const char* device = "v3") {
  hapticd_msg_ControlRequest r{};
  r.request_id = id;
  dds::set_text(r.client, client);
  dds::set_text(r.device, device);
  return r;
}
hapticd_msg_ControlReply reply_to(const hapticd_msg_ControlRequest& r, const char* message) {
  hapticd_msg_ControlReply a{};
  a.request_id = r.request_id;
  std::copy(std::begin(r.client), std::end(r.client), a.client);
  std::copy(std::begin(r.device), std::end(r.device), a.device);
  dds::set_text(a.message, message);
  return a;
}

TEST(AnsweredRequests, ARequestIsKnownByRequesterClientIdAndTarget) {
  auto answered = std::make_unique<AnsweredRequests>();
  answered->remember(peer(1), reply_to(request(7), "first"));
  const hapticd_msg_ControlReply* again = answered->find(peer(1), request(7));
  ASSERT_NE(again, nullptr);
  EXPECT_EQ(dds::text_of(again->message), "first");
  EXPECT_EQ(answered->find(peer(2), request(7)), nullptr);             // another participant
  EXPECT_EQ(answered->find(peer(1), request(8)), nullptr);             // another id
  EXPECT_EQ(answered->find(peer(1), request(7, "d")), nullptr);        // another client id
  EXPECT_EQ(answered->find(peer(1), request(7, "c", "v4")), nullptr);  // another target
}

TEST(AnsweredRequests, TheMemoryIsBoundedAndForgetsTheOldestFirst) {
  auto answered = std::make_unique<AnsweredRequests>();
  const std::size_t n = AnsweredRequests::kCapacity;
  for (std::uint64_t id = 1; id <= n + 10; ++id) answered->remember(peer(1), reply_to(request(id), "ok"));
  EXPECT_EQ(answered->size(), n);
  for (std::uint64_t id = 1; id <= 10; ++id) EXPECT_EQ(answered->find(peer(1), request(id)), nullptr) << id;
  for (std::uint64_t id = 11; id <= n + 10; ++id) EXPECT_NE(answered->find(peer(1), request(id)), nullptr) << id;
}

}  // namespace
}  // namespace hapticd::server
