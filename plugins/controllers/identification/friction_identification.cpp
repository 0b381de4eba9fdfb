#include "friction_identification.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hapticd/chain_state.hpp"
#include "hapticd/model/friction_file.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/task_space.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::controllers {

ParameterSchema FrictionIdentification::parameter_schema() {
  ParameterSchema s;
  s.string("output_file", "friction file to write (relative: to the session file's folder)");
  s.real_vector("joints", "joints to identify, counted from 1; empty: all").default_value(std::vector<double>{});
  s.real_vector("speeds", "cruise speeds of the strokes, increasing")
      .unit("rad/s")
      .default_value(std::vector<double>{0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0});
  s.real("stroke_rad", "length of each stroke, centred on the joint's start position")
      .unit("rad")
      .greater_than(0.0)
      .default_value(0.6);
  s.real("max_stroke_time_s", "slow strokes are shortened to cruise for at most this long")
      .unit("s")
      .greater_than(0.0)
      .default_value(4.0);
  s.real("acceleration", "acceleration at the ends of each stroke")
      .unit("rad/s^2")
      .greater_than(0.0)
      .default_value(30.0);
  s.real("breakaway_rate", "torque ramp of the break-away test").unit("N m/s").greater_than(0.0).default_value(2.0);
  s.integer("breakaway_repeats", "break-away tests per joint (alternating directions)")
      .minimum(1)
      .maximum(50)
      .default_value(4);
  s.real("breakaway_motion_rad", "motion that ends a break-away ramp")
      .unit("rad")
      .greater_than(0.0)
      .default_value(0.0005);
  s.real("hold_hz", "bandwidth of the computed-torque position hold").unit("Hz").greater_than(0.0).default_value(5.0);
  s.real("load_scale_nm", "typical load torque (scales the fit's load features)")
      .unit("N m")
      .greater_than(0.0)
      .default_value(20.0);
  s.real("min_load_spread_nm",
         "the load part is identified only when the load torque varied this much (standard "
         "deviation)")
      .unit("N m")
      .greater_than(0.0)
      .default_value(2.0);
  s.integer("window", "samples of the friction estimator's differences and averages")
      .minimum(2)
      .maximum(kMaxEstimationWindow)
      .default_value(40);
  return s;
}

