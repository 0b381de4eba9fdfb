#include "doors/doors.hpp"

#include <stdexcept>

namespace hapticd::server {

Doors::Doors(const SessionConfig& config, std::vector<DeviceSession*> sessions, std::vector<GroupStage*> stages,
             std::vector<int> cpus)
    : gate_(std::make_unique<Gate>(config.gate, config.server.rate_hz, std::move(sessions), std::move(stages), cpus)) {
  if (config.dds.enabled) {
    try {
      dds_ = std::make_unique<DdsDoor>(config.dds, *gate_, cpus);
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("DDS interface: ") + e.what());
    }
  }
  if (config.teleoperation.enabled) {
    DeviceGate* linked = gate_->devices().find(config.teleoperation.device);
    if (linked == nullptr) throw std::runtime_error("teleoperation: no device '" + config.teleoperation.device + "'");
    if (!dds_) throw std::runtime_error("teleoperation: the link travels over DDS: the session needs a dds section");
    TeleopPhase* phase = linked->device->teleoperation();
    if (phase == nullptr)
      throw std::runtime_error("teleoperation: the device '" + config.teleoperation.device +
                               "' runs no link side (DeviceSession::enable_teleoperation)");
    link_ = std::make_unique<TeleopLink>(config.teleoperation, *linked, *phase, dds_->participant(), gate_->events(),
                                         config.server.clock != ClockMode::lockstep);
    gate_->add_door(*link_);
  }
  if (config.engine_socket.enabled) {
    socket_ = std::make_unique<EngineSocket>(config.engine_socket, *gate_, cpus);  // binds its port (an error names it)
    gate_->add_door(*socket_);
  }
  if (dds_) gate_->add_door(*dds_);
  if (config.ros2.enabled) {
    try {
      ros2_ = std::make_unique<Ros2Door>(config.ros2, config.dds, *gate_);
    } catch (const std::exception& e) {
      throw std::runtime_error(std::string("ROS 2 topics: ") + e.what());
    }
    gate_->add_door(*ros2_);  // last: the ROS 2 topics are for watching, the engines' doors come first
  }
}

Doors::~Doors() {
  gate_->stop();
  ros2_.reset();
  link_.reset();
  socket_.reset();
  dds_.reset();
}

void Doors::relay_worlds(std::function<void(const hapticd_msg_World&)> sink) {
  if (dds_) dds_->relay_worlds(std::move(sink));
}

}  // namespace hapticd::server
