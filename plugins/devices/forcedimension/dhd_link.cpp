#include "dhd_link.hpp"

#include <cstdio>

namespace hapticd::plugins::forcedimension {

DhdLink::DhdLink(std::unique_ptr<VendorLibrary> loaded)
    : library(std::move(loaded)), dhd(std::make_unique<DhdApi>(*library)) {
  read_job = [this] {
    failed = false;
    read();
  };
  write_job = [this] {
    failed = false;
    sdk.calling("dhdSetForceAndTorqueAndGripperForce");
    (void)check(dhd->set_force_and_torque_and_gripper_force(force[0], force[1], force[2], force[3], force[4], force[5],
                                                            force[6], id),
                "writing the force");  // kMotorSaturated (> 0): clamped by the device, within its own limits
  };
  brake_job = [this] {
    failed = false;
    sdk.calling("dhdSetBrakes");
    (void)check(dhd->set_brakes(brakes_on ? 1 : 0, id), brakes_on ? "braking" : "releasing the brakes");
  };
  enable_job = [this] {
    failed = false;
    sdk.calling("dhdSetGravityCompensation");
    if (!check(dhd->set_gravity_compensation(device_gravity ? 1 : 0, id), "gravity compensation")) return;
    sdk.calling("dhdEnableForce");
    if (!check(dhd->enable_force(1, id), "enabling forces")) return;
    sdk.calling("dhdSetBrakes");
    (void)check(dhd->set_brakes(0, id), "releasing the brakes");
  };
  close_job = [this] { close(); };
}

DhdLink::~DhdLink() { close(); }

bool DhdLink::check(int result, const char* what) noexcept {
  if (result >= 0) return true;
  failed = true;
  std::snprintf(error.data(), error.size(), "%s: %.200s", what, dhd->last_error());
  return false;
}

void DhdLink::read() noexcept {
  DhdReading& r = reading;
  sdk.calling("dhdGetPosition");
  if (!check(dhd->get_position(&r.position[0], &r.position[1], &r.position[2], id), "reading the position")) return;
  sdk.calling("dhdGetLinearVelocity");
  if (!check(dhd->get_linear_velocity(&r.velocity[0], &r.velocity[1], &r.velocity[2], id), "reading the velocity"))
    return;
  if (orientation) {
    sdk.calling("dhdGetOrientationFrame");
    if (!check(dhd->get_orientation_frame(r.frame, id), "reading the orientation")) return;
    sdk.calling("dhdGetAngularVelocityRad");
    if (!check(
            dhd->get_angular_velocity_rad(&r.angular_velocity[0], &r.angular_velocity[1], &r.angular_velocity[2], id),
            "reading the angular velocity"))
      return;
  }
  sdk.calling("dhdGetButtonMask");
  r.buttons = dhd->get_button_mask(id);
  if (gripper) {
    sdk.calling("dhdGetGripperAngleRad");
    (void)check(dhd->get_gripper_angle_rad(&r.gripper_rad, id), "reading the gripper");
  }
}

void DhdLink::close() noexcept {
  if (!open) return;
  sdk.calling("dhdSetForceAndTorqueAndGripperForce");
  (void)dhd->set_force_and_torque_and_gripper_force(0, 0, 0, 0, 0, 0, 0, id);
  sdk.calling("dhdEnableForce");
  (void)dhd->enable_force(0, id);
  sdk.calling("dhdSetBrakes");
  (void)dhd->set_brakes(1, id);
  sdk.calling("dhdClose");
  (void)dhd->close(id);
  open = false;
}

}  // namespace hapticd::plugins::forcedimension
