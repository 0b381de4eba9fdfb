#include "stability_trial.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "device_presets.hpp"
#include "stability.hpp"

namespace hapticd::eval {
namespace {

constexpr double kRate = 2000.0;

std::string vector3(const Eigen::Vector3d& v) {
  return fmt::format("[{:.17g}, {:.17g}, {:.17g}]", v.x(), v.y(), v.z());
}

std::vector<std::string> wall_lines(const Eigen::Vector3d& direction, const WallSpec& wall, double ahead_m = 0.01) {
  const Eigen::Vector3d point = ahead_m * direction;  // relative to the handle at activation
  const Eigen::Vector3d normal = -direction;          // the free side is behind
  return {fmt::format("walls: [{:.17g}, {:.17g}, {:.17g}, {:.17g}, {:.17g}, {:.17g}]", point.x(), point.y(), point.z(),
                      normal.x(), normal.y(), normal.z()),
          "walls_relative: true", fmt::format("wall_stiffness_n_per_m: {:.17g}", wall.stiffness_n_per_m),
          fmt::format("wall_damping_n_s_per_m: {:.17g}", wall.damping_n_s_per_m)};
}

}  // namespace

OperatorLoad wall_collision(const Eigen::Vector3d& direction, double grasp, const WallSpec& wall) {
  return {fmt::format("wall-collision-grasp{:g}", grasp),
          fmt::format("collision with a {:g} N/m wall, grasp {:g}", wall.stiffness_n_per_m, grasp),
          {"attachment: operator", fmt::format("operator_grasp: {:g}", grasp), "operator_motion: step",
           "operator_motion_m: " + vector3(0.06 * direction), "operator_motion_start_s: 0.2"},
          wall_lines(direction, wall),
          true};
}

std::vector<OperatorLoad> standard_loads(const Eigen::Vector3d& direction, const WallSpec& wall) {
  std::vector<OperatorLoad> loads;
  loads.push_back({"firm-grasp",
                   "firm grasp, 5 N push",
                   {"attachment: operator", "operator_grasp: 1", "operator_force: step",
                    "operator_force_n: " + vector3(5.0 * direction), "operator_force_start_s: 0.2"},
                   {}});
  loads.push_back({"loose-grasp",
                   "loose grasp, 5 N push",
                   {"attachment: operator", "operator_grasp: 0", "operator_force: step",
                    "operator_force_n: " + vector3(5.0 * direction), "operator_force_start_s: 0.2"},
                   {}});
  loads.push_back({"voluntary-motion",
                   "voluntary motion, 4 cm at 0.5 Hz",
                   {"attachment: operator", "operator_grasp: 0.5", "operator_motion: sine",
                    "operator_motion_m: " + vector3(0.04 * direction), "operator_motion_frequency_hz: 0.5"},
                   {}});
  OperatorLoad collision = wall_collision(direction, 0.0, wall);
  collision.id = "wall-collision";
  loads.push_back(collision);
  return loads;
}

std::vector<OperatorLoad> rotational_loads(const Eigen::Vector3d& axis) {
  std::vector<OperatorLoad> loads;
  loads.push_back({"firm-grasp",
                   "firm grasp, 0.2 N m twist",
                   {"attachment: operator", "operator_grasp: 1", "operator_torque: step",
                    "operator_torque_nm: " + vector3(0.2 * axis), "operator_torque_start_s: 0.2"},
                   {}});
  loads.push_back({"loose-grasp",
                   "loose grasp, 0.2 N m twist",
                   {"attachment: operator", "operator_grasp: 0", "operator_torque: step",
                    "operator_torque_nm: " + vector3(0.2 * axis), "operator_torque_start_s: 0.2"},
                   {}});
  loads.push_back({"voluntary-motion",
                   "voluntary motion, 0.1 rad at 0.5 Hz",
                   {"attachment: operator", "operator_grasp: 0.5", "operator_rotation: sine",
                    "operator_rotation_rad: " + vector3(0.1 * axis), "operator_rotation_frequency_hz: 0.5"},
                   {}});
  return loads;
}

std::vector<OperatorLoad> selected_loads(const std::vector<OperatorLoad>& loads, const std::vector<std::string>& ids) {
  std::vector<OperatorLoad> out;
  for (const OperatorLoad& load : loads)
    if (std::find(ids.begin(), ids.end(), load.id) != ids.end()) out.push_back(load);
  return out;
}

Json loads_json(const std::vector<OperatorLoad>& loads) {
  Json list = Json::array();
  for (const OperatorLoad& load : loads) list.push(Json::object().set("id", load.id).set("label", load.label));
  return list;
}

Json criterion_json(const StabilityCriterion& c) {
  return Json::object()
      .set("duration_s", c.duration_s)
      .set("window_s", c.window_s)
      .set("cutoff_hz", c.cutoff_hz)
      .set("threshold_m_s", c.threshold_m_s)
      .set("rotational_threshold_rad_s", c.rotational_threshold_rad_s)
      .set("collision_tolerance_j", c.collision_tolerance_j);
}

RigSpec with_load(RigSpec spec, const OperatorLoad& load) {
  spec.attachment.insert(spec.attachment.end(), load.attachment.begin(), load.attachment.end());
  spec.model.insert(spec.model.end(), load.model.begin(), load.model.end());
  return spec;
}

TrialResult run_trial(const RigSpec& spec, const OperatorLoad& load, const StabilityCriterion& criterion) {
  server::Session session = make_rig_session(with_load(spec, load));
  const auto cycles = static_cast<std::uint64_t>(std::llround(criterion.duration_s * kRate));
  const bool rotations = device_preset(spec.device.name).task != model::TaskRows::translation;
  std::vector<std::vector<double>> velocity(6);  // linear x, y, z; angular x, y, z
  for (auto& v : velocity) v.reserve(cycles);
  TrialResult r;
  double work = 0.0;
  r.fault = run_rig(session, cycles, [&](const RigSample& s) {
    for (int i = 0; i < 3; ++i) {
      velocity[static_cast<std::size_t>(i)].push_back(s.true_velocity[i]);
      velocity[static_cast<std::size_t>(i) + 3].push_back(s.true_angular_velocity[i]);
    }
    work += s.true_force.dot(s.true_velocity) / kRate;
    r.least_operator_work_j = std::min(r.least_operator_work_j, work);
  });
  if (!r.fault.empty() || velocity[0].size() < cycles) return r;
  // Each axis's oscillation relative to its threshold; the frequency is the largest one's.
  double linear = 0.0, angular = 0.0, largest = -1.0;
  for (std::size_t i = 0; i < (rotations ? 6U : 3U); ++i) {
    const Oscillation o = oscillation(velocity[i], kRate, criterion.cutoff_hz, criterion.window_s);
    const double threshold = i < 3 ? criterion.threshold_m_s : criterion.rotational_threshold_rad_s;
    (i < 3 ? linear : angular) += o.rms * o.rms;
    if (o.rms / threshold > largest) {
      largest = o.rms / threshold;
      r.oscillation_hz = o.frequency_hz;
    }
  }
  r.oscillation_m_s = std::sqrt(linear);
  r.oscillation_rad_s = std::sqrt(angular);
  r.stable = load.collision ? r.least_operator_work_j >= -criterion.collision_tolerance_j
                            : r.oscillation_m_s < criterion.threshold_m_s &&
                                  r.oscillation_rad_s < criterion.rotational_threshold_rad_s;
  return r;
}

PassivityResult port_energy(RigSpec spec, const Eigen::Vector3d& direction, const WallSpec& wall, double frequency_hz) {
  spec.attachment.insert(spec.attachment.end(), {"attachment: operator", "operator_grasp: 1", "operator_force: sine",
                                                 "operator_force_n: " + vector3(10.0 * direction),
                                                 fmt::format("operator_force_frequency_hz: {:.17g}", frequency_hz)});
  const std::vector<std::string> walls = wall_lines(direction, wall, 0.0);
  spec.model.insert(spec.model.end(), walls.begin(), walls.end());
  server::Session session = make_rig_session(spec);
  const double period = 1.0 / frequency_hz;
  const double settle = std::ceil(std::max(0.3, 2.0 * period) / period) * period;
  const double periods = std::max(4.0, std::ceil(0.5 / period));
  const auto settle_cycles = static_cast<std::uint64_t>(std::llround(settle * kRate));
  const auto cycles = settle_cycles + static_cast<std::uint64_t>(std::llround(periods * period * kRate));
  PassivityResult r;
  double energy = 0.0;
  std::uint64_t k = 0;
  r.fault = run_rig(session, cycles, [&](const RigSample& s) {
    if (k++ >= settle_cycles) energy += s.true_force.dot(s.true_velocity) / kRate;
  });
  r.energy_per_period_j = energy / periods;
  return r;
}

}  // namespace hapticd::eval
