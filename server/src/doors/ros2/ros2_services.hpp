#pragma once
// The ROS 2 door's services (docs/ros2.md, "Services"): each device's E-stop and recovery as std_srvs/srv/Trigger,
//   <ns>/<device>/estop    stops the device (a stop latches under the client that asked, as every door's)
//   <ns>/<device>/recover  leaves the safe mode (refused while another client's stop holds it)
// on the topics rmw_cyclonedds makes of a service: requests on "rq" + the name + "Request", replies on "rr" + the name
// + "Reply", each sample led by the request header rmw_cyclonedds writes before the payload (the client's GUID, the
// request's sequence number), which the reply repeats so the client knows its answer. The requests wake the gate's
// service thread, which answers them through the request dispatcher like every door's (applied once, answered again
// when sent again). Who asks is the ROS 2 participant of the request's writer (client "ros2-<its GUID prefix>"): a
// stop latches under it, and only it - any of its service clients - releases it.
#include <dds/dds.h>

#include <memory>
#include <string>
#include <vector>

#include "config/ros2_settings.hpp"
#include "hapticd/dds/entity.hpp"

namespace hapticd::server {

class Gate;
class RequestDispatcher;

namespace ros2 {

class Services {
 public:
  Services(const Ros2Settings& settings, dds_entity_t participant, Gate& gate);
  ~Services();
  Services(const Services&) = delete;
  Services& operator=(const Services&) = delete;

  void listen();
  void close();
  // The gate's service thread: answers the requests waiting.
  void answer(RequestDispatcher& dispatcher);

 private:
  struct Service {
    std::string device;
    bool estop = true;  // else recover
    dds::Entity request_topic, reply_topic, reader, writer;
  };
  Gate& gate_;
  std::vector<std::unique_ptr<Service>> services_;
};

}  // namespace ros2
}  // namespace hapticd::server
