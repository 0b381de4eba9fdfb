#pragma once
// The functions of Force Dimension's SDK (libdhd, libdrd; SDK 3.x) the plugin uses, as function-pointer types
// with the prototypes of the vendor's published C headers (dhdc.h, drdc.h): every call takes the device's ID as
// its last argument (`char`; -1: the default device, the last opened). Taken by name from the library loaded at
// run time (VendorLibrary): nothing of the vendor's is compiled in.
#include "vendor_library.hpp"

namespace hapticd::plugins::forcedimension {

struct DhdApi {
  int (*error_get_last)();
  const char* (*error_get_last_str)();
  int (*get_device_count)();
  int (*open_id)(char index);
  int (*open_serial)(int serial);
  int (*close)(char id);
  const char* (*get_system_name)(char id);
  bool (*has_gripper)(char id);
  int (*enable_force)(unsigned char on, char id);
  int (*set_brakes)(int on, char id);
  int (*set_gravity_compensation)(int on, char id);
  int (*get_position)(double* x, double* y, double* z, char id);
  int (*get_linear_velocity)(double* x, double* y, double* z, char id);
  int (*get_orientation_frame)(double matrix[3][3], char id);
  int (*get_angular_velocity_rad)(double* x, double* y, double* z, char id);
  unsigned int (*get_button_mask)(char id);
  int (*get_gripper_angle_rad)(double* angle, char id);
  int (*set_force_and_torque_and_gripper_force)(double fx, double fy, double fz, double tx, double ty, double tz,
                                                double fg, char id);
  // Optional (null when the SDK lacks them): the unit's serial number and the SDK's version.
  int (*get_serial_number)(unsigned short* serial, char id);
  void (*get_sdk_version)(int* major, int* minor, int* release, int* revision);
  // libdrd only (the robotic SDK): calibration. Null when only libdhd was found.
  int (*drd_open_id)(char id);
  bool (*drd_is_initialized)(char id);
  int (*drd_auto_init)(char id);
  int (*drd_stop)(bool keep_forces, char id);

  // Takes every function from `library`; throws VendorLibraryError naming one that is missing.
  explicit DhdApi(const VendorLibrary& library);
  // The vendor's text of the last error ("no error" when none).
  [[nodiscard]] const char* last_error() const noexcept;
};

// DHD_MOTOR_SATURATED: a force call that succeeded with the force clamped by the device.
inline constexpr int kMotorSaturated = 2;

}  // namespace hapticd::plugins::forcedimension
