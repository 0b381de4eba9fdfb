#pragma once
// Drive train of one joint (gear, motor, encoder) as read from the URDF's <hapticd_drive> extension
// (docs/robot-models.md). Torques in N m, inertias in kg m^2; "joint" quantities are at the gear output.
#include <string>

#include "hapticd/export.hpp"

namespace hapticd::model {

struct HAPTICD_API DriveData {
  std::string gear;                  // type designation, informative
  double gear_ratio = 1.0;           // motor turns per joint turn
  double gear_peak_torque = 0.0;     // repeated peak torque of the gear [N m, output]
  double gear_average_torque = 0.0;  // limit for average torque of the gear [N m, output]
  double stiffness_min = 0.0;        // torsional stiffness at low load [N m/rad]
  double stiffness_max = 0.0;        // torsional stiffness at rated load [N m/rad]
  // Compliance of the structure (links, bearings, sensor mount) in series with the gear, as a torsional
  // stiffness at the joint [N m/rad]; 0: rigid (optional attribute; the simulator's structural_compliance).
  double structural_stiffness = 0.0;
  // Damping ratio of the drive's spring (the gear's hysteresis, on the motor inertia); below 0: not given
  // (optional attribute; the simulator then uses its own default).
  double damping_ratio = -1.0;
  double max_input_speed_rpm = 0.0;      // gear input (motor) speed limit
  double wave_generator_inertia = 0.0;   // [kg m^2, motor side]
  std::string motor;                     // type designation, informative
  double motor_stall_torque = 0.0;       // [N m, motor side]
  double motor_continuous_torque = 0.0;  // [N m, motor side]
  double rotor_inertia = 0.0;            // [kg m^2, motor side]
  int encoder_counts_per_motor_rev = 0;  // after quadrature
  bool present = false;                  // false: a joint without drive data (ideal actuator)

  // Derived joint-output quantities ([U06] device data).
  [[nodiscard]] double peak_joint_torque() const noexcept {
    const double motor_limit = motor_stall_torque * gear_ratio;
    return motor_limit < gear_peak_torque ? motor_limit : gear_peak_torque;
  }
  [[nodiscard]] double continuous_joint_torque() const noexcept { return motor_continuous_torque * gear_ratio; }
  [[nodiscard]] double max_joint_speed() const noexcept;  // [rad/s]
  [[nodiscard]] double reflected_inertia() const noexcept {
    return (rotor_inertia + wave_generator_inertia) * gear_ratio * gear_ratio;
  }
  [[nodiscard]] double joint_counts_per_rev() const noexcept { return encoder_counts_per_motor_rev * gear_ratio; }
};

}  // namespace hapticd::model
