#include "disturbance_observer.hpp"

#include "hapticd/model/model_data.hpp"

namespace hapticd::controllers {

void DisturbanceObserver::configure(int dof, double rate_hz, double cutoff_hz, double limit_nm,
                                    double nominal_inertia) {
  dof_ = dof;
  nominal_inertia_ = nominal_inertia;
  limit_nm_ = limit_nm;
  q_filter_.set_coefficients(signal::BiquadCoefficients::lowpass(cutoff_hz, rate_hz));
  // The acceleration's own low-pass sits well above Q, so that Q sets the observer's bandwidth.
  acceleration_.configure(1.0 / rate_hz, 4.0 * cutoff_hz);
  raw_.setZero(dof);
  compensation_.setZero(dof);
}

void DisturbanceObserver::reset(const JointVector& velocity) noexcept {
  acceleration_.reset(velocity);
  raw_.setZero(dof_);
  q_filter_.reset(raw_);
  compensation_.setZero(dof_);
}

const JointVector& DisturbanceObserver::update(const model::ModelData& d, const JointVector& velocity,
                                               const JointVector& previous_command,
                                               const JointVector& operator_torques) noexcept {
  const JointVector& qdd = acceleration_.update(velocity);
  raw_.noalias() = nominal_inertia_ * (d.mass_matrix * qdd);
  raw_ += d.coriolis_torque + d.gravity_torque - previous_command - operator_torques;
  compensation_ = (-q_filter_.update(raw_)).cwiseMax(-limit_nm_).cwiseMin(limit_nm_);
  return compensation_;
}

}  // namespace hapticd::controllers
