#include "hapticd/mujoco/coupled_world.hpp"

#include <mujoco/mujoco.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "hapticd/model/collision.hpp"
#include "hapticd/model/kinematics.hpp"
#include "hapticd/model/model_data.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::mujoco {

namespace {

constexpr double kPi = 3.14159265358979323846;
// When the device does not couple rotation, the proxy's orientation is held at the hand's by a spring-damper of
// this natural frequency (critically damped) at the proxy's own inertia: stiff enough that a peg stays upright,
// soft enough for the explicit step.
constexpr double kHoldFrequencyHz = 20.0;
// Faster than any hand moves a haptic device: a proxy this fast is a world going unstable.
constexpr double kMaxProxySpeed = 3.0;  // m/s

struct ModelDeleter {
  void operator()(mjModel* m) const noexcept { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const noexcept { mj_deleteData(d); }
};

struct ProxyBody {
  std::string device;
  std::string name;
  int body = -1;
  int qpos = 0;  // the free joint's addresses
  int dof = 0;
  double mass = 0.0;
  double inertia = 0.0;                                                  // the smallest principal inertia
  Eigen::Quaterniond rest_orientation = Eigen::Quaterniond::Identity();  // as the scene placed it
  CouplingGains gains;
  Eigen::Vector3d coupling_force = Eigen::Vector3d::Zero();
};

Eigen::Vector3d vec3(const mjtNum* v) { return {v[0], v[1], v[2]}; }
Eigen::Quaterniond quat(const mjtNum* q) { return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized(); }

std::string geom_type_name(int type) {
  switch (type) {
    case mjGEOM_PLANE:
      return "plane";
    case mjGEOM_SPHERE:
      return "sphere";
    case mjGEOM_CAPSULE:
      return "capsule";
    case mjGEOM_ELLIPSOID:
      return "ellipsoid";
    case mjGEOM_CYLINDER:
      return "cylinder";
    default:
      return "box";
  }
}

std::string fmt_error(const std::string& proxy, const char* what, double k, const char* unit_k, double b,
                      const char* unit_b, double m, double h, double wh, double bh) {
  char text[600];
  std::snprintf(text, sizeof text,
                "the proxy '%s' is too light for the coupling (%g %s, %g %s) at a physics step of %g ms: its %s %g "
                "gives sqrt(K/m) h = %.2f (at most 0.5) and B h / m = %.2f (at most 1); give it more mass or inertia "
                "(<inertial> in the MJCF), a smaller timestep, or lower the device's coupling gains",
                proxy.c_str(), k, unit_k, b, unit_b, 1e3 * h, what, m, wh, bh);
  return text;
}

}  // namespace

struct ArmBody {
  int body = -1;
  int mocap = -1;
  int geom = -1;
};

struct CoupledWorld::Impl {
  std::unique_ptr<mjModel, ModelDeleter> model;
  std::unique_ptr<mjData, DataDeleter> data;
  std::vector<ProxyBody> proxies;
  std::vector<std::vector<ArmBody>> arms;  // per device
  Eigen::Isometry3d to_world = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d to_scene = Eigen::Isometry3d::Identity();
  int substeps = 1;
  int bad_acceleration_count = 0;
  double work_j = 0.0;

  [[nodiscard]] Pose scene_pose(const ProxyBody& p) const {
    const mjtNum* q = data->qpos + p.qpos;
    return Pose{vec3(q), quat(q + 3)};
  }
  // The free joint's velocity: linear in the scene frame, angular in the body's frame (MuJoCo's convention).
  [[nodiscard]] Twist scene_twist(const ProxyBody& p, const Eigen::Quaterniond& orientation) const {
    const mjtNum* v = data->qvel + p.dof;
    return Twist{vec3(v), orientation * vec3(v + 3)};
  }

  // A proxy at a pose (scene frame), at rest.
  void put(const ProxyBody& p, const Pose& pose) noexcept {
    const Eigen::Quaterniond q = p.gains.rotational_stiffness_n_m_per_rad > 0.0 ? pose.orientation : p.rest_orientation;
    mjtNum* qpos = data->qpos + p.qpos;
    for (int k = 0; k < 3; ++k) qpos[k] = pose.position[k];
    qpos[3] = q.w();
    qpos[4] = q.x();
    qpos[5] = q.y();
    qpos[6] = q.z();
    std::fill_n(data->qvel + p.dof, 6, 0.0);
  }

