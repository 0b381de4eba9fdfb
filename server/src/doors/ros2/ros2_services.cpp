#include "doors/ros2/ros2_services.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "doors/ros2/ros2_topic.hpp"
#include "gate/gate.hpp"
#include "gate/request_dispatcher.hpp"
#include "hapticd/dds/conversion.hpp"
#include "ros2_msg.h"

namespace hapticd::server::ros2 {
namespace {

std::optional<dds_guid_t> participant_of(dds_entity_t reader, dds_instance_handle_t writer) {
  dds_builtintopic_endpoint_t* e = dds_get_matched_publication_data(reader, writer);
  if (e == nullptr) return std::nullopt;
  const dds_guid_t guid = e->participant_key;
  dds_builtintopic_free_endpoint(e);
  return guid;
}

}  // namespace

Services::Services(const Ros2Settings& settings, dds_entity_t participant, Gate& gate) : gate_(gate) {
  const dds::Qos q = qos(Profile::commands);  // rmw_qos_profile_services_default: reliable, volatile, keep last 10
  for (const auto& d : gate.devices())
    for (const bool estop : {true, false}) {
      auto s = std::make_unique<Service>();
      s->device = d->device->name();
      s->estop = estop;
      const std::string name = settings.ns + "/" + s->device + (estop ? "/estop" : "/recover");
      const std::string what = "cannot offer the ROS 2 service " + name;
      s->request_topic =
          make_topic(participant, "rq" + name + "Request", &std_srvs_srv_dds__Trigger_Request__desc, q.get(), what);
      s->reply_topic =
          make_topic(participant, "rr" + name + "Reply", &std_srvs_srv_dds__Trigger_Response__desc, q.get(), what);
      s->reader = make_reader(participant, s->request_topic, q.get(), what);
      s->writer = make_writer(participant, s->reply_topic, q.get(), what);
      services_.push_back(std::move(s));
    }
}

Services::~Services() { close(); }

void Services::listen() {
  for (const auto& s : services_) {
    const dds::Listener listener(dds_create_listener(&gate_));
    dds_lset_data_available(listener.get(), [](dds_entity_t, void* gate) { static_cast<Gate*>(gate)->wake(); });
    (void)dds_set_listener(s->reader.get(), listener.get());
  }
}

void Services::close() {
  for (const auto& s : services_) (void)dds_set_listener(s->reader.get(), nullptr);
}

void Services::answer(RequestDispatcher& dispatcher) {
  for (const auto& s : services_)
    for (;;) {
      void* samples[8] = {};
      dds_sample_info_t infos[8];
      const dds_return_t n = dds_take(s->reader.get(), samples, infos, 8, 8);  // loaned
      if (n <= 0) break;
      for (dds_return_t i = 0; i < n; ++i) {
        if (!infos[i].valid_data) continue;
        const auto& request = *static_cast<const std_srvs_srv_dds__Trigger_Request_*>(samples[i]);
        // Who asks is the ROS 2 participant (a node's process) of the request's writer, from discovery - as the
        // DDS door's peers: a stop latches under it, and its recover client (another writer of it) may release it.
        const std::optional<dds_guid_t> participant = participant_of(s->reader.get(), infos[i].publication_handle);
        if (!participant) continue;  // a writer already gone: no one to answer
        PeerId peer = PeerId::ros2();
        std::copy(std::begin(participant->v), std::end(participant->v), peer.key.begin());
        std::string client = "ros2-";
        for (std::size_t b = 0; b < 12; ++b) client += fmt::format("{:02x}", participant->v[b]);  // its GUID prefix
        hapticd_msg_ControlRequest m{};
        dds::set_text(m.device, s->device);
        dds::set_text(m.client, client);
        // Unique within the participant: each service client of it numbers its requests from 1.
        m.request_id = (request.client_guid << 32) ^ static_cast<std::uint64_t>(request.sequence_number);
        m.kind = s->estop ? hapticd_msg_REQUEST_ESTOP : hapticd_msg_REQUEST_RECOVER;
        const hapticd_msg_ControlReply reply = dispatcher.answer(m, Sender{peer, request.client_guid});
        const std::string message(dds::text_of(reply.message));
        std_srvs_srv_dds__Trigger_Response_ response{};
        response.client_guid = request.client_guid;  // the client matches its answer by these two
        response.sequence_number = request.sequence_number;
        response.success = reply.accepted;
        response.message = const_cast<char*>(message.c_str());
        (void)dds_write(s->writer.get(), &response);
      }
      (void)dds_return_loan(s->reader.get(), samples, n);
    }
}

}  // namespace hapticd::server::ros2
