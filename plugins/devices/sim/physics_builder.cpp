#include "physics_builder.hpp"

#include <cmath>
#include <random>
#include <stdexcept>

namespace hapticd::sim {

namespace {
constexpr double kReferenceGearAverageTorque = 39.0;  // HFUC-2UH-17 [N m]
}  // namespace

FlexibleChain build_flexible_chain(const model::RobotModel& model, int handle_frame, const PhysicsOptions& options,
                                   std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform;
  std::vector<model::Body> bodies = model.bodies();
  std::vector<JointPhysics> joints;
  for (model::Body& b : bodies) {
    if (!b.drive.present) {
      throw std::invalid_argument("joint '" + b.joint_name + "' of " + model.source_file() +
                                  " has no <hapticd_drive>: the simulation needs its drive data");
    }
    const model::DriveData& d = b.drive;
    JointPhysics j;
    j.motor_inertia = b.reflected_inertia;
    j.gear_ratio = d.gear_ratio;
    // A compliant structure in series with the gear: no mass between them, so the two springs act as one whose
    // stiffness at each load is the series combination k k_s / (k + k_s). The gear's stiffness rises with its
    // deflection; the combination keeps that shape between the combined end values, reaching the upper one at
    // the rated torque (a close approximation of the exact series curve, with the right end points).
    const double ks = options.structural_compliance ? d.structural_stiffness : 0.0;
    const auto series = [ks](double k) { return ks > 0.0 ? k * ks / (k + ks) : k; };
    j.spring.k_min = series(d.stiffness_min);
    j.spring.k_max = series(d.stiffness_max);
    j.spring.rated_deflection = std::max(1e-6, d.gear_average_torque / j.spring.k_max);
    const double zeta = options.damping_ratio >= 0.0 ? options.damping_ratio
                        : d.damping_ratio >= 0.0     ? d.damping_ratio
                                                     : PhysicsOptions::kDefaultDampingRatio;
    j.damping = 2.0 * zeta * std::sqrt(j.spring.k_min * j.motor_inertia);
    j.friction = options.friction_template;
    if (!options.friction) {
      j.friction.sliding = j.friction.load_dependent = j.friction.stiction = false;
    }
    j.friction.scale = std::max(0.2, 1.0 + options.friction_variation * normal(rng));
    // The friction and ripple data were measured on ViSHaRD3's HFUC-17 gears (rated average torque 39 N m):
    // other sizes scale with their rated torque (ViSHaRD6's HFUC-25 base x2.8, its HFUC-8 wrist x0.085).
    const double size = d.gear_average_torque > 0.0 ? d.gear_average_torque / kReferenceGearAverageTorque : 1.0;
    j.friction.size = size;
    j.ripple_amplitude =
        options.ripple ? size * (options.ripple_min_nm + (options.ripple_max_nm - options.ripple_min_nm) * uniform(rng))
                       : 0.0;
    j.ripple_phase = 2.0 * M_PI * uniform(rng);
    joints.push_back(j);
    b.reflected_inertia = 0.0;  // the motor is its own coordinate here
  }
  model::RobotModel links(model.name(), model.source_file(), std::move(bodies), model.frames(), model.gravity());
  return FlexibleChain(std::move(links), std::move(joints), handle_frame, seed);
}

}  // namespace hapticd::sim
