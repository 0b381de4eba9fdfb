#include "dhd_api.hpp"

namespace hapticd::plugins::forcedimension {

DhdApi::DhdApi(const VendorLibrary& l)
    : error_get_last(l.function<decltype(error_get_last)>("dhdErrorGetLast")),
      error_get_last_str(l.function<decltype(error_get_last_str)>("dhdErrorGetLastStr")),
      get_device_count(l.function<decltype(get_device_count)>("dhdGetDeviceCount")),
      open_id(l.function<decltype(open_id)>("dhdOpenID")),
      open_serial(l.function<decltype(open_serial)>("dhdOpenSerial")),
      close(l.function<decltype(close)>("dhdClose")),
      get_system_name(l.function<decltype(get_system_name)>("dhdGetSystemName")),
      has_gripper(l.function<decltype(has_gripper)>("dhdHasGripper")),
      enable_force(l.function<decltype(enable_force)>("dhdEnableForce")),
      set_brakes(l.function<decltype(set_brakes)>("dhdSetBrakes")),
      set_gravity_compensation(l.function<decltype(set_gravity_compensation)>("dhdSetGravityCompensation")),
      get_position(l.function<decltype(get_position)>("dhdGetPosition")),
      get_linear_velocity(l.function<decltype(get_linear_velocity)>("dhdGetLinearVelocity")),
      get_orientation_frame(l.function<decltype(get_orientation_frame)>("dhdGetOrientationFrame")),
      get_angular_velocity_rad(l.function<decltype(get_angular_velocity_rad)>("dhdGetAngularVelocityRad")),
      get_button_mask(l.function<decltype(get_button_mask)>("dhdGetButtonMask")),
      get_gripper_angle_rad(l.function<decltype(get_gripper_angle_rad)>("dhdGetGripperAngleRad")),
      set_force_and_torque_and_gripper_force(
          l.function<decltype(set_force_and_torque_and_gripper_force)>("dhdSetForceAndTorqueAndGripperForce")),
      get_serial_number(l.optional_function<decltype(get_serial_number)>("dhdGetSerialNumber")),
      get_sdk_version(l.optional_function<decltype(get_sdk_version)>("dhdGetSDKVersion")),
      drd_open_id(l.optional_function<decltype(drd_open_id)>("drdOpenID")),
      drd_is_initialized(l.optional_function<decltype(drd_is_initialized)>("drdIsInitialized")),
      drd_auto_init(l.optional_function<decltype(drd_auto_init)>("drdAutoInit")),
      drd_stop(l.optional_function<decltype(drd_stop)>("drdStop")) {}

const char* DhdApi::last_error() const noexcept {
  const char* text = error_get_last_str();
  return text != nullptr ? text : "an error the SDK does not describe";
}

}  // namespace hapticd::plugins::forcedimension