void FrictionIdentification::configure(const Parameters& p, const PluginContext& context) {
  if (context.device == nullptr || context.device->robot_model_file.empty()) {
    throw ParameterError("output_file", "friction identification needs a device with a robot model");
  }
  dof_ = context.device->dof();
  device_name_ = context.device->model.empty() ? context.device_name : context.device->model;
  joint_names_.clear();
  for (const auto& j : context.device->joints) joint_names_.push_back(j.name);
  output_ = p.string("output_file");
  if (output_.is_relative()) output_ = context.config_directory / output_;
  joints_.clear();
  for (double j : p.real_vector("joints")) {
    const int i = static_cast<int>(std::lround(j)) - 1;
    if (i < 0 || i >= dof_ || std::abs(j - std::round(j)) > 1e-9) {
      throw ParameterError("joints", "joint numbers run from 1 to " + std::to_string(dof_));
    }
    joints_.push_back(i);
  }
  if (joints_.empty())
    for (int i = 0; i < dof_; ++i) joints_.push_back(i);
  speeds_ = p.real_vector("speeds");
  if (speeds_.size() < 5) throw ParameterError("speeds", "needs at least 5 speeds for the 4th-order curve");
  for (std::size_t k = 0; k < speeds_.size(); ++k) {
    if (!(speeds_[k] > 0.0) || (k > 0 && speeds_[k] <= speeds_[k - 1]))
      throw ParameterError("speeds", "must be positive and increasing");
  }
  stroke_ = p.real("stroke_rad");
  acceleration_ = p.real("acceleration");
  max_stroke_time_ = p.real("max_stroke_time_s");
  if (!TrapezoidMove::reaches_speed(stroke_, speeds_.back(), acceleration_)) {
    throw ParameterError("stroke_rad", "too short to cruise at " + std::to_string(speeds_.back()) +
                                           " rad/s (needs at least speed^2 / acceleration)");
  }
  breakaway_rate_ = p.real("breakaway_rate");
  breakaway_repeats_ = static_cast<int>(p.integer("breakaway_repeats"));
  breakaway_motion_ = p.real("breakaway_motion_rad");
  const double w = 2.0 * M_PI * p.real("hold_hz");
  kp_ = w * w;
  kd_ = 2.0 * w;
  load_scale_ = p.real("load_scale_nm");
  min_load_spread_ = p.real("min_load_spread_nm");
  period_s_ = 1.0 / context.rate_hz;
  window_ = static_cast<int>(p.integer("window"));
  estimator_.configure(dof_, period_s_, window_, 0.05, 0.5 * speeds_.front());
  no_load_model_.configure(FrictionModels{}, 1.0, 0.05);  // the estimates keep their load part

  // Timeline (break-away ramps end at kMaxBreakaway at the latest).
  double per_joint = settle_s_ + breakaway_repeats_ * (kMaxBreakaway / breakaway_rate_ + hold_s_);
  per_joint += 2.0 * (TrapezoidMove{0.0, stroke_ / 2, kPositioningSpeed, acceleration_}.duration() + pause_s_);
  for (double v : speeds_)
    per_joint += 2.0 * (TrapezoidMove{0.0, stroke_length(v), v, acceleration_}.duration() + pause_s_);
  duration_s_ = per_joint * static_cast<double>(joints_.size());

  peak_torque_.resize(dof_);
  continuous_torque_.resize(dof_);
  for (int i = 0; i < dof_; ++i) {
    const JointDescription& j = context.device->joints[static_cast<std::size_t>(i)];
    peak_torque_[i] = j.torque_peak_nm;
    continuous_torque_[i] = j.torque_continuous_nm > 0.0 ? j.torque_continuous_nm : j.torque_peak_nm;
  }
  q_ref_.setZero(dof_);
  qd_ref_.setZero(dof_);
  qdd_ref_.setZero(dof_);
  qdd_c_.setZero(dof_);
  previous_command_.setZero(dof_);
}

Outcome FrictionIdentification::activate(const ControllerInput& current, const JointCommand& last_command) {
  if (current.chain.model == nullptr) return Outcome::failure("friction identification needs the device's robot model");
  q_ref_ = current.device.joints.position;
  qd_ref_.setZero(dof_);
  qdd_ref_.setZero(dof_);
  previous_command_ =
      last_command.torque_nm.size() == dof_ ? last_command.torque_nm : current.chain.data->gravity_torque;
  estimator_.reset(current.device.joints.position);
  for (auto& n : normal_) n.setZero();
  for (auto& r : rhs_) r.setZero();
  samples_.fill(0.0);
  breakaway_sum_.fill(0.0);
  breakaway_count_.fill(0);
  joint_index_ = -1;
  next_joint(current.device.joints.position);
  return Outcome::success();
}

void FrictionIdentification::next_joint(const JointVector& q) noexcept {
  ++joint_index_;
  phase_time_ = 0.0;
  if (joint_index_ >= static_cast<int>(joints_.size())) {
    phase_ = Phase::done;
    return;
  }
  joint_ = joints_[static_cast<std::size_t>(joint_index_)];
  centre_ = q[joint_];
  q_ref_[joint_] = centre_;
  repeat_ = 0;
  phase_ = Phase::settle;
}

void FrictionIdentification::start_move(double target, double speed) noexcept {
  trapezoid_ = TrapezoidMove{q_ref_[joint_], target - q_ref_[joint_], speed, acceleration_};
  phase_ = Phase::stroke;
  phase_time_ = 0.0;
}

double FrictionIdentification::stroke_length(double speed) const noexcept {
  return std::min(stroke_, speed * max_stroke_time_ + speed * speed / acceleration_);
}

