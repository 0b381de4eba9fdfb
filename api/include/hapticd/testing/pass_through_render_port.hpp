#pragma once
// A RenderPort for testing a virtual model outside the server: no passivity control, no limits, no safety force
// (the server's own is in server/src/safety/render_guard). Counts the calls, so a test can see what the model used.
#include "hapticd/render_port.hpp"

namespace hapticd::testing {

class PassThroughRenderPort final : public RenderPort {
 public:
  Vector6 engine_port(const Vector6& wrench, const Vector6& /*port_twist*/) noexcept override {
    ++engine_port_calls;
    return wrench;
  }
  Vector6 limit(const Vector6& wrench) noexcept override {
    ++limit_calls;
    return wrench;
  }
  [[nodiscard]] Eigen::Vector3d take_safety_force() noexcept override {
    ++safety_force_takes;
    return Eigen::Vector3d::Zero();
  }

  int engine_port_calls = 0;
  int safety_force_takes = 0;
  int limit_calls = 0;
};

}  // namespace hapticd::testing
