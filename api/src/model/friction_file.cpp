#include "hapticd/model/friction_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <iomanip>

#include "hapticd/input_file.hpp"
#include "hapticd/model/urdf_loader.hpp"

namespace hapticd::model {

namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const YAML::Node& node, const std::string& key,
                       const std::string& what) {
  const int line = node.IsDefined() ? node.Mark().line + 1 : 0;
  throw ModelError(file.string() + ":" + std::to_string(line) + ": " + key + ": " + what);
}

double number(const std::filesystem::path& file, const YAML::Node& node, const std::string& key) {
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v)) fail(file, node, key, "must be finite");
    return v;
  } catch (const YAML::Exception&) {
    fail(file, node, key, "must be a number");
  }
}

template <std::size_t N>
void numbers(const std::filesystem::path& file, const YAML::Node& node, const std::string& key, double* out) {
  if (!node.IsSequence() || node.size() != N)
    fail(file, node, key, "must be a list of " + std::to_string(N) + " numbers");
  for (std::size_t i = 0; i < N; ++i) out[i] = number(file, node[i], key + "[" + std::to_string(i) + "]");
}

}  // namespace

FrictionFile read_friction_file(const std::filesystem::path& file) {
  std::string text;
  try {
    text = read_input_file(file, "friction file");
  } catch (const std::runtime_error& e) {
    throw ModelError(e.what());
  }
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw ModelError(file.string() + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  FrictionFile f;
  if (!root.IsMap()) fail(file, root, "(top)", "must be a map with 'device' and 'joints'");
  if (root["device"]) f.device = root["device"].as<std::string>();
  const YAML::Node joints = root["joints"];
  if (!joints || !joints.IsSequence() || joints.size() == 0) fail(file, root, "joints", "must be a non-empty list");
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const YAML::Node j = joints[i];
    const std::string key = "joints[" + std::to_string(i) + "]";
    if (!j.IsMap()) fail(file, j, key, "must be a map");
    for (const auto& entry : j) {
      const std::string k = entry.first.as<std::string>();
      if (k != "name" && k != "coulomb" && k != "viscous" && k != "load" && k != "velocity_max" && k != "breakaway")
        fail(file, entry.first, key + "." + k,
             "unknown key (known: name, coulomb, viscous, load, velocity_max, breakaway)");
    }
    FrictionModel m;
    if (!j["coulomb"]) fail(file, j, key + ".coulomb", "missing");
    m.p[0] = number(file, j["coulomb"], key + ".coulomb");
    if (!j["viscous"]) fail(file, j, key + ".viscous", "missing");
    numbers<4>(file, j["viscous"], key + ".viscous", m.p.data() + 1);
    if (j["load"]) numbers<3>(file, j["load"], key + ".load", m.load.data());
    if (j["velocity_max"]) {
      m.velocity_max = number(file, j["velocity_max"], key + ".velocity_max");
      if (!(m.velocity_max > 0.0)) fail(file, j["velocity_max"], key + ".velocity_max", "must be > 0");
    }
    if (j["breakaway"]) m.breakaway_nm = number(file, j["breakaway"], key + ".breakaway");
    f.joint_names.push_back(j["name"] ? j["name"].as<std::string>() : "joint" + std::to_string(i + 1));
    f.joints.push_back(m);
  }
  return f;
}

void write_friction_file(const std::filesystem::path& file, const FrictionFile& f) {
  std::ofstream out(file);
  if (!out) throw ModelError(file.string() + ": cannot write the friction file");
  out << std::setprecision(6);
  out << "# Joint friction of " << (f.device.empty() ? "a device" : f.device)
      << ": sliding f = coulomb + viscous[0]|v| + .. + viscous[3]|v|^4 (held beyond velocity_max),\n"
         "# load part a0 + a1|t| + a2 t^2 with load = [a0, a1, a2] [N m, rad/s]. Loaded by the controllers'\n"
         "# friction_file (impedance, and admittance display's inner loops).\n";
  out << "device: " << (f.device.empty() ? "unknown" : f.device) << "\njoints:\n";
  for (std::size_t i = 0; i < f.joints.size(); ++i) {
    const FrictionModel& m = f.joints[i];
    const std::string name = i < f.joint_names.size() ? f.joint_names[i] : "joint" + std::to_string(i + 1);
    out << "  - {name: " << name << ", coulomb: " << m.p[0] << ", viscous: [" << m.p[1] << ", " << m.p[2] << ", "
        << m.p[3] << ", " << m.p[4] << "], load: [" << m.load[0] << ", " << m.load[1] << ", " << m.load[2]
        << "], velocity_max: " << m.velocity_max << ", breakaway: " << m.breakaway_nm << "}\n";
  }
  if (!out) throw ModelError(file.string() + ": writing failed");
}

}  // namespace hapticd::model