void FrictionIdentification::advance_stroke(const JointVector& q) noexcept {
  // Move 0 goes out to the stroke's end, moves 1 .. 2K are the recorded strokes (two per speed), the last one
  // returns to the centre (the load relaxes before the next joint).
  const int strokes = 2 * static_cast<int>(speeds_.size());
  ++move_;
  if (move_ == strokes + 1) {
    start_move(centre_, kPositioningSpeed);
    return;
  }
  if (move_ > strokes + 1) {
    next_joint(q);
    return;
  }
  const double speed = speeds_[static_cast<std::size_t>((move_ - 1) / 2)];
  start_move(centre_ + (move_ % 2 == 1 ? -0.5 : 0.5) * stroke_length(speed), speed);
}

Outcome FrictionIdentification::update(const CycleTime& /*cycle*/, const ControllerInput& in, JointCommand& command) {
  const ChainState& c = in.chain;
  const model::ModelData& d = *c.data;
  const JointVector& q = in.device.joints.position;
  const JointVector operator_torques =
      model::operator_wrench_torques(c, std::min(6, static_cast<int>(d.frame_jacobian.rows())));
  estimator_.sample(q, previous_command_, operator_torques, d, no_load_model_, false);
  phase_time_ += period_s_;

  double ramp = 0.0;
  bool ramping = false;
  switch (phase_) {
    case Phase::settle:
      if (phase_time_ >= settle_s_) {
        phase_ = Phase::breakaway;
        phase_time_ = 0.0;
        breakaway_start_ = q[joint_];
      }
      break;
    case Phase::breakaway: {
      const double sign = repeat_ % 2 == 0 ? 1.0 : -1.0;
      ramp = sign * breakaway_rate_ * phase_time_;
      ramping = true;
      const bool moved = std::abs(q[joint_] - breakaway_start_) > breakaway_motion_;
      if (moved || std::abs(ramp) > kMaxBreakaway) {
        if (moved) {
          // The torque friction held at the gear: the ramp plus the load the operator put on the joint.
          breakaway_sum_[static_cast<std::size_t>(joint_)] += std::abs(ramp + operator_torques[joint_]);
          ++breakaway_count_[static_cast<std::size_t>(joint_)];
        }
        q_ref_[joint_] = q[joint_];
        phase_ = Phase::breakaway_hold;
        phase_time_ = 0.0;
      }
      break;
    }
    case Phase::breakaway_hold:
      if (phase_time_ >= hold_s_) {
        ++repeat_;
        if (repeat_ < breakaway_repeats_) {
          phase_ = Phase::breakaway;
          phase_time_ = 0.0;
          breakaway_start_ = q[joint_];
        } else {
          move_ = 0;
          start_move(centre_ + 0.5 * stroke_length(speeds_.front()), kPositioningSpeed);
        }
      }
      break;
    case Phase::stroke: {
      double qj = 0.0, vj = 0.0, aj = 0.0;
      trapezoid_.at(phase_time_, qj, vj, aj);
      q_ref_[joint_] = qj;
      qd_ref_[joint_] = vj;
      qdd_ref_[joint_] = aj;
      const double ta = trapezoid_.accel_time();
      const double settled = ta + 2.0 * window_ * period_s_;
      const double v = estimator_.last_velocity()[joint_];
      const bool recorded = move_ > 0 && move_ <= 2 * static_cast<int>(speeds_.size());
      if (recorded && estimator_.valid() && phase_time_ > settled && phase_time_ < ta + trapezoid_.cruise_time() &&
          std::abs(v - vj) < 0.1 * trapezoid_.speed &&  // cruising, not catching up with the reference
          !saturated_) {
        const double u = std::abs(v) / speeds_.back();
        const double w = std::abs(estimator_.last_load()[joint_]) / load_scale_;
        Features x;
        x << 1.0, u, u * u, u * u * u, u * u * u * u, w, w * w;
        const auto k = static_cast<std::size_t>(joint_);
        const double h = (v > 0.0 ? 1.0 : -1.0) * estimator_.last_estimate()[joint_];
        normal_[k].noalias() += x * x.transpose();
        rhs_[k].noalias() += x * h;
        samples_[k] += 1.0;
      }
      if (phase_time_ >= trapezoid_.duration()) {
        qd_ref_[joint_] = 0.0;
        qdd_ref_[joint_] = 0.0;
        phase_ = Phase::pause;
        phase_time_ = 0.0;
      }
      break;
    }
    case Phase::pause:
      if (phase_time_ >= pause_s_) advance_stroke(q);
      break;
    case Phase::done:
      break;
  }

  // Computed-torque hold / tracking of every joint.
  qdd_c_ = qdd_ref_ + kd_ * (qd_ref_ - in.device.joints.velocity) + kp_ * (q_ref_ - q);
  command.torque_nm.noalias() = d.mass_matrix * qdd_c_;
  command.torque_nm += d.coriolis_torque + d.gravity_torque;
  if (ramping) command.torque_nm[joint_] = d.gravity_torque[joint_] + d.coriolis_torque[joint_] + ramp;
  // What the drives will deliver: the server clamps to the peak torque. A saturated sample says nothing
  // about friction (the torque balance no longer holds with the commanded value) and is not recorded.
  const JointVector limited = command.torque_nm.cwiseMax(-peak_torque_).cwiseMin(peak_torque_);
  // Above the continuous torque a drive may be thermally limited below the command, so those samples are
  // not recorded either.
  saturated_ = (command.torque_nm.cwiseAbs().array() > 0.9 * continuous_torque_.array()).any();
  command.torque_nm = limited;
  previous_command_ = command.torque_nm;
  return Outcome::success();
}

