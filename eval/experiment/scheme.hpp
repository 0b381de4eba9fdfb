#pragma once
// The control schemes the thesis evaluates (../shared/spec/CONTROL-METHODS.md section 4), as plugin chains:
//   impedance display: open-loop impedance control, PD force feedback (Kp, Kd);
//   admittance display: a virtual admittance (pure mass) and an inner motion loop - resolved acceleration (RAC),
//   inverse Jacobian (IJC), transposed Jacobian (TJC), or computed torque in joint space on the device's inverse
//   kinematics (CTC) - with position gain kp (bandwidth sqrt(kp), critically damped) and acceleration
//   feedforward on or off.
// The task rows (translation for ViSHaRD3, full for the others) are the rig's: they follow the device.
#include <string>

namespace hapticd::eval {

struct Scheme {
  enum class Display { impedance, admittance };
  std::string id;     // file-name friendly: "rac-kp10000-ff"
  std::string label;  // for figures: "RAC, kp 10000, 3 kg, feedforward"
  Display display = Display::impedance;
  std::string controller;             // plugin name
  std::string controller_parameters;  // YAML flow-mapping body without the task: "force_gain: 1.5"
  double virtual_mass_kg = 0.0;       // admittance display
  double force_gain = 0.0;            // impedance display: Kp
  // The same as id and label without the rendered mass ("rac-kp10000-ff", "RAC, kp 10000, feedforward").
  std::string loop_id, loop_label;
  bool joint_space = false;  // runs on the device's inverse kinematics (computed torque)
  bool task_rows = true;     // the controller takes the rig's `task` (not so a joint-space identification)
};

Scheme open_loop_impedance();
Scheme pd_force_feedback(double kp, double kd);
// inner: "rac", "ijc", "tjc" or "ctc".
Scheme admittance(const std::string& inner, double kp, double virtual_mass_kg, bool feedforward);

}  // namespace hapticd::eval

namespace hapticd::eval {

// A scheme from its command-line spelling: "open-loop"; "pd:KP:KD"; "rac:KP[:ff]", "ijc:KP[:ff]", "tjc:KP[:ff]",
// "ctc:KP[:ff]"
// (admittance display rendering `virtual_mass_kg`). Throws std::invalid_argument naming the bad part.
Scheme parse_scheme(const std::string& text, double virtual_mass_kg);

}  // namespace hapticd::eval