  // The coupling and the weight compensation on one proxy for the coming substep (scene frame).
  void apply(ProxyBody& p, const Pose& hand, const Twist& hand_twist) noexcept {
    const Pose x = scene_pose(p);
    const Twist v = scene_twist(p, x.orientation);
    const CouplingGains& g = p.gains;
    const Eigen::Vector3d force =
        g.stiffness_n_per_m * (hand.position - x.position) + g.damping_n_s_per_m * (hand_twist.linear - v.linear);
    double kr = g.rotational_stiffness_n_m_per_rad, br = g.rotational_damping_n_m_s;
    Eigen::Quaterniond target = hand.orientation;
    Eigen::Vector3d target_rate = hand_twist.angular;
    if (kr <= 0.0) {  // the device does not couple rotation: the proxy keeps the orientation the scene gave it
      const double w = 2.0 * kPi * kHoldFrequencyHz;
      kr = p.inertia * w * w;
      br = 2.0 * p.inertia * w;
      target = p.rest_orientation;
      target_rate.setZero();
    }
    const Eigen::AngleAxisd error(target * x.orientation.conjugate());
    const Eigen::Vector3d torque = kr * error.angle() * error.axis() + br * (target_rate - v.angular);
    // MuJoCo applies xfrc_applied at the body's centre of mass; the coupling acts at the body's origin.
    const Eigen::Vector3d com_offset = x.orientation * vec3(model->body_ipos + 3 * p.body);
    const Eigen::Vector3d weight = -p.mass * vec3(model->opt.gravity);
    mjtNum* f = data->xfrc_applied + 6 * p.body;
    const Eigen::Vector3d total = force + weight;
    const Eigen::Vector3d moment = torque + (-com_offset).cross(force);
    for (int k = 0; k < 3; ++k) {
      f[k] = total[k];
      f[3 + k] = moment[k];
    }
    p.coupling_force = force;
    work_j += model->opt.timestep * force.dot(v.linear);
  }
};

CoupledWorld::CoupledWorld(const WorldOptions& options) : impl_(std::make_unique<Impl>()) {
  if (options.devices.empty()) throw SceneError("no device to couple");
  if (!(options.state_period_s > 0.0)) throw SceneError("the state period must be positive");
  std::array<char, 1000> error{};
  const std::string file = options.scene.string();
  impl_->model.reset(mj_loadXML(file.c_str(), nullptr, error.data(), static_cast<int>(error.size())));
  if (!impl_->model) throw SceneError(file + ": " + std::string(error.data()));
  mjModel* m = impl_->model.get();
  impl_->substeps = std::max(1, static_cast<int>(std::lround(options.state_period_s / m->opt.timestep)));
  m->opt.timestep = options.state_period_s / impl_->substeps;
  impl_->data.reset(mj_makeData(m));
  if (!impl_->data) throw SceneError(file + ": MuJoCo could not allocate its data");
  impl_->to_world = options.scene_to_world;
  impl_->to_scene = options.scene_to_world.inverse();

  for (const std::string& device : options.devices) {
    int body = mj_name2id(m, mjOBJ_BODY, ("proxy_" + device).c_str());
    if (body < 0 && options.devices.size() == 1) body = mj_name2id(m, mjOBJ_BODY, "proxy");
    if (body < 0) {
      throw SceneError(file + ": no proxy body for device '" + device + "' (a body named 'proxy_" + device + "'" +
                       (options.devices.size() == 1 ? " or 'proxy'" : "") + ")");
    }
    const char* name = mj_id2name(m, mjOBJ_BODY, body);
    if (m->body_jntnum[body] != 1 || m->jnt_type[m->body_jntadr[body]] != mjJNT_FREE) {
      throw SceneError(file + ": the proxy body '" + name + "' must have exactly one joint, a free joint");
    }
    for (int b = 0; b < m->nbody; ++b) {
      if (b != body && m->body_parentid[b] == body) {
        throw SceneError(file + ": the proxy body '" + std::string(name) +
                         "' must have no child bodies (put its geoms in the body itself)");
      }
    }
    ProxyBody p;
    p.device = device;
    p.body = body;
    p.qpos = m->jnt_qposadr[m->body_jntadr[body]];
    p.dof = m->jnt_dofadr[m->body_jntadr[body]];
    p.mass = m->body_mass[body];
    p.inertia = std::min({m->body_inertia[3 * body], m->body_inertia[3 * body + 1], m->body_inertia[3 * body + 2]});
    p.rest_orientation = quat(m->qpos0 + p.qpos + 3);
    if (!(p.mass > 0.0) || !(p.inertia > 0.0)) {
      throw SceneError(file + ": the proxy body '" + std::string(name) + "' has no mass or no inertia");
    }
    p.name = name;
    impl_->proxies.push_back(p);
    // The arm's bodies, if the scene shows the arm.
    std::vector<ArmBody> arm;
    for (int k = 0;; ++k) {
      int b = mj_name2id(m, mjOBJ_BODY, ("arm_" + device + "_" + std::to_string(k)).c_str());
      if (b < 0 && options.devices.size() == 1) b = mj_name2id(m, mjOBJ_BODY, ("arm_" + std::to_string(k)).c_str());
      if (b < 0) break;
      const std::string arm_name = mj_id2name(m, mjOBJ_BODY, b);
      if (m->body_mocapid[b] < 0 || m->body_geomnum[b] != 1 || m->geom_type[m->body_geomadr[b]] != mjGEOM_CAPSULE) {
        throw SceneError(file + ": the arm body '" + arm_name +
                         "' must be a mocap body (mocap=\"true\") with exactly one geom, a capsule");
      }
      arm.push_back(ArmBody{b, m->body_mocapid[b], m->body_geomadr[b]});
    }
    impl_->arms.push_back(std::move(arm));
  }
  // A device's arm ends at its handle, inside its proxy: the two must not touch, while both touch everything else
  // (collision bit 0, the scenes' default) and the other devices' proxies and arms. Device i has its own bit b_i:
  // its proxy's geoms and its arm's have contype b_i; the arm's conaffinity is bit 0, the proxy's bit 0 and every
  // other device's bit. Only in scenes that show an arm.
  const auto has_arm = [&] {
    for (const auto& a : impl_->arms)
      if (!a.empty()) return true;
    return false;
  };
  if (has_arm()) {
    if (impl_->proxies.size() > 30) throw SceneError(file + ": at most 30 devices in a scene that shows arms");
    int all = 0;
    for (std::size_t i = 0; i < impl_->proxies.size(); ++i) all |= 1 << (i + 1);
    for (std::size_t i = 0; i < impl_->proxies.size(); ++i) {
      const int bit = 1 << (i + 1);
      const int b = impl_->proxies[i].body;
      for (int g = m->body_geomadr[b]; g < m->body_geomadr[b] + m->body_geomnum[b]; ++g) {
        m->geom_contype[g] = bit;
        m->geom_conaffinity[g] = 1 | (all & ~bit);
      }
      for (const ArmBody& a : impl_->arms[i]) {
        m->geom_contype[a.geom] = bit;
        m->geom_conaffinity[a.geom] = 1;
      }
    }
  }
  mj_forward(m, impl_->data.get());
}

CoupledWorld::~CoupledWorld() = default;

std::size_t CoupledWorld::device_count() const noexcept { return impl_->proxies.size(); }
const std::string& CoupledWorld::device(std::size_t i) const { return impl_->proxies.at(i).device; }
int CoupledWorld::substeps() const noexcept { return impl_->substeps; }
double CoupledWorld::timestep_s() const noexcept { return impl_->model->opt.timestep; }
double CoupledWorld::time_s() const noexcept { return impl_->data->time; }
const Eigen::Isometry3d& CoupledWorld::scene_to_world() const noexcept { return impl_->to_world; }
double CoupledWorld::coupling_work_j() const noexcept { return impl_->work_j; }

void CoupledWorld::set_gains(std::size_t device, const CouplingGains& gains) {
  ProxyBody& p = impl_->proxies.at(device);
  // The coupling acts on the proxy explicitly, once per physics step: the step must resolve its frequency and its
  // damping at the proxy's mass and inertia (natural frequency times step below 0.5, damping times step over mass
  // below 1: well inside the explicit step's limits of 2).
  const double h = impl_->model->opt.timestep;
  const auto check = [&](double k, double b, double m, const char* what, const char* unit_k, const char* unit_b) {
    if (!(k >= 0.0) || !(b >= 0.0)) throw SceneError("the coupling's gains must not be negative");
    const double wh = std::sqrt(k / m) * h, bh = b * h / m;
    if (wh > 0.5 || bh > 1.0) {
      throw SceneError(fmt_error(p.name, what, k, unit_k, b, unit_b, m, h, wh, bh));
    }
  };
  check(gains.stiffness_n_per_m, gains.damping_n_s_per_m, p.mass, "mass", "N/m", "N s/m");
  check(gains.rotational_stiffness_n_m_per_rad, gains.rotational_damping_n_m_s, p.inertia, "smallest inertia",
        "N m/rad", "N m s");
  // The coupling acts at the body's origin: with the centre of mass away from it, it also turns the proxy (a
  // rotational spring of K d^2 on the inertia).
  const double d2 = vec3(impl_->model->body_ipos + 3 * p.body).squaredNorm();
  if (d2 > 0.0) {
    check(gains.stiffness_n_per_m * d2, gains.damping_n_s_per_m * d2, p.inertia,
          "smallest inertia (the coupling's lever: its centre of mass is off its origin)", "N m/rad", "N m s");
  }
  p.gains = gains;
}
const CouplingGains& CoupledWorld::gains(std::size_t device) const { return impl_->proxies.at(device).gains; }

void CoupledWorld::place(std::size_t device, const Hand& hand) {
  const Eigen::Matrix3d r = impl_->to_scene.linear();
  impl_->put(impl_->proxies.at(device),
             Pose{impl_->to_scene * hand.pose.position,
                  Eigen::Quaterniond(r * hand.pose.orientation.normalized().toRotationMatrix())});
  mj_forward(impl_->model.get(), impl_->data.get());
}

std::size_t CoupledWorld::arm_bodies(std::size_t device) const noexcept {
  return device < impl_->arms.size() ? impl_->arms[device].size() : 0;
}

void CoupledWorld::set_arm(std::size_t device, std::span<const ArmCapsule> capsules) noexcept {
  if (device >= impl_->arms.size()) return;
  mjModel* m = impl_->model.get();
  mjData* d = impl_->data.get();
  const std::vector<ArmBody>& arm = impl_->arms[device];
  for (std::size_t k = 0; k < arm.size(); ++k) {
    mjtNum* pos = d->mocap_pos + 3 * arm[k].mocap;
    mjtNum* quat = d->mocap_quat + 4 * arm[k].mocap;
    if (k >= capsules.size() || !(capsules[k].radius > 0.0)) {  // parked far below, out of every contact
      pos[0] = pos[1] = 0.0;
      pos[2] = -1000.0;
      continue;
    }
    const Eigen::Vector3d a = impl_->to_scene * capsules[k].a, b = impl_->to_scene * capsules[k].b;
    const Eigen::Vector3d centre = 0.5 * (a + b);
    const double half = 0.5 * (b - a).norm();
    const Eigen::Quaterniond q = half > 1e-9 ? Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), b - a)
                                             : Eigen::Quaterniond::Identity();
    for (int i = 0; i < 3; ++i) pos[i] = centre[i];
    quat[0] = q.w();
    quat[1] = q.x();
    quat[2] = q.y();
    quat[3] = q.z();
    m->geom_size[3 * arm[k].geom] = capsules[k].radius;
    m->geom_size[3 * arm[k].geom + 1] = half;
    m->geom_rbound[arm[k].geom] = half + capsules[k].radius;
  }
}