void FrictionIdentification::deactivate() {
  const bool complete = phase_ == Phase::done;
  const int finished = joint_index_;
  model::FrictionFile file;
  file.device = device_name_;
  for (int i = 0; i < dof_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    model::FrictionModel m;
    const bool identified = std::find(joints_.begin(), joints_.end(), i) != joints_.end() && samples_[k] > 100.0;
    if (identified) {
      // With the load features only when the load varied enough to tell them from the constant; else the
      // sliding curve alone (which then holds the average load part).
      const double n = samples_[k];
      const double mean_w = normal_[k](0, 5) / n;
      const double spread_nm = std::sqrt(std::max(0.0, normal_[k](5, 5) / n - mean_w * mean_w)) * load_scale_;
      Features x = Features::Zero();
      const Eigen::ColPivHouseholderQR<Normal> full(normal_[k]);
      if (spread_nm >= min_load_spread_ && full.rank() == kFeatures) {
        x = full.solve(rhs_[k]);
      } else {
        const Eigen::Matrix<double, 5, 5> a = normal_[k].topLeftCorner<5, 5>();
        x.head<5>() = Eigen::ColPivHouseholderQR<Eigen::Matrix<double, 5, 5>>(a).solve(rhs_[k].head<5>());
      }
      double scale = 1.0;
      for (std::size_t j = 0; j < 5; ++j) {
        m.p[j] = x[static_cast<int>(j)] / scale;
        scale *= speeds_.back();
      }
      m.load = {0.0, x[5] / load_scale_, x[6] / (load_scale_ * load_scale_)};
      m.velocity_max = speeds_.back();
    }
    if (breakaway_count_[k] > 0) m.breakaway_nm = breakaway_sum_[k] / breakaway_count_[k];
    file.joint_names.push_back(k < joint_names_.size() ? joint_names_[k] : "joint" + std::to_string(i + 1));
    file.joints.push_back(m);
  }
  model::write_friction_file(output_, file);
  if (!complete) {
    throw std::runtime_error("friction identification incomplete: the session ended after " + std::to_string(finished) +
                             " of " + std::to_string(joints_.size()) + " joints; it needs " +
                             std::to_string(static_cast<int>(std::ceil(duration_s_))) + " s (server.duration_s). " +
                             output_.string() + " holds the joints identified so far");
  }
}

}  // namespace hapticd::controllers
