#include "hapticd/model/urdf_loader.hpp"

#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "hapticd/input_file.hpp"

namespace hapticd::model {
namespace {

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  const Eigen::Quaterniond rotation(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z);
  t.linear() = rotation.normalized().toRotationMatrix();
  t.translation() = Eigen::Vector3d(pose.position.x, pose.position.y, pose.position.z);
  return t;
}

struct MassProperties {
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about com
};

// Inertial of a link expressed in a frame whose pose relative to the link is `link_in_frame`.
MassProperties link_mass_properties(const urdf::Link& link, const Eigen::Isometry3d& link_in_frame) {
  MassProperties p;
  if (!link.inertial) return p;
  const urdf::Inertial& in = *link.inertial;
  Eigen::Matrix3d i_com;
  i_com << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  const Eigen::Isometry3d com_frame = link_in_frame * to_isometry(in.origin);
  p.mass = in.mass;
  p.com = com_frame.translation();
  p.inertia = com_frame.linear() * i_com * com_frame.linear().transpose();
  return p;
}

MassProperties combine(const MassProperties& a, const MassProperties& b) {
  MassProperties c;
  c.mass = a.mass + b.mass;
  if (c.mass <= 0.0) return c;
  c.com = (a.mass * a.com + b.mass * b.com) / c.mass;
  auto shifted = [&](const MassProperties& p) {
    const Eigen::Vector3d d = p.com - c.com;
    return Eigen::Matrix3d(p.inertia + p.mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
  };
  c.inertia = shifted(a) + shifted(b);
  return c;
}

class ChainBuilder {
 public:
  explicit ChainBuilder(std::string source) : source_(std::move(source)) {}

  // Adds the link's frame and those below it; returns the mass the link carries rigidly (itself and its fixed
  // subtree), in the body's frame.
  MassProperties walk(const urdf::Link& link, int body, const Eigen::Isometry3d& link_in_body) {
    const std::size_t frame = frames_.size();
    frames_.push_back({link.name, body, link_in_body});
    MassProperties carried = link_mass_properties(link, link_in_body);
    for (const auto& collision : link.collision_array)
      if (collision && collision->geometry)
        add_capsule(link.name, body, link_in_body * to_isometry(collision->origin), *collision->geometry);
    for (const auto& joint_ptr : link.child_joints) {
      const urdf::Joint& joint = *joint_ptr;
      const urdf::LinkConstSharedPtr child = find_link(joint.child_link_name);
      const Eigen::Isometry3d joint_in_body = link_in_body * to_isometry(joint.parent_to_joint_origin_transform);
      if (joint.type == urdf::Joint::FIXED) {
        if (body >= 0) {
          Body& b = bodies_[static_cast<std::size_t>(body)];
          const MassProperties merged =
              combine({b.mass, b.com, b.inertia}, link_mass_properties(*child, joint_in_body));
          b.mass = merged.mass;
          b.com = merged.com;
          b.inertia = merged.inertia;
        }
        carried = combine(carried, walk(*child, body, joint_in_body));
        continue;
      }
      if (joint.type != urdf::Joint::REVOLUTE && joint.type != urdf::Joint::CONTINUOUS &&
          joint.type != urdf::Joint::PRISMATIC) {
        fail("joint '" + joint.name + "': type not supported (revolute, continuous, prismatic and fixed are)");
      }
      if (!has_child_.insert(body).second) {
        fail("the chain branches below link '" + link.name + "' (joint '" + joint.name +
             "' is a second movable child): only serial chains are supported");
      }
      if (static_cast<int>(bodies_.size()) == kMaxJoints) {
        fail("more than " + std::to_string(kMaxJoints) + " movable joints");
      }
      Body b;
      b.joint_name = joint.name;
      b.link_name = child->name;
      b.type = joint.type == urdf::Joint::PRISMATIC ? JointType::prismatic : JointType::revolute;
      b.placement = joint_in_body;
      b.axis = Eigen::Vector3d(joint.axis.x, joint.axis.y, joint.axis.z);
      if (b.axis.norm() < 1e-9) fail("joint '" + joint.name + "': zero axis");
      b.axis.normalize();
      if (joint.limits) {
        b.velocity_limit = joint.limits->velocity;
        b.effort_limit = joint.limits->effort;
        if (joint.type != urdf::Joint::CONTINUOUS) {
          b.position_min = joint.limits->lower;
          b.position_max = joint.limits->upper;
        }
      }
      const MassProperties own = link_mass_properties(*child, Eigen::Isometry3d::Identity());
      b.mass = own.mass;
      b.com = own.com;
      b.inertia = own.inertia;
      bodies_.push_back(std::move(b));
      walk(*child, static_cast<int>(bodies_.size()) - 1, Eigen::Isometry3d::Identity());
    }
    frames_[frame].carried_mass = carried.mass;
    frames_[frame].carried_com = link_in_body.inverse() * carried.com;
    return carried;
  }

  // A <collision> shape as the capsule that covers it, along its local z (a cylinder), its longest side (a box),
  // or of zero length (a sphere). Meshes are refused: give the link capsules in the session file instead.
  void add_capsule(const std::string& link, int body, const Eigen::Isometry3d& at, const urdf::Geometry& geometry) {
    Capsule c;
    c.link = link;
    c.body = body;
    Eigen::Vector3d half = Eigen::Vector3d::Zero();
    switch (geometry.type) {
      case urdf::Geometry::SPHERE:
        c.radius = static_cast<const urdf::Sphere&>(geometry).radius;
        break;
      case urdf::Geometry::CYLINDER: {
        const auto& cylinder = static_cast<const urdf::Cylinder&>(geometry);
        c.radius = cylinder.radius;
        half = Eigen::Vector3d(0.0, 0.0, cylinder.length / 2);
        break;
      }
      case urdf::Geometry::BOX: {
        const auto& box = static_cast<const urdf::Box&>(geometry);
        Eigen::Vector3d size(box.dim.x, box.dim.y, box.dim.z);
        Eigen::Index longest = 0;
        size.maxCoeff(&longest);
        half[longest] = size[longest] / 2;
        size[longest] = 0.0;
        c.radius = size.norm() / 2;  // the box's cross-section's half diagonal
        break;
      }
      default:
        fail("link '" + link + "': a <collision> mesh is not supported (cylinders, spheres and boxes are; or give " +
             "the link's capsules in the session file)");
    }
    c.a = at * (-half);
    c.b = at * half;
    if (!(c.radius >= 0.0) || !c.a.allFinite() || !c.b.allFinite())
      fail("link '" + link + "': a <collision> shape with a negative or non-finite size");
    capsules_.push_back(std::move(c));
  }

  void set_model(const urdf::ModelInterface* m) { model_ = m; }
  std::vector<Capsule>& capsules() { return capsules_; }
  std::vector<Body>& bodies() { return bodies_; }
  std::vector<Frame>& frames() { return frames_; }

  [[noreturn]] void fail(const std::string& what) const { throw ModelError(source_ + ": " + what); }

 private:
  urdf::LinkConstSharedPtr find_link(const std::string& name) const {
    urdf::LinkConstSharedPtr l = model_->getLink(name);
    if (!l) fail("link '" + name + "' not found");
    return l;
  }

  std::string source_;
  const urdf::ModelInterface* model_ = nullptr;
  std::vector<Body> bodies_;
  std::vector<Frame> frames_;
  std::vector<Capsule> capsules_;
  std::set<int> has_child_;
};

// <hapticd_drive joint="..." .../>: every numeric attribute of kNumeric is required, those of kOptional may be
// left out (zero); gear and motor are optional names.
void read_drives(const TiXmlDocument& doc, const std::string& source, std::vector<Body>& bodies) {
  static const char* const kNumeric[] = {"gear_ratio",
                                         "gear_peak_torque",
                                         "gear_average_torque",
                                         "stiffness_min",
                                         "stiffness_max",
                                         "max_input_speed_rpm",
                                         "wave_generator_inertia",
                                         "motor_stall_torque",
                                         "motor_continuous_torque",
                                         "rotor_inertia",
                                         "encoder_counts_per_motor_rev"};
  static const char* const kOptional[] = {"structural_stiffness", "damping_ratio"};
  const TiXmlElement* robot = doc.RootElement();
  std::set<std::string> seen;
  for (const TiXmlElement* e = robot->FirstChildElement("hapticd_drive"); e != nullptr;
       e = e->NextSiblingElement("hapticd_drive")) {
    const std::string where = source + ":" + std::to_string(e->Row()) + ": hapticd_drive";
    const char* joint = e->Attribute("joint");
    if (joint == nullptr) throw ModelError(where + ": attribute 'joint' missing");
    Body* body = nullptr;
    for (Body& b : bodies) {
      if (b.joint_name == joint) body = &b;
    }
    if (body == nullptr) throw ModelError(where + ": joint '" + joint + "' is not a movable joint of the chain");
    if (!seen.insert(joint).second) throw ModelError(where + ": second drive for joint '" + joint + "'");
    std::map<std::string, double> values;
    for (const TiXmlAttribute* a = e->FirstAttribute(); a != nullptr; a = a->Next()) {
      const std::string name = a->Name();
      if (name == "joint" || name == "gear" || name == "motor") continue;
      bool known = false;
      for (const char* k : kNumeric) known = known || name == k;
      for (const char* k : kOptional) known = known || name == k;
      if (!known) throw ModelError(where + ": unknown attribute '" + name + "'");
      std::istringstream in(a->Value());
      double v = 0.0;
      in >> v;
      if (in.fail() || !in.eof() || !std::isfinite(v) || v < 0.0) {
        throw ModelError(where + ": attribute '" + name + "' = '" + a->Value() +
                         "' is not a finite non-negative number");
      }
      values[name] = v;
    }
    for (const char* k : kNumeric) {
      if (values.count(k) == 0) throw ModelError(where + " joint='" + joint + "': attribute '" + k + "' missing");
    }
    DriveData& d = body->drive;
    d.present = true;
    d.gear = e->Attribute("gear") ? e->Attribute("gear") : "";
    d.motor = e->Attribute("motor") ? e->Attribute("motor") : "";
    d.gear_ratio = values["gear_ratio"];
    d.gear_peak_torque = values["gear_peak_torque"];
    d.gear_average_torque = values["gear_average_torque"];
    d.stiffness_min = values["stiffness_min"];
    d.stiffness_max = values["stiffness_max"];
    d.structural_stiffness = values.count("structural_stiffness") ? values["structural_stiffness"] : 0.0;
    d.damping_ratio = values.count("damping_ratio") ? values["damping_ratio"] : -1.0;
    d.max_input_speed_rpm = values["max_input_speed_rpm"];
    d.wave_generator_inertia = values["wave_generator_inertia"];
    d.motor_stall_torque = values["motor_stall_torque"];
    d.motor_continuous_torque = values["motor_continuous_torque"];
    d.rotor_inertia = values["rotor_inertia"];
    d.encoder_counts_per_motor_rev = static_cast<int>(values["encoder_counts_per_motor_rev"]);
    if (d.gear_ratio < 1.0) throw ModelError(where + " joint='" + joint + "': gear_ratio must be >= 1");
    if (d.stiffness_min > d.stiffness_max) {
      throw ModelError(where + " joint='" + joint + "': stiffness_min exceeds stiffness_max");
    }
    body->reflected_inertia = d.reflected_inertia();
  }
}

// Every <inertial> must be physical: a finite mass above zero, a finite inertia tensor that is positive definite
// and whose principal moments satisfy the triangle inequality (each at most the sum of the other two). urdfdom
// accepts "nan" and negative masses, and the dynamics would run on them.
void check_inertials(const TiXmlElement& robot, const std::string& source) {
  for (const TiXmlElement* link = robot.FirstChildElement("link"); link != nullptr;
       link = link->NextSiblingElement("link")) {
    const TiXmlElement* inertial = link->FirstChildElement("inertial");
    if (inertial == nullptr) continue;
    const std::string name = link->Attribute("name") != nullptr ? link->Attribute("name") : "?";
    const auto fail = [&](const TiXmlElement& at, const std::string& what) {
      throw ModelError(source + ":" + std::to_string(at.Row()) + ": link '" + name + "': " + what);
    };
    const auto number = [&](const TiXmlElement& at, const char* attribute) {
      const char* text = at.Attribute(attribute);
      if (text == nullptr) fail(at, std::string("<") + at.Value() + "> has no '" + attribute + "'");
      char* end = nullptr;
      const double v = std::strtod(text, &end);
      if (end == text || *end != '\0' || !std::isfinite(v))
        fail(at, std::string(at.Value()) + " " + attribute + "=\"" + text + "\" is not a finite number");
      return v;
    };
    const TiXmlElement* mass = inertial->FirstChildElement("mass");
    if (mass == nullptr) fail(*inertial, "<inertial> without <mass>");
    if (const double m = number(*mass, "value"); !(m > 0.0))
      fail(*mass, "mass " + std::to_string(m) + " kg: must be above zero");
    const TiXmlElement* inertia = inertial->FirstChildElement("inertia");
    if (inertia == nullptr) fail(*inertial, "<inertial> without <inertia>");
    Eigen::Matrix3d i;
    i << number(*inertia, "ixx"), number(*inertia, "ixy"), number(*inertia, "ixz"), 0, number(*inertia, "iyy"),
        number(*inertia, "iyz"), 0, 0, number(*inertia, "izz");
    i(1, 0) = i(0, 1);
    i(2, 0) = i(0, 2);
    i(2, 1) = i(1, 2);
    const Eigen::Vector3d moments =
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(i, Eigen::EigenvaluesOnly).eigenvalues();
    if (!(moments.minCoeff() > 0.0)) fail(*inertia, "the inertia tensor is not positive definite");
    const double tolerance = 1e-9 * moments.maxCoeff();
    for (int k = 0; k < 3; ++k)
      if (moments[k] > moments[(k + 1) % 3] + moments[(k + 2) % 3] + tolerance)
        fail(*inertia,
             "the principal moments of inertia violate the triangle inequality (one exceeds the sum of the others)");
  }
}

}  // namespace

RobotModel parse_robot_model(const std::string& urdf_text, const std::string& source_name) {
  TiXmlDocument doc;
  doc.Parse(urdf_text.c_str());
  if (doc.Error()) {
    throw ModelError(source_name + ":" + std::to_string(doc.ErrorRow()) + ": XML error: " + doc.ErrorDesc());
  }
  if (doc.RootElement() == nullptr || std::string(doc.RootElement()->Value()) != "robot") {
    throw ModelError(source_name + ": the root element is not <robot>");
  }
  check_inertials(*doc.RootElement(), source_name);
  const urdf::ModelInterfaceSharedPtr urdf_model = urdf::parseURDF(urdf_text);
  if (!urdf_model) {
    throw ModelError(source_name + ": not a valid URDF (urdfdom rejected it; its reason is printed above)");
  }
  ChainBuilder builder(source_name);
  builder.set_model(urdf_model.get());
  builder.walk(*urdf_model->getRoot(), -1, Eigen::Isometry3d::Identity());
  if (builder.bodies().empty()) throw ModelError(source_name + ": no movable joint");
  read_drives(doc, source_name, builder.bodies());
  RobotModel model(urdf_model->getName(), source_name, std::move(builder.bodies()), std::move(builder.frames()),
                   Eigen::Vector3d(0.0, 0.0, -9.81));
  if (builder.capsules().empty()) return model;
  try {
    return model.with_collision(std::move(builder.capsules()));
  } catch (const std::invalid_argument& e) {
    throw ModelError(source_name + ": " + e.what());
  }
}

RobotModel load_robot_model(const std::filesystem::path& urdf_file) {
  std::string text;
  try {
    text = read_input_file(urdf_file, "robot model");
  } catch (const std::runtime_error& e) {
    throw ModelError(e.what());
  }
  return parse_robot_model(text, urdf_file.string());
}

}  // namespace hapticd::model
