#pragma once
// The virtual admittance ([U06] methods 2): the operator's wrench drives a virtual rigid body,
//   translation  M_t xdd + D_t xd = F              (world axes)
//   rotation     M_r wd + w x (M_r w) + D_r w = T  (Euler's equations in the body frame)
// whose pose (a unit quaternion: no representation singularities) is the desired handle pose of the inner
// motion controller. Semi-implicit Euler at the control rate, with integration limits on the velocities.
// Virtual walls (half-spaces: a point and an outward normal of the free side) push the virtual body back with
// a unilateral spring-damper; the wall force is reported as the environment wrench of the target. With
// motion_based the walls act on the measured handle motion instead of the virtual body's (the thesis's
// motion-based impedance control: walls do not drift when the inner loop is not integral). A workspace spring
// (workspace_radius_m) pulls the body back towards a sphere around its start position, a soft workspace limit.
// Virtual coupling (spec section 2, [3.5]): with coupling on, an impedance-type rendering engine's proxy pose
// (EngineInput) pulls the virtual body through a spring-damper Z_d1 in series with the admittance Z_d2; a
// wrench the engine sends is applied as it is, plus its local linear model (stiffness and damping about an
// anchor) evaluated every cycle; an admittance-type engine's desired motion replaces the body's own. All of it
// is scaled by EngineInput::weight, which the server fades to zero when the engine misses its deadline (a
// stalled or disconnected engine lets go of the device smoothly instead of holding it).
// The wrench of walls, coupling and engine is reported as the target's environment wrench.
// Anti-windup: while the drives saturate (ChainState::output_saturated), the virtual body would run away from
// the device and the inner loop would "wind up" its error, lunging after the body once free. With
// max_tracking_error_m / max_tracking_angle_rad the body is then kept within that distance of the measured
// handle (conditional integration): it is projected back onto the limit and loses the velocity and
// acceleration that would take it further.
#include <array>

#include "hapticd/chain_state.hpp"
#include "hapticd/engine_input.hpp"
#include "hapticd/realtime/latest_value.hpp"
#include "hapticd/virtual_model.hpp"

namespace hapticd::models {

// Impedance display: the device displays `wrench` ([force; torque], world) at the measured handle, which is the
// target's pose and twist (the state's target pose: the body an engine's proxy is computed from).
inline void display_on_handle(TaskTarget& target, const ChainState& chain, const Eigen::Matrix<double, 6, 1>& wrench) {
  target.pose = chain.handle_pose;
  target.twist = chain.handle_twist;
  target.wrench.force = wrench.head<3>();
  target.wrench.torque = wrench.tail<3>();
  target.has_wrench = true;
  target.has_motion = false;
}

class VirtualAdmittance final : public VirtualModel {
 public:
  static ParameterSchema parameter_schema();

  void configure(const Parameters& parameters, const PluginContext& context) override;
  // configure() without the check that the device measures the operator's force: the walls, the workspace spring
  // and the coupling rendered on the measured handle motion (impedance display; the scripted_wrench model).
  void configure_environment(const Parameters& parameters, const PluginContext& context);
  Outcome activate(const VirtualModelInput& current) override;
  Outcome update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target) override;
  // The same with a scripted wrench ([force; torque], world) added to the environment's: a test signal the
  // model renders as it renders its walls (through the limits, not through the engine port's passivity
  // controller, which would damp an active source away). The scripted_wrench model uses it.
  Outcome update(const CycleTime& cycle, const VirtualModelInput& input, TaskTarget& target,
                 const Eigen::Matrix<double, 6, 1>& scripted);
  void deactivate() override {}
  // The tunable parameters (masses, dampings, wall, coupling and workspace stiffness), taken at the next cycle.
  void tune(const Parameters& parameters) override;
  // Takes the parameters tune() handed over (update() does it every cycle; a caller that uses wall_force alone
  // calls it at its cycle boundary). Real-time safe.
  void take_tuning() noexcept {
    if (tunable_inbox_.take(tunable_incoming_)) apply(tunable_incoming_);
  }
  // The force of the walls and the workspace spring (world) on a body at `position` moving with `velocity`;
  // the scripted_wrench model renders them on the measured handle motion in impedance display.
  [[nodiscard]] Eigen::Vector3d wall_force(const Eigen::Vector3d& position,
                                           const Eigen::Vector3d& velocity) const noexcept;
  // With `coupling`, the rendering engine's coupling and wrench [force; torque] (world) on a body at (position,
  // orientation) moving with (velocity, angular velocity), scaled by the engine input's weight (zero without
  // `coupling`, without input, or for a motion command); the scripted_wrench model renders it on the measured
  // handle in impedance display.
  [[nodiscard]] Eigen::Matrix<double, 6, 1> engine_wrench(const EngineInput& engine, const Eigen::Vector3d& position,
                                                          const Eigen::Quaterniond& orientation,
                                                          const Eigen::Vector3d& velocity,
                                                          const Eigen::Vector3d& angular_velocity) const noexcept;
  [[nodiscard]] bool takes_engine_input() const noexcept { return coupling_; }
  // The virtual body's position and velocity (world) as the last cycle left them: the haptic scene's proxy
  // follows the body in admittance display.
  [[nodiscard]] const Eigen::Vector3d& body_position() const noexcept { return position_; }
  [[nodiscard]] const Eigen::Vector3d& body_velocity() const noexcept { return velocity_; }

