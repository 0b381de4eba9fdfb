#pragma once
// Finiteness checks of the chain's signals: nothing non-finite may reach a motor.
#include "hapticd/chain_signals.hpp"

namespace hapticd::server {

inline bool is_finite(const Wrench& w) noexcept { return w.force.allFinite() && w.torque.allFinite(); }
inline bool is_finite(const Twist& t) noexcept { return t.linear.allFinite() && t.angular.allFinite(); }
inline bool is_finite(const Pose& p) noexcept { return p.position.allFinite() && p.orientation.coeffs().allFinite(); }

inline bool is_finite(const DeviceState& s) noexcept {
  return s.joints.position.allFinite() && s.joints.velocity.allFinite() && s.joints.effort.allFinite() &&
         is_finite(s.sensor_wrench);
}

inline bool is_finite(const TaskTarget& t) noexcept {
  return is_finite(t.pose) && is_finite(t.twist) && is_finite(t.acceleration) && is_finite(t.wrench);
}

inline bool is_finite(const JointTarget& t) noexcept {
  return t.position.allFinite() && t.velocity.allFinite() && t.acceleration.allFinite();
}

}  // namespace hapticd::server
