#pragma once
// Joint-space disturbance observer ([U06] methods 1, [4.6-4.9]). With the nominal model of the
// device, M qdd + C qd + g = tau + J^T F_h + d, the disturbance (friction, model errors) is estimated as
//   d_hat = Q(s) [ a M qdd + C qd + g - tau_prev - J^T F_h ]
// with qdd from the differentiated joint velocity, tau_prev the torque commanded in the previous cycle and
// Q a second-order low-pass; the controller adds -d_hat to its command. The nominal inertia a M (a <= 1)
// sets what the operator feels: a = 1 removes friction and model errors, a < 1 also (1 - a) of the inertia. At rest the
// estimate acts as an integrator of the operator's force (it breaks stiction), so it is limited to +-limit per joint.
// Real-time safe.
#include "hapticd/joint_vector.hpp"
#include "hapticd/signal/biquad.hpp"
#include "hapticd/signal/differentiator.hpp"

namespace hapticd::model {
struct ModelData;
}

namespace hapticd::controllers {

class DisturbanceObserver {
 public:
  // Throws std::invalid_argument for a cut-off at or above the Nyquist frequency.
  void configure(int dof, double rate_hz, double cutoff_hz, double limit_nm, double nominal_inertia = 1.0);
  void reset(const JointVector& velocity) noexcept;
  // data: the cycle's model terms (mass_matrix, coriolis_torque, gravity_torque); operator_torques: J^T F_h.
  // Returns the torque to add to the command (-d_hat).
  const JointVector& update(const model::ModelData& data, const JointVector& velocity,
                            const JointVector& previous_command, const JointVector& operator_torques) noexcept;

 private:
  int dof_ = 0;
  double limit_nm_ = 2.0;
  double nominal_inertia_ = 1.0;
  signal::Differentiator<JointVector> acceleration_;
  signal::Biquad<JointVector> q_filter_;
  JointVector raw_, compensation_;
};

}  // namespace hapticd::controllers