StepReport CoupledWorld::step(std::span<const Hand> hands, int periods) noexcept {
  Impl& w = *impl_;
  const std::size_t n = std::min(hands.size(), w.proxies.size());
  // The hands in the scene frame (at most a few devices: a fixed array, no allocation).
  constexpr std::size_t kMaxHands = 16;
  std::array<Hand, kMaxHands> local;
  const Eigen::Matrix3d r = w.to_scene.linear();
  for (std::size_t i = 0; i < n && i < kMaxHands; ++i) {
    local[i].pose.position = w.to_scene * hands[i].pose.position;
    local[i].pose.orientation = Eigen::Quaterniond(r * hands[i].pose.orientation.normalized().toRotationMatrix());
    local[i].twist.linear = r * hands[i].twist.linear;
    local[i].twist.angular = r * hands[i].twist.angular;
  }
  StepReport report;
  for (int s = 0; s < periods * w.substeps; ++s) {
    for (std::size_t i = 0; i < n && i < kMaxHands; ++i) w.apply(w.proxies[i], local[i].pose, local[i].twist);
    mj_step(w.model.get(), w.data.get());
    const int bad = w.data->warning[mjWARN_BADQACC].number;
    bool runaway = false;
    for (std::size_t i = 0; i < n && i < kMaxHands; ++i) {
      runaway = runaway || !(vec3(w.data->qvel + w.proxies[i].dof).norm() <= kMaxProxySpeed);
    }
    if (bad != w.bad_acceleration_count || runaway) {
      // MuJoCo reset the world to its initial state (the proxies would jump to where the scene put them and the
      // coupling would pull the hands there), or a proxy runs away. Put them back at the hands, at rest, and say so.
      w.bad_acceleration_count = bad;
      report.stable = false;
      for (std::size_t i = 0; i < n && i < kMaxHands; ++i) w.put(w.proxies[i], local[i].pose);
      mj_forward(w.model.get(), w.data.get());
      break;
    }
  }
  return report;
}

