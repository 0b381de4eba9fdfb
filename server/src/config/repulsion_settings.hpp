#pragma once
// A device group's `repulsion` settings (docs/multi-device.md): the spring-damper between two arms of a group
// below a clearance. The group stage computes it (group/repulsion.hpp).

namespace hapticd::server {

struct RepulsionSettings {
  double distance_m = 0.0;  // 0: off
  double stiffness_n_per_m = 1000.0;
  double damping_n_s_per_m = 10.0;
  double max_force_n = 20.0;  // on each handle
  // Low-pass of the joint torques (first order, Hz; 0: none): the closest points of two nearly parallel links jump
  // along their overlap as the links turn past parallel, and with them the lever of the force.
  double filter_hz = 40.0;
};

}  // namespace hapticd::server
