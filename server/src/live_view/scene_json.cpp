#include "live_view/scene_json.hpp"

#include "hapticd/json_text.hpp"

namespace hapticd::server::live_view::scene_json {

using namespace json_text;

void append_colour(std::string& out, const Rgba& c) {
  append_number_object(out, {{"r", c.r}, {"g", c.g}, {"b", c.b}, {"a", c.a}});
}

void append_pose(std::string& out, const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  out += "{\"position\":";
  append_vector3(out, p.x(), p.y(), p.z());
  out += ",\"orientation\":";
  append_quaternion(out, q.x(), q.y(), q.z(), q.w());
  out += '}';
}
void append_pose(std::string& out, const Pose& p) { append_pose(out, p.position, p.orientation); }

void begin_entity(std::string& out, bool first, std::uint64_t time_ns, const std::string& id,
                  const std::string& metadata) {
  if (!first) out += ',';
  out += "{\"timestamp\":";
  append_time(out, time_ns);
  out += ",\"frame_id\":\"world\",\"id\":";
  append_string(out, id);
  out += ",\"lifetime\":{\"sec\":0,\"nsec\":0},\"frame_locked\":false,\"metadata\":[";
  out += metadata;
  out += ']';
}
void end_entity(std::string& out) { out += '}'; }

void empty_lists(std::string& out, std::initializer_list<const char*> names) {
  for (const char* n : names) {
    out += ",\"";
    out += n;
    out += "\":[]";
  }
}

void append_sphere(std::string& out, bool first, const Eigen::Vector3d& centre, double diameter, const Rgba& c) {
  if (!first) out += ',';
  out += "{\"pose\":";
  append_pose(out, centre, Eigen::Quaterniond::Identity());
  out += ",\"size\":";
  append_vector3(out, diameter, diameter, diameter);
  out += ",\"color\":";
  append_colour(out, c);
  out += '}';
}

void append_cylinder(std::string& out, bool first, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double diameter,
                     const Rgba& c) {
  if (!first) out += ',';
  const Eigen::Vector3d axis = b - a;
  const Eigen::Quaterniond q = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis);
  out += "{\"pose\":";
  append_pose(out, 0.5 * (a + b), q);
  out += ",\"size\":";
  append_vector3(out, diameter, diameter, axis.norm());
  out += ",\"bottom_scale\":1,\"top_scale\":1,\"color\":";
  append_colour(out, c);
  out += '}';
}

void append_sized(std::string& out, bool first, const Pose& pose, const Eigen::Vector3d& size, const Rgba& c,
                  bool cylinder) {
  if (!first) out += ',';
  out += "{\"pose\":";
  append_pose(out, pose);
  out += ",\"size\":";
  append_vector3(out, size.x(), size.y(), size.z());
  if (cylinder) out += ",\"bottom_scale\":1,\"top_scale\":1";
  out += ",\"color\":";
  append_colour(out, c);
  out += '}';
}

}  // namespace hapticd::server::live_view::scene_json
