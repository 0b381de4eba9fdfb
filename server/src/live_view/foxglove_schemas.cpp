#include "live_view/foxglove_schemas.hpp"

namespace hapticd::server::live_view {

namespace {

// Pieces of JSON Schema the messages share.
std::string object(const std::string& title, const std::string& properties) {
  return R"({"type":"object","title":")" + title + R"(","properties":{)" + properties + "}}";
}
std::string number(const std::string& name) { return "\"" + name + R"(":{"type":"number"})"; }
std::string text(const std::string& name) { return "\"" + name + R"(":{"type":"string"})"; }
std::string boolean(const std::string& name) { return "\"" + name + R"(":{"type":"boolean"})"; }
std::string field(const std::string& name, const std::string& schema) { return "\"" + name + "\":" + schema; }
std::string array_of(const std::string& schema) { return R"({"type":"array","items":)" + schema + "}"; }

std::string time() { return object("time", number("sec") + "," + number("nsec")); }
std::string vector3() { return object("Vector3", number("x") + "," + number("y") + "," + number("z")); }
std::string quaternion() {
  return object("Quaternion", number("x") + "," + number("y") + "," + number("z") + "," + number("w"));
}
std::string pose() { return object("Pose", field("position", vector3()) + "," + field("orientation", quaternion())); }
std::string color() { return object("Color", number("r") + "," + number("g") + "," + number("b") + "," + number("a")); }
std::string sized(const std::string& title) {
  return object(title, field("pose", pose()) + "," + field("size", vector3()) + "," + field("color", color()));
}
std::string wrench() { return object("Wrench", field("force", vector3()) + "," + field("torque", vector3())); }

}  // namespace

std::string frame_transforms_schema() {
  const std::string transform =
      object("foxglove.FrameTransform", field("timestamp", time()) + "," + text("parent_frame_id") + "," +
                                            text("child_frame_id") + "," + field("translation", vector3()) + "," +
                                            field("rotation", quaternion()));
  return object(kFrameTransformsName, field("transforms", array_of(transform)));
}

std::string scene_update_schema() {
  const std::string arrow =
      object("foxglove.ArrowPrimitive", field("pose", pose()) + "," + number("shaft_length") + "," +
                                            number("shaft_diameter") + "," + number("head_length") + "," +
                                            number("head_diameter") + "," + field("color", color()));
  const std::string cylinder =
      object("foxglove.CylinderPrimitive", field("pose", pose()) + "," + field("size", vector3()) + "," +
                                               number("bottom_scale") + "," + number("top_scale") + "," +
                                               field("color", color()));
  const std::string key_value = object("foxglove.KeyValuePair", text("key") + "," + text("value"));
  const std::string entity = object(
      "foxglove.SceneEntity",
      field("timestamp", time()) + "," + text("frame_id") + "," + text("id") + "," + field("lifetime", time()) + "," +
          boolean("frame_locked") + "," + field("metadata", array_of(key_value)) + "," +
          field("arrows", array_of(arrow)) + "," + field("cubes", array_of(sized("foxglove.CubePrimitive"))) + "," +
          field("spheres", array_of(sized("foxglove.SpherePrimitive"))) + "," + field("cylinders", array_of(cylinder)) +
          "," + field("lines", array_of(R"({"type":"object"})")) + "," +
          field("triangles", array_of(R"({"type":"object"})")) + "," +
          field("texts", array_of(R"({"type":"object"})")) + "," + field("models", array_of(R"({"type":"object"})")));
  const std::string deletion =
      object("foxglove.SceneEntityDeletion", field("timestamp", time()) + "," + number("type") + "," + text("id"));
  return object(kSceneUpdateName, field("deletions", array_of(deletion)) + "," + field("entities", array_of(entity)));
}

std::string device_state_schema() {
  const std::string numbers = array_of(R"({"type":"number"})");
  const std::string names = array_of(R"({"type":"string"})");
  const std::string joints = object("joints", field("name", names) + "," + field("position", numbers) + "," +
                                                  field("velocity", numbers) + "," + field("torque", numbers));
  const std::string handle =
      object("handle", field("position", vector3()) + "," + field("orientation", quaternion()) + "," +
                           field("linear_velocity", vector3()) + "," + field("angular_velocity", vector3()));
  const std::string engine =
      object("engine", number("weight") + "," + boolean("stale") + "," + number("sequence") + "," +
                           field("proxy", R"({"anyOf":[)" + pose() + R"(,{"type":"null"}]})") + "," +
                           field("wrench", R"({"anyOf":[)" + wrench() + R"(,{"type":"null"}]})"));
  const std::string safety = object("safety", text("fault") + "," + number("faults") + "," + number("thermal_load") +
                                                  "," + number("dissipated_j") + "," + boolean("passivity_control"));
  return object(kDeviceStateName, field("timestamp", time()) + "," + text("device") + "," + number("cycle") + "," +
                                      text("mode") + "," + field("flags", names) + "," + text("scheme") + "," +
                                      field("joints", joints) + "," + field("handle", handle) + "," +
                                      field("target", pose()) + "," + field("operator_wrench", wrench()) + "," +
                                      field("rendered_wrench", wrench()) + "," + field("engine", engine) + "," +
                                      field("safety", safety));
}

}  // namespace hapticd::server::live_view
