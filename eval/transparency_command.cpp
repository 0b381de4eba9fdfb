#include "transparency_command.hpp"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <numbers>

#include "device_presets.hpp"
#include "eval_options.hpp"
#include "experiment/device_model.hpp"
#include "hapticd/model/friction_file.hpp"
#include "report/progress.hpp"

namespace hapticd::eval {
namespace {

struct Options {
  CommonOptions common;
  int points = 5;                 // grid points per axis
  double probe_speed_m_s = 0.05;  // the handle speed at which the friction is felt
  std::string friction_file;      // default: <config>/friction/<device>.yaml
};

struct PointIndices {
  Eigen::Vector3d position;
  Eigen::Vector3d mass;      // apparent mass along x, y, z: 1 / (d^T Lambda^-1 d)
  Eigen::Vector3d friction;  // friction force felt moving along x, y, z at the probe speed
  double condition = 0.0;    // of Lambda
  double angle_deg = 0.0;    // largest angle between an acceleration and its inertial force
};

PointIndices indices_at(DeviceModel& device, const Eigen::Vector3d& p, const model::FrictionFile* friction,
                        double speed) {
  PointIndices r;
  r.position = p;
  const std::vector<double> q = device.joints_at(p);
  const DeviceModel::Inertia in = device.inertia_at(q);
  const Eigen::Matrix3d lambda_inv = in.task_inertia.inverse();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(in.task_inertia);
  const double lo = eig.eigenvalues()(0), hi = eig.eigenvalues()(2);
  r.condition = hi / lo;
  // For a symmetric positive definite Lambda the angle between a and Lambda a is largest at
  // cos = 2 sqrt(l_min l_max) / (l_min + l_max).
  r.angle_deg = std::acos(2.0 * std::sqrt(lo * hi) / (lo + hi)) * 180.0 / std::numbers::pi;
  for (int a = 0; a < 3; ++a) {
    const Eigen::Vector3d d = Eigen::Vector3d::Unit(a);
    r.mass[a] = 1.0 / d.dot(lambda_inv * d);
    r.friction[a] = 0.0;
    if (friction == nullptr) continue;
    // Joint rates that move the handle along d (the least-norm ones), each joint's sliding friction at its rate
    // against it, mapped to the handle: F = J^+T tau; the part along d resists the motion. J (3 x n) has full
    // row rank at every reached pose (its condition is bounded), so J^+ = J^T (J J^T)^-1: a 3 x 3 solve.
    const Eigen::LDLT<Eigen::Matrix3d> jjt((in.jacobian * in.jacobian.transpose()).eval());
    const Eigen::VectorXd qd = in.jacobian.transpose() * jjt.solve(speed * d);
    Eigen::VectorXd tau(qd.size());
    for (Eigen::Index j = 0; j < qd.size(); ++j) {
      const auto& m = friction->joints[static_cast<std::size_t>(j)];
      tau[j] = std::copysign(m.sliding(std::abs(qd[j])), qd[j]);
    }
    const Eigen::Vector3d force = jjt.solve(in.jacobian * tau);
    r.friction[a] = force.dot(d);
  }
  return r;
}

Json vec(const Eigen::Vector3d& v) { return Json(std::vector<double>{v.x(), v.y(), v.z()}); }

int run(const Options& o) {
  DeviceModel device(o.common.device);
  const DevicePreset preset = device_preset(o.common.device);
  std::unique_ptr<model::FrictionFile> friction;
  std::string friction_path = o.friction_file;
  if (friction_path.empty()) {
    if (auto found = find_config_file(std::filesystem::path("friction") / (o.common.device + ".yaml")))
      friction_path = found->string();
  }
  if (!friction_path.empty())
    friction = std::make_unique<model::FrictionFile>(model::read_friction_file(friction_path));
  const int n = std::max(2, o.points);
  Progress progress("transparency", static_cast<std::size_t>(n * n * n));
  std::vector<PointIndices> points;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d f(i / (n - 1.0) - 0.5, j / (n - 1.0) - 0.5, k / (n - 1.0) - 0.5);
        const Eigen::Vector3d p = preset.workspace_center + preset.workspace_size.cwiseProduct(f);
        points.push_back(indices_at(device, p, friction.get(), o.probe_speed_m_s));
        progress.advance(fmt::format("({:.2f}, {:.2f}, {:.2f})", p.x(), p.y(), p.z()));
      }
    }
  }
  Eigen::Vector3d worst_mass = Eigen::Vector3d::Zero(), least_mass = Eigen::Vector3d::Constant(1e300),
                  worst_friction = Eigen::Vector3d::Zero();
  double worst_condition = 0.0, worst_angle = 0.0;
  Json map = Json::array();
  for (const PointIndices& p : points) {
    worst_mass = worst_mass.cwiseMax(p.mass);
    least_mass = least_mass.cwiseMin(p.mass);
    worst_friction = worst_friction.cwiseMax(p.friction);
    worst_condition = std::max(worst_condition, p.condition);
    worst_angle = std::max(worst_angle, p.angle_deg);
    map.push(Json::object()
                 .set("position_m", vec(p.position))
                 .set("mass_kg", vec(p.mass))
                 .set("friction_n", vec(p.friction))
                 .set("condition", p.condition)
                 .set("angle_deg", p.angle_deg));
  }
  fmt::print("open-loop {} over {} points of its workspace (model; friction from {})\n", o.common.device, points.size(),
             friction_path.empty() ? "nothing" : friction_path);
  fmt::print("apparent mass x/y/z: {:.2f} .. {:.2f} / {:.2f} .. {:.2f} / {:.2f} .. {:.2f} kg\n", least_mass.x(),
             worst_mass.x(), least_mass.y(), worst_mass.y(), least_mass.z(), worst_mass.z());
  fmt::print("friction felt at {:g} m/s, worst x/y/z: {:.2f} / {:.2f} / {:.2f} N\n", o.probe_speed_m_s,
             worst_friction.x(), worst_friction.y(), worst_friction.z());
  fmt::print(
      "condition number of the mass matrix: up to {:.2f}; largest angle between acceleration and inertial "
      "force: {:.1f} deg\n",
      worst_condition, worst_angle);
  fmt::print(
      "(PD force feedback with gain Kp divides the apparent mass and friction by 1 + Kp and keeps the "
      "condition number and angle; an admittance display with an ideal inner loop renders its virtual mass: "
      "condition 1, angle 0)\n");
  Json result = Json::object();
  result.set("experiment", "transparency")
      .set("title", "Transparency indices (Table 5.1) over the workspace, open loop")
      .set("device", o.common.device)
      .set("friction_file", friction_path)
      .set("probe_speed_m_s", o.probe_speed_m_s)
      .set("worst", Json::object()
                        .set("mass_kg", vec(worst_mass))
                        .set("least_mass_kg", vec(least_mass))
                        .set("friction_n", vec(worst_friction))
                        .set("condition", worst_condition)
                        .set("angle_deg", worst_angle))
      .set("points", map)
      .set("command", command_line());
  publish_result(o.common.report(), "transparency", result);
  return 0;
}

}  // namespace

void add_transparency_command(CLI::App& app, int& exit_code) {
  auto o = command_options<Options>();
  CLI::App* cmd = app.add_subcommand(
      "transparency",
      "Over the workspace grid: the handle's apparent inertia and friction per direction, the condition number of "
      "the mass matrix and the largest angle between acceleration and inertial force (Table 5.1; from the model)");
  add_common_options(cmd, o->common);
  cmd->add_option("--points", o->points, "grid points per axis")->check(CLI::Range(2, 21))->capture_default_str();
  cmd->add_option("--speed", o->probe_speed_m_s, "handle speed at which the friction is felt [m/s]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--friction-file", o->friction_file, "the joints' friction (default: config/friction/DEVICE.yaml)");
  cmd->callback([o, &exit_code] {
    Options run_options = *o;
    if (run_options.common.quick) run_options.points = 2;
    exit_code = run(run_options);
  });
}

}  // namespace hapticd::eval