Proxy CoupledWorld::proxy(std::size_t device) const noexcept {
  const Impl& w = *impl_;
  const ProxyBody& p = w.proxies[device];
  const Pose x = w.scene_pose(p);
  const Twist v = w.scene_twist(p, x.orientation);
  const Eigen::Matrix3d r = w.to_world.linear();
  Proxy out;
  out.pose.position = w.to_world * x.position;
  out.pose.orientation = Eigen::Quaterniond(r * x.orientation.toRotationMatrix());
  out.twist.linear = r * v.linear;
  out.twist.angular = r * v.angular;
  out.coupling_force = r * p.coupling_force;
  // The contacts' forces on the proxy: MuJoCo gives each in its contact frame (normal from geom1 to geom2), as
  // the force on geom2.
  const mjModel* m = w.model.get();
  const mjData* d = w.data.get();
  Eigen::Vector3d contact = Eigen::Vector3d::Zero();
  for (int c = 0; c < d->ncon; ++c) {
    const mjContact& k = d->contact[c];
    const bool first = m->geom_bodyid[k.geom1] == p.body, second = m->geom_bodyid[k.geom2] == p.body;
    if (first == second) continue;
    mjtNum f[6];
    mj_contactForce(m, d, c, f);
    Eigen::Vector3d world = Eigen::Vector3d::Zero();
    for (int a = 0; a < 3; ++a) world += f[a] * Eigen::Vector3d(k.frame[3 * a], k.frame[3 * a + 1], k.frame[3 * a + 2]);
    contact += second ? world : -world;
  }
  out.contact_force = r * contact;
  return out;
}

