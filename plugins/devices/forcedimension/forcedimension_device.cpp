#include "forcedimension_device.hpp"

#include <cstdio>
#include <stdexcept>
#include <string_view>

namespace hapticd::plugins::forcedimension {
namespace {

// Nominal figures of each model from the vendor's product pages (translation workspace as a box around the
// centre, the largest force, torque and gripper force); the parameters may lower them. The recommended
// stiffness is the vendor's published closed-loop stiffness where one is given; the damping is the project's
// choice (a tenth of the stiffness's square root times the handle's mass scale - about critical for a 0.2 kg
// handle), to be lowered if a lab's unit buzzes.
struct ModelFigures {
  std::string_view name;
  bool orientation, torque, gripper;
  double half_x, half_yz;  // m
  double force_n, torque_nm, gripper_n;
  double stiffness, damping, rotational_stiffness, rotational_damping;
};
constexpr ModelFigures kModels[] = {
    {"omega.3", false, false, false, 0.055, 0.08, 12.0, 0.0, 0.0, 14500.0, 20.0, 0.0, 0.0},
    {"omega.6", true, false, false, 0.055, 0.08, 12.0, 0.0, 0.0, 14500.0, 20.0, 0.0, 0.0},
    {"omega.7", true, false, true, 0.055, 0.08, 12.0, 0.0, 8.0, 14500.0, 20.0, 0.0, 0.0},
    {"sigma.7", true, true, true, 0.065, 0.095, 20.0, 0.4, 8.0, 14500.0, 20.0, 2.0, 0.02},
    {"delta.3", false, false, false, 0.13, 0.2, 20.0, 0.0, 0.0, 14500.0, 30.0, 0.0, 0.0},
    {"delta.6", true, true, false, 0.13, 0.2, 20.0, 0.15, 0.0, 14500.0, 30.0, 1.0, 0.01},
    {"lambda.7", true, true, true, 0.065, 0.12, 20.0, 0.3, 8.0, 14500.0, 20.0, 2.0, 0.02},
};

const ModelFigures* figures_of(std::string_view system_name) {
  for (const ModelFigures& m : kModels)
    if (system_name.substr(0, m.name.size()) == m.name) return &m;
  return nullptr;
}

}  // namespace

ParameterSchema ForceDimensionDevice::parameter_schema() {
  ParameterSchema s;
  s.string("sdk_path", "the SDK's libdrd.so / libdhd.so, or its folder; empty: FORCEDIM_SDK, then the library path")
      .default_value("");
  s.integer("index", "the device's index among those connected (0: the first); used when serial is 0")
      .minimum(0)
      .maximum(15)
      .default_value(0);
  s.integer("serial", "open the device with this serial number (0: by index)").minimum(0).default_value(0);
  s.boolean("calibrate", "an uncalibrated device is calibrated by the robotic SDK (drdAutoInit; it moves!)")
      .default_value(false);
  s.string("gravity_compensation",
           "the device's own gravity compensation, or none (the server adds none on handle devices)")
      .choices({"device", "off"})
      .default_value("device");
  s.real("max_force_n", "the largest force to command; 0: the model's nominal")
      .unit("N")
      .minimum(0.0)
      .default_value(0.0);
  s.real("max_torque_nm", "the largest torque to command; 0: the model's nominal")
      .unit("N m")
      .minimum(0.0)
      .default_value(0.0);
  s.real("max_gripper_force_n", "the largest gripper force; 0: the model's nominal")
      .unit("N")
      .minimum(0.0)
      .default_value(0.0);
  return s;
}

ForceDimensionDevice::~ForceDimensionDevice() { close_device(); }

void ForceDimensionDevice::configure(const Parameters& p, const PluginContext&) {
  VendorLibrarySearch search;
  search.vendor = "Force Dimension SDK";
  search.names = {"libdrd.so.3", "libdrd.so", "libdhd.so.3", "libdhd.so"};
  search.path = p.string("sdk_path");
  search.environment = "FORCEDIM_SDK";
  search.subdirs = {"lib", "lib/release/lin-x86_64-gcc"};
  try {
    library_ = std::make_unique<VendorLibrary>(search);
    dhd_ = std::make_unique<DhdApi>(*library_);
  } catch (const VendorLibraryError& e) {
    throw DeviceUnavailable(e.what());
  }
  const long long serial = p.integer("serial");
  const int opened =
      serial > 0 ? dhd_->open_serial(static_cast<int>(serial)) : dhd_->open_id(static_cast<char>(p.integer("index")));
  if (opened < 0) {
    const std::string which =
        serial > 0 ? "serial number " + std::to_string(serial) : "index " + std::to_string(p.integer("index"));
    throw DeviceUnavailable("no Force Dimension device with " + which + " (" +
                            std::to_string(dhd_->get_device_count()) +
                            " connected): " + vendor_text(dhd_->last_error()));
  }
  id_ = static_cast<char>(opened);
  open_ = true;
  const std::string system = vendor_text(dhd_->get_system_name(id_));
  const ModelFigures* m = figures_of(system);
  if (m == nullptr) {
    close_device();
    throw std::runtime_error("Force Dimension device '" + system +
                             "' is not one this plugin knows (omega.3/6/7, sigma.7, delta.3/6, lambda.7)");
  }
  // Calibration: the robotic SDK knows whether the device has been; the haptic SDK alone cannot tell.
  if (dhd_->drd_is_initialized != nullptr && !dhd_->drd_is_initialized(id_)) {
    if (!p.boolean("calibrate")) {
      close_device();
      throw std::runtime_error("the " + system +
                               " is not calibrated (the SDK: device not ready); calibrate it with the vendor's "
                               "tool, or set calibrate: true to have the SDK calibrate it (the handle moves)");
    }
    if (dhd_->drd_open_id(id_) < 0 || dhd_->drd_auto_init(id_) < 0) {
      const std::string why = vendor_text(dhd_->last_error());
      close_device();
      throw std::runtime_error("the " + system + " could not be calibrated: " + why);
    }
    if (dhd_->drd_stop != nullptr) (void)dhd_->drd_stop(true, id_);
  }
  device_gravity_ = p.string("gravity_compensation") == "device";

  DeviceDescription& d = description_;
  d.model = "forcedimension " + system;
  d.interface = DeviceInterface::handle;
  HandleDescription& h = d.handle;
  h.senses_orientation = m->orientation;
  h.actuated_torque = m->torque;
  h.has_gripper = m->gripper && dhd_->has_gripper(id_);
  h.actuated_gripper = h.has_gripper;
  h.buttons = 1;
  h.workspace_min = Eigen::Vector3d(-m->half_x, -m->half_yz, -m->half_yz);
  h.workspace_max = -h.workspace_min;
  const auto lowered = [&](const char* key, double nominal) {
    const double asked = p.real(key);
    if (asked > nominal && nominal > 0.0)
      throw ParameterError(key, "above the " + system + "'s nominal " + std::to_string(nominal));
    return asked > 0.0 ? asked : nominal;
  };
  h.max_force_n = lowered("max_force_n", m->force_n);
  h.max_torque_nm = lowered("max_torque_nm", m->torque_nm);
  h.max_gripper_force_n = lowered("max_gripper_force_n", m->gripper_n);
  h.recommended_stiffness_n_per_m = m->stiffness;
  h.recommended_damping_n_s_per_m = m->damping;
  h.recommended_rotational_stiffness_nm_per_rad = m->rotational_stiffness;
  h.recommended_rotational_damping_nm_s_per_rad = m->rotational_damping;
  d.capabilities.brakes = true;
}

const char* ForceDimensionDevice::failure(const char* what) noexcept {
  std::array<char, 256>& text = errors_[static_cast<std::size_t>(error_)];
  if (text[0] == '\0') std::snprintf(text.data(), text.size(), "%s: %.200s", what, dhd_->last_error());
  return text.data();
}

Outcome ForceDimensionDevice::enable() {
  if (!open_) return Outcome::failure("the Force Dimension device is not open");
  errors_[static_cast<std::size_t>(error_)][0] = '\0';
  gripper_read_ = false;
  if (dhd_->set_gravity_compensation(device_gravity_ ? 1 : 0, id_) < 0)
    return Outcome::failure(failure("gravity compensation"));
  if (dhd_->enable_force(1, id_) < 0) return Outcome::failure(failure("enabling forces"));
  if (dhd_->set_brakes(0, id_) < 0) return Outcome::failure(failure("releasing the brakes"));
  return Outcome::success();
}

Outcome ForceDimensionDevice::read(const CycleTime& cycle, DeviceState& state) {
  HandleState& h = state.handle;
  state.timestamp_ns = cycle.time_ns;
  if (dhd_->get_position(&h.pose.position.x(), &h.pose.position.y(), &h.pose.position.z(), id_) < 0)
    return Outcome::failure(failure("reading the position"));
  if (dhd_->get_linear_velocity(&h.twist.linear.x(), &h.twist.linear.y(), &h.twist.linear.z(), id_) < 0)
    return Outcome::failure(failure("reading the velocity"));
  if (description_.handle.senses_orientation) {
    double r[3][3];
    if (dhd_->get_orientation_frame(r, id_) < 0) return Outcome::failure(failure("reading the orientation"));
    Eigen::Matrix3d m;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m(i, j) = r[i][j];
    h.pose.orientation = Eigen::Quaterniond(m);
    if (dhd_->get_angular_velocity_rad(&h.twist.angular.x(), &h.twist.angular.y(), &h.twist.angular.z(), id_) < 0)
      return Outcome::failure(failure("reading the angular velocity"));
  }
  h.buttons = dhd_->get_button_mask(id_);
  if (description_.handle.has_gripper) {
    const double before = h.gripper;
    if (dhd_->get_gripper_angle_rad(&h.gripper, id_) < 0) return Outcome::failure(failure("reading the gripper"));
    // The first sample has nothing to differentiate against: rate zero, not a jump from zero.
    h.gripper_rate = gripper_read_ && cycle.period_ns > 0
                         ? (h.gripper - before) / (static_cast<double>(cycle.period_ns) * 1e-9)
                         : 0.0;
    gripper_read_ = true;
  }
  return Outcome::success();
}

Outcome ForceDimensionDevice::write(const CycleTime&, const JointCommand& command) {
  const HandleDescription& h = description_.handle;
  const JointVector& e = command.torque_nm;
  if (e.size() != h.axes()) return Outcome::failure("the command does not match the device's axes");
  const double tx = h.actuated_torque ? e[3] : 0.0, ty = h.actuated_torque ? e[4] : 0.0,
               tz = h.actuated_torque ? e[5] : 0.0;
  const double grip = h.actuated_gripper ? e[e.size() - 1] : 0.0;
  const int r = dhd_->set_force_and_torque_and_gripper_force(e[0], e[1], e[2], tx, ty, tz, grip, id_);
  if (r < 0) return Outcome::failure(failure("writing the force"));
  return Outcome::success();  // r == kMotorSaturated: the device clamped it, within its own limits
}

Outcome ForceDimensionDevice::brake(bool on) {
  if (dhd_->set_brakes(on ? 1 : 0, id_) < 0) return Outcome::failure(failure(on ? "braking" : "releasing the brakes"));
  return Outcome::success();
}

Outcome ForceDimensionDevice::reset_fault() {
  // A recovery: the next failure says its own reason, in the other buffer.
  error_ = 1 - error_;
  errors_[static_cast<std::size_t>(error_)][0] = '\0';
  return Outcome::success();
}

void ForceDimensionDevice::disable() { close_device(); }

void ForceDimensionDevice::close_device() noexcept {
  if (!open_ || !dhd_) return;
  (void)dhd_->set_force_and_torque_and_gripper_force(0, 0, 0, 0, 0, 0, 0, id_);
  (void)dhd_->enable_force(0, id_);
  (void)dhd_->set_brakes(1, id_);
  (void)dhd_->close(id_);
  open_ = false;
}

}  // namespace hapticd::plugins::forcedimension
