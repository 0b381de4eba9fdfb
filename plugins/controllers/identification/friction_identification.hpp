#pragma once
// Friction identification as a controller plugin ("friction_identification"): run in a session on the device
// (simulated or real), it identifies each selected joint in turn and writes the friction file the impedance
// controller loads (friction_file). Per joint ([U06] methods 1, friction model):
//   1. break-away: from rest, the joint's torque ramps up (alternating directions) until the joint moves; the
//      torque beyond the model's gravity and Coriolis terms at that moment is a break-away sample;
//   2. Stribeck curve and load dependency: constant-velocity strokes at increasing speeds (a stepped velocity
//      ramp), back and forth. During each cruise the friction is estimated every sample against the rigid-body
//      model (FrictionEstimator: tau + J^T F_h - (M qdd + C qd + g)), and the least-squares normal equations of
//      f = p0 + p1|v| + .. + p4|v|^4 + a1|t| + a2 t^2 are accumulated, t being the static load torque the joint
//      transmits. The load varies when the handle is braced (the shipped sessions let the simulated operator's
//      arm spring resist the strokes: the other joints hold, coupling the moving joint to the load).
// All other joints hold their position under computed-torque control. The experiment's timeline is fixed by
// the parameters (duration() tells how long a session must run); the file is written at deactivate().
#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "friction_compensation.hpp"
#include "friction_estimator.hpp"
#include "hapticd/controller.hpp"
#include "trapezoid_move.hpp"

namespace hapticd::controllers {

class FrictionIdentification final : public Controller {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  Outcome activate(const ControllerInput& current, const JointCommand& last_command) override;
  Outcome update(const CycleTime& cycle, const ControllerInput& input, JointCommand& command) override;
  void deactivate() override;

  // Simulated time the whole experiment needs [s] (upper bound: break-away phases end early).
  [[nodiscard]] double duration() const noexcept { return duration_s_; }

 private:
  enum class Phase { settle, breakaway, breakaway_hold, stroke, pause, done };
  static constexpr int kFeatures = 7;
  using Features = Eigen::Matrix<double, kFeatures, 1>;
  using Normal = Eigen::Matrix<double, kFeatures, kFeatures>;

  void next_joint(const JointVector& q) noexcept;
  void start_move(double target, double speed) noexcept;
  void advance_stroke(const JointVector& q) noexcept;
  [[nodiscard]] double stroke_length(double speed) const noexcept;
  static constexpr double kPositioningSpeed = 0.5;  // [rad/s] moves that are not recorded
  static constexpr double kMaxBreakaway = 4.5;      // [N m] a ramp that has not broken away by then ends

  // Settings.
  std::vector<int> joints_;
  std::vector<double> speeds_;
  double stroke_ = 0.6, max_stroke_time_ = 4.0, acceleration_ = 30.0, breakaway_rate_ = 2.0, breakaway_motion_ = 0.002;
  int breakaway_repeats_ = 4;
  double settle_s_ = 0.5, pause_s_ = 0.2, hold_s_ = 0.3;
  double kp_ = 0.0, kd_ = 0.0;
  double load_scale_ = 20.0;
  double min_load_spread_ = 2.0;
  double period_s_ = 5e-4;
  double duration_s_ = 0.0;
  int window_ = 40;
  std::filesystem::path output_;
  std::string device_name_;
  std::vector<std::string> joint_names_;
  int dof_ = 0;

  // State.
  Phase phase_ = Phase::settle;
  int joint_index_ = -1;  // into joints_
  int joint_ = 0;         // the joint under identification
  double phase_time_ = 0.0;
  int repeat_ = 0;
  int move_ = 0;  // stroke index within the speed list (two per speed)
  double centre_ = 0.0, breakaway_start_ = 0.0;
  TrapezoidMove trapezoid_;
  JointVector q_ref_, qd_ref_, qdd_ref_, previous_command_, qdd_c_, peak_torque_, continuous_torque_;
  bool saturated_ = false;
  FrictionCompensation no_load_model_;
  FrictionEstimator estimator_;
  std::array<Normal, kMaxJoints> normal_{};
  std::array<Features, kMaxJoints> rhs_{};
  std::array<double, kMaxJoints> samples_{};
  std::array<double, kMaxJoints> breakaway_sum_{};
  std::array<int, kMaxJoints> breakaway_count_{};
};

}  // namespace hapticd::controllers