std::optional<Pose> CoupledWorld::body_pose(std::string_view body) const {
  const int id = mj_name2id(impl_->model.get(), mjOBJ_BODY, std::string(body).c_str());
  if (id < 0) return std::nullopt;
  const mjData* d = impl_->data.get();
  const Eigen::Matrix3d r = impl_->to_world.linear();
  return Pose{impl_->to_world * vec3(d->xpos + 3 * id),
              Eigen::Quaterniond(r * quat(d->xquat + 4 * id).toRotationMatrix())};
}

std::optional<Twist> CoupledWorld::body_twist(std::string_view body) const {
  const int id = mj_name2id(impl_->model.get(), mjOBJ_BODY, std::string(body).c_str());
  if (id < 0) return std::nullopt;
  mjtNum v[6];
  mj_objectVelocity(impl_->model.get(), impl_->data.get(), mjOBJ_BODY, id, v, 0);
  const Eigen::Matrix3d r = impl_->to_world.linear();
  return Twist{r * vec3(v + 3), r * vec3(v)};
}

std::vector<BodyShape> CoupledWorld::shapes() const {
  const mjModel* m = impl_->model.get();
  const mjData* d = impl_->data.get();
  const Eigen::Matrix3d r = impl_->to_world.linear();
  std::vector<BodyShape> out;
  out.reserve(static_cast<std::size_t>(m->ngeom));
  for (int g = 0; g < m->ngeom; ++g) {
    BodyShape s;
    const char* body = mj_id2name(m, mjOBJ_BODY, m->geom_bodyid[g]);
    s.body = body != nullptr ? body : "world";
    s.type = geom_type_name(m->geom_type[g]);
    s.size = vec3(m->geom_size + 3 * g);
    s.rgba =
        Eigen::Vector4f(m->geom_rgba[4 * g], m->geom_rgba[4 * g + 1], m->geom_rgba[4 * g + 2], m->geom_rgba[4 * g + 3]);
    Eigen::Matrix3d rotation;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) rotation(a, b) = d->geom_xmat[9 * g + 3 * a + b];
    }
    s.pose.position = impl_->to_world * vec3(d->geom_xpos + 3 * g);
    s.pose.orientation = Eigen::Quaterniond(r * rotation);
    out.push_back(std::move(s));
  }
  return out;
}