 private:
  struct Wall {
    Eigen::Vector3d point, normal;
  };
  static constexpr int kMaxWalls = 8;

  // The body's state at the start of a cycle, before its own dynamics: what an engine's motion is followed from.
  struct BodyState {
    Eigen::Vector3d position, velocity, body_angular_velocity;
    Eigen::Quaterniond orientation;
  };
  void follow_engine_motion(const EngineInput& engine, std::int64_t now_ns, const BodyState& start,
                            const ChainState& chain) noexcept;
  // At most 1: the factor that keeps the joint speeds of the handle moving at `velocity` within their shares.
  [[nodiscard]] double joint_speed_scale(const ChainState& chain, const Eigen::Vector3d& velocity) const noexcept;

  // The parameters tune() may change.
  struct Tunable {
    Eigen::Vector3d mass, damping, inertia, rotational_damping;
    double wall_k = 0.0, wall_b = 0.0, coupling_k = 0.0, coupling_b = 0.0, coupling_kr = 0.0, coupling_br = 0.0,
           workspace_k = 0.0;
  };
  static Tunable tunable_of(const Parameters& parameters);
  void apply(const Tunable& tunable) noexcept;
  realtime::LatestValue<Tunable> tunable_inbox_;
  Tunable tunable_incoming_{};

  Eigen::Vector3d mass_, inertia_, damping_, rotational_damping_;
  std::array<Wall, kMaxWalls> walls_{};
  int wall_count_ = 0;
  double wall_stiffness_ = 0.0, wall_damping_ = 0.0;
  bool motion_based_ = false;
  bool walls_relative_ = false;
  double workspace_radius_ = 0.0, workspace_stiffness_ = 1000.0;
  Eigen::Vector3d workspace_centre_ = Eigen::Vector3d::Zero();
  std::array<Eigen::Vector3d, kMaxWalls> configured_wall_points_{};
  bool coupling_ = false;
  double coupling_k_ = 2000.0, coupling_b_ = 20.0, coupling_kr_ = 20.0, coupling_br_ = 0.2;
  double max_velocity_ = 1.0, max_angular_velocity_ = 5.0;
  // An admittance-type engine's motion is followed within these (and the speed limits above).
  double engine_max_acceleration_ = 10.0, engine_max_angular_acceleration_ = 50.0;
  double engine_max_hand_force_ = 50.0;
  double hand_yield_ = 1.0;  // the share of the engine's motion followed (1: all; less while the hand is loaded)
  std::array<double, 16> joint_speed_limit_{};  // engine_joint_speed_fraction x each joint's velocity_max
  std::size_t joint_count_ = 0;
  double max_tracking_error_ = 0.0, max_tracking_angle_ = 0.0;  // 0: no anti-windup limit
  // true when the translation was limited.
  bool limit_tracking_error(const ChainState& chain) noexcept;
  bool rotation_ = true;
  double period_s_ = 0.0005;

  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d body_angular_velocity_ = Eigen::Vector3d::Zero();
};

}  // namespace hapticd::models
