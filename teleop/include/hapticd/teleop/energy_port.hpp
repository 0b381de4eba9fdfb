#pragma once
// One port of a teleoperation link under the time-domain passivity approach (Hannaford and Ryu; Ryu and
// Preusche's energy exchange for delayed links; docs/teleoperation.md, "Passivity"): an observer that splits the
// power through the port into the energy that enters the link here and the energy that leaves it here, and a
// passivity controller that lets no more energy leave here than has entered at the other port - as that port
// last reported it, which a lost or late packet only makes smaller. The controller is a variable damper: in
// series at a port where the link outputs a force, in parallel where it outputs a velocity. Real-time safe.
#include <Eigen/Core>

namespace hapticd::teleop {

class EnergyPort {
 public:
  // A port where the link applies `force` to the local side, which moves at `velocity`: the power out of the link
  // is force . velocity. With `control`, the force is reduced along the velocity so that the energy out stays
  // within `available_in` (the energy in at the other port, as received, in this port's units); without, it is
  // only observed. Returns the force to apply.
  Eigen::Vector3d force_out(const Eigen::Vector3d& force, const Eigen::Vector3d& velocity, double dt,
                            double available_in, bool control) noexcept;

  // A port where the link moves the local side at `velocity` against the local side's `reaction` force on it: the
  // power out of the link is -reaction . velocity. With `control`, the velocity is reduced along the reaction
  // force as above. Returns the velocity to impose.
  Eigen::Vector3d velocity_out(const Eigen::Vector3d& velocity, const Eigen::Vector3d& reaction, double dt,
                               double available_in, bool control) noexcept;

  [[nodiscard]] double energy_in() const noexcept { return in_; }           // entered the link here [J]
  [[nodiscard]] double energy_out() const noexcept { return out_; }         // left it here [J]
  [[nodiscard]] double dissipated() const noexcept { return dissipated_; }  // by the controller [J]
  // The last step's observed energy: what the other port has let in minus what left here (negative: the link
  // created energy at this port - what the controller prevents).
  [[nodiscard]] double observed() const noexcept { return observed_; }
  [[nodiscard]] bool limiting() const noexcept { return limiting_; }  // the controller acted in the last step

 private:
  // The step's energies from the power out before and after the controller.
  void account(double power_before, double power_after, double dt, double available_in) noexcept;
  // The power out the budget cannot pay for this step (0: none).
  [[nodiscard]] double excess(double power, double dt, double available_in) const noexcept;

  double in_ = 0.0, out_ = 0.0, dissipated_ = 0.0, observed_ = 0.0;
  bool limiting_ = false;
};

}  // namespace hapticd::teleop