struct ArmModel::Impl {
  model::RobotModel robot;
  model::ModelData data;
  Eigen::Isometry3d base;
  JointVector q;
  model::PlacedCapsules placed;
  std::array<ArmCapsule, model::PlacedCapsules::kMax> capsules;

  Impl(model::RobotModel r, const Pose& base_pose)
      : robot(std::move(r)), data(robot), base(to_isometry(base_pose)), q(JointVector::Zero(robot.dof())) {}
};

namespace {
model::RobotModel arm_robot(const std::filesystem::path& urdf, double radius) {
  model::RobotModel m = model::load_robot_model(urdf);
  if (m.collision().empty()) m = m.with_collision(model::skeleton_capsules(m, radius));
  return m;
}
}  // namespace

ArmModel::ArmModel(const std::filesystem::path& urdf, double radius, const Pose& base)
    : impl_(std::make_unique<Impl>(arm_robot(urdf, radius), base)) {}
ArmModel::~ArmModel() = default;
ArmModel::ArmModel(ArmModel&&) noexcept = default;
ArmModel& ArmModel::operator=(ArmModel&&) noexcept = default;
int ArmModel::dof() const noexcept { return impl_->robot.dof(); }

std::span<const ArmCapsule> ArmModel::place(std::span<const double> q) noexcept {
  Impl& a = *impl_;
  for (int i = 0; i < a.robot.dof() && i < static_cast<int>(q.size()); ++i) a.q[i] = q[static_cast<std::size_t>(i)];
  model::forward_kinematics(a.robot, a.data, a.q, model::BodyInertias::skip);
  model::place_capsules(a.robot, a.data, a.placed);
  for (int k = 0; k < a.placed.count; ++k) {
    a.capsules[static_cast<std::size_t>(k)] =
        ArmCapsule{a.base * a.placed.a[k], a.base * a.placed.b[k], a.placed.radius[k]};
  }
  return {a.capsules.data(), static_cast<std::size_t>(a.placed.count)};
}

Eigen::Isometry3d scene_frame(std::span<const Eigen::Vector3d> start_positions) {
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  if (start_positions.empty()) return frame;
  Eigen::Vector3d middle = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : start_positions) middle += p;
  frame.translation() = middle / static_cast<double>(start_positions.size());
  if (start_positions.size() > 1) {
    Eigen::Vector3d x = start_positions.back() - start_positions.front();
    x.z() = 0.0;
    if (x.norm() > 1e-9) {
      x.normalize();
      frame.linear().col(0) = x;
      frame.linear().col(1) = Eigen::Vector3d::UnitZ().cross(x);
      frame.linear().col(2) = Eigen::Vector3d::UnitZ();
    }
  }
  return frame;
}

}  // namespace hapticd::mujoco
