#include "hapticd/scene/scene_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "hapticd/input_file.hpp"
#include "hapticd/scene/convex_hull.hpp"
#include "hapticd/scene/mesh_file.hpp"

namespace hapticd::scene {
namespace {

class Reader {
 public:
  explicit Reader(std::string name, bool files_allowed = true, TriangleMeshData* uploaded = nullptr)
      : name_(std::move(name)),
        folder_(std::filesystem::path(name_).parent_path()),
        files_allowed_(files_allowed),
        uploaded_(uploaded) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& key, const std::string& what) const {
    const std::string line = node.IsDefined() && node.Mark().line >= 0 ? std::to_string(node.Mark().line + 1) : "?";
    throw SceneFileError(name_ + ":" + line + ": " + key + ": " + what);
  }

  void only(const YAML::Node& map, const std::string& where, const std::set<std::string>& keys) const {
    if (!map.IsMap()) fail(map, where, "must be a mapping");
    for (const auto& entry : map) {
      const std::string key = entry.first.as<std::string>();
      if (!keys.contains(key)) {
        std::string known;
        for (const auto& k : keys) known += (known.empty() ? "" : ", ") + k;
        fail(entry.first, where + "." + key, "unknown key (known: " + known + ")");
      }
    }
  }

  double real(const YAML::Node& node, const std::string& key) const {
    double v = 0.0;
    try {
      v = node.as<double>();
    } catch (const YAML::Exception&) {
      fail(node, key, "must be a number");
    }
    if (!std::isfinite(v)) fail(node, key, "must be finite");
    return v;
  }

  double real(const YAML::Node& map, const std::string& where, const std::string& key, double fallback, double minimum,
              bool positive) const {
    const YAML::Node node = map[key];
    if (!node.IsDefined()) return fallback;
    const double v = real(node, where + "." + key);
    if (positive && v <= 0.0) fail(node, where + "." + key, "must be positive");
    if (v < minimum) fail(node, where + "." + key, "must be at least " + std::to_string(minimum));
    return v;
  }

  double required_positive(const YAML::Node& map, const std::string& where, const std::string& key) const {
    if (!map[key].IsDefined()) fail(map, where + "." + key, "missing (this shape needs it)");
    return real(map, where, key, 0.0, 0.0, true);
  }

  Eigen::Vector3d vector3(const YAML::Node& node, const std::string& key) const {
    if (!node.IsSequence() || node.size() != 3) fail(node, key, "must be a list of 3 numbers");
    return {real(node[0], key + "[0]"), real(node[1], key + "[1]"), real(node[2], key + "[2]")};
  }

  Material material(const YAML::Node& map, const std::string& where) const {
    only(map, where,
         {"stiffness", "damping", "static_friction", "dynamic_friction", "texture_amplitude", "texture_period"});
    Material m;
    m.stiffness_n_per_m = real(map, where, "stiffness", m.stiffness_n_per_m, 0.0, true);
    m.damping_n_s_per_m = real(map, where, "damping", m.damping_n_s_per_m, 0.0, false);
    m.static_friction = real(map, where, "static_friction", 0.0, 0.0, false);
    m.dynamic_friction = real(map, where, "dynamic_friction", m.static_friction, 0.0, false);
    if (m.dynamic_friction > m.static_friction) {
      if (map["static_friction"].IsDefined())
        fail(map["dynamic_friction"], where + ".dynamic_friction", "must not exceed static_friction");
      m.static_friction = m.dynamic_friction;
    }
    m.texture_amplitude_m = real(map, where, "texture_amplitude", 0.0, 0.0, false);
    m.texture_period_m = real(map, where, "texture_period", m.texture_period_m, 0.0, true);
    return m;
  }

  Eigen::Isometry3d pose(const YAML::Node& map, const std::string& where) const {
    Eigen::Isometry3d x = Eigen::Isometry3d::Identity();
    if (map["position"].IsDefined()) x.translation() = vector3(map["position"], where + ".position");
    const int orientations = map["rpy_deg"].IsDefined() + map["quaternion"].IsDefined() + map["normal"].IsDefined();
    if (orientations > 1) fail(map, where, "give one of rpy_deg, quaternion and normal");
    if (map["rpy_deg"].IsDefined()) {
      const Eigen::Vector3d a = vector3(map["rpy_deg"], where + ".rpy_deg") * (std::numbers::pi / 180.0);
      x.linear() =
          (Eigen::AngleAxisd(a.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(a.y(), Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(a.x(), Eigen::Vector3d::UnitX()))
              .toRotationMatrix();
    } else if (map["quaternion"].IsDefined()) {
      const YAML::Node q = map["quaternion"];
      if (!q.IsSequence() || q.size() != 4) fail(q, where + ".quaternion", "must be [w, x, y, z]");
      Eigen::Quaterniond quat(real(q[0], where + ".quaternion[0]"), real(q[1], where + ".quaternion[1]"),
                              real(q[2], where + ".quaternion[2]"), real(q[3], where + ".quaternion[3]"));
      if (quat.norm() < 1e-9) fail(q, where + ".quaternion", "must not be zero");
      x.linear() = quat.normalized().toRotationMatrix();
    } else if (map["normal"].IsDefined()) {
      const Eigen::Vector3d n = vector3(map["normal"], where + ".normal");
      if (n.norm() < 1e-9) fail(map["normal"], where + ".normal", "must not be zero");
      x.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), n.normalized()).toRotationMatrix();
    }
    return x;
  }

  SceneObject object(const YAML::Node& map, const std::string& where,
                     const std::map<std::string, Material>& materials) const {
    only(map, where,
         {"name", "shape", "radius", "size", "length", "file", "scale", "points", "position", "rpy_deg", "quaternion",
          "normal", "material", "moving", "upload"});
    SceneObject o;
    if (!map["name"].IsDefined()) fail(map, where + ".name", "missing");
    o.name = map["name"].as<std::string>();
    if (o.name.empty() || o.name.size() > 64) fail(map["name"], where + ".name", "must have 1 to 64 characters");
    if (!map["shape"].IsDefined())
      fail(map, where + ".shape", "missing (plane, sphere, box, capsule, cylinder, convex_hull or mesh)");
    const std::string shape = map["shape"].as<std::string>();
    // An upload is a client's mesh: named by a mesh added with its triangles, by nothing else (a hull too).
    if (map["upload"].IsDefined() && (uploaded_ == nullptr || shape != "mesh"))
      fail(map["upload"], where + ".upload",
           uploaded_ == nullptr ? "names no upload here (an engine's mesh, added at run time)"
                                : "an uploaded mesh is added as a mesh");
    if (uploaded_ != nullptr && shape != "mesh")
      fail(map["shape"], where + ".shape", "an uploaded mesh is added as a mesh");
    if (shape == "convex_hull") return convex_hull_object(map, where, materials);
    const std::map<std::string, ShapeKind> kinds{{"plane", ShapeKind::plane},       {"sphere", ShapeKind::sphere},
                                                 {"box", ShapeKind::box},           {"capsule", ShapeKind::capsule},
                                                 {"cylinder", ShapeKind::cylinder}, {"mesh", ShapeKind::mesh}};
    const auto kind = kinds.find(shape);
    if (kind == kinds.end())
      fail(map["shape"], where + ".shape",
           "'" + shape + "' is not plane, sphere, box, capsule, cylinder, convex_hull or mesh");
    o.shape.kind = kind->second;
    const bool round =
        o.shape.kind == ShapeKind::sphere || o.shape.kind == ShapeKind::capsule || o.shape.kind == ShapeKind::cylinder;
    const bool long_ = o.shape.kind == ShapeKind::capsule || o.shape.kind == ShapeKind::cylinder;
    auto refuse = [&](const char* key, bool wanted) {
      if (!wanted && map[key].IsDefined()) fail(map[key], where + "." + key, "a " + shape + " has no " + key);
    };
    refuse("radius", round);
    refuse("length", long_);
    refuse("size", o.shape.kind == ShapeKind::box);
    refuse("normal", o.shape.kind == ShapeKind::plane);
    refuse("file", o.shape.kind == ShapeKind::mesh);
    refuse("scale", o.shape.kind == ShapeKind::mesh);
    refuse("points", false);
    if (o.shape.kind == ShapeKind::mesh)
      o.shape.mesh = uploaded_ ? uploaded_mesh(map, where, o.name) : mesh(map, where, o.name);
    if (round) o.shape.radius = required_positive(map, where, "radius");
    if (long_) o.shape.half_length = 0.5 * required_positive(map, where, "length");
    if (o.shape.kind == ShapeKind::box) {
      if (!map["size"].IsDefined()) fail(map, where + ".size", "missing (a box's edge lengths [x, y, z])");
      const Eigen::Vector3d size = vector3(map["size"], where + ".size");
      if (size.minCoeff() <= 0.0) fail(map["size"], where + ".size", "every edge must be positive");
      o.shape.half_extents = 0.5 * size;
    }
    place_and_dress(o, map, where, materials);
    return o;
  }

  // A convex hull: of the points given, or of a mesh file's vertices (scaled); met as the mesh of its faces.
  SceneObject convex_hull_object(const YAML::Node& map, const std::string& where,
                                 const std::map<std::string, Material>& materials) const {
    for (const char* key : {"radius", "length", "size", "normal"})
      if (map[key].IsDefined()) fail(map[key], where + "." + key, std::string("a convex_hull has no ") + key);
    SceneObject o;
    o.name = map["name"].as<std::string>();
    o.shape.kind = ShapeKind::mesh;
    const bool listed = map["points"].IsDefined(), from_file = map["file"].IsDefined();
    if (listed == from_file)
      fail(map, where + ".points", "give the hull's points, or a mesh file whose vertices it wraps (file), not both");
    if (listed && map["scale"].IsDefined()) fail(map["scale"], where + ".scale", "scale goes with file");
    std::vector<Eigen::Vector3d> points;
    if (listed) {
      const YAML::Node list = map["points"];
      if (!list.IsSequence() || list.size() > kMaxHullPoints)
        fail(list, where + ".points", "expected a list of [x, y, z] points (at most 1000000)");
      for (std::size_t i = 0; i < list.size(); ++i)
        points.push_back(vector3(list[i], where + ".points[" + std::to_string(i) + "]"));
    } else {
      points = mesh_data(map, where).vertices;
    }
    try {
      o.shape.mesh = MeshShape::build(convex_hull(points, o.name), o.name);
    } catch (const std::invalid_argument& e) {
      fail(listed ? map["points"] : map["file"], where + (listed ? ".points" : ".file"), e.what());
    }
    place_and_dress(o, map, where, materials);
    return o;
  }

  // The object's pose and material.
  void place_and_dress(SceneObject& o, const YAML::Node& map, const std::string& where,
                       const std::map<std::string, Material>& materials) const {
    o.pose = pose(map, where);
    if (map["material"].IsDefined()) o.material = named_or_in_place(map["material"], where + ".material", materials);
    if (const YAML::Node m = map["moving"]; m.IsDefined()) {
      try {
        o.moving = m.as<bool>();
      } catch (const YAML::Exception&) {
        fail(m, where + ".moving", "must be true or false");
      }
    }
  }

  // A material: a name from `materials`, or one in place.
  Material named_or_in_place(const YAML::Node& m, const std::string& where,
                             const std::map<std::string, Material>& materials) const {
    if (!m.IsScalar()) return material(m, where);
    const auto found = materials.find(m.as<std::string>());
    if (found == materials.end()) fail(m, where, "no material '" + m.as<std::string>() + "' in materials");
    return found->second;
  }

  // The client's uploaded triangles, checked and given their structure here, off the loop.
  std::shared_ptr<const MeshShape> uploaded_mesh(const YAML::Node& map, const std::string& where,
                                                 const std::string& name) const {
    if (map["file"].IsDefined()) fail(map["file"], where + ".file", "an uploaded mesh names no file");
    try {
      return MeshShape::build(std::move(*uploaded_), name);
    } catch (const std::exception& e) {
      fail(map["upload"], where + ".upload", e.what());
    }
  }

  // A mesh file (relative to the scene file), read, checked and given its structure here, off the loop.
  std::shared_ptr<const MeshShape> mesh(const YAML::Node& map, const std::string& where,
                                        const std::string& name) const {
    TriangleMeshData data = mesh_data(map, where);
    try {
      return MeshShape::build(std::move(data), name);
    } catch (const std::exception& e) {
      fail(map["file"], where + ".file", e.what());
    }
  }

  // A mesh file's triangles (relative to the scene file), scaled.
  TriangleMeshData mesh_data(const YAML::Node& map, const std::string& where) const {
    if (!map["file"].IsDefined()) fail(map, where + ".file", "missing (a mesh's STL, OBJ, PLY or glTF file)");
    if (!files_allowed_)
      fail(map["file"], where + ".file",
           "a file named by a client is not read (the server's files are not a client's to open): list a hull's "
           "points, or name the mesh in the session's scene file");
    std::filesystem::path file = map["file"].as<std::string>();
    if (file.is_relative()) file = folder_ / file;
    Eigen::Vector3d scale = Eigen::Vector3d::Ones();
    if (const YAML::Node s = map["scale"]; s.IsDefined()) {
      scale = s.IsSequence() ? vector3(s, where + ".scale") : Eigen::Vector3d::Constant(real(s, where + ".scale"));
      if (scale.minCoeff() <= 0.0) fail(s, where + ".scale", "must be positive");
    }
    try {
      return load_mesh_file(file, scale);
    } catch (const std::exception& e) {
      fail(map["file"], where + ".file", e.what());
    }
  }

  SceneDocument document(const YAML::Node& root) const {
    if (!root.IsDefined() || root.IsNull()) throw SceneFileError(name_ + ": the scene file is empty");
    only(root, "scene", {"materials", "objects"});
    SceneDocument d;
    std::map<std::string, Material>& materials = d.materials;
    if (root["materials"].IsDefined()) {
      const YAML::Node ms = root["materials"];
      if (!ms.IsMap()) fail(ms, "materials", "must be a mapping of names to materials");
      for (const auto& entry : ms)
        materials[entry.first.as<std::string>()] = material(entry.second, "materials." + entry.first.as<std::string>());
    }
    const YAML::Node objects = root["objects"];
    if (!objects.IsDefined() || !objects.IsSequence()) fail(root, "objects", "missing (a list of objects)");
    if (objects.size() > kMaxSceneObjects)
      fail(objects, "objects",
           std::to_string(objects.size()) + " objects: at most " + std::to_string(kMaxSceneObjects));
    Scene& s = d.scene;
    std::set<std::string> names;
    std::size_t triangles = 0;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      const std::string where = "objects[" + std::to_string(i) + "]";
      s.objects.push_back(object(objects[i], where, materials));
      if (s.objects.back().shape.mesh) triangles += s.objects.back().shape.mesh->data().triangles.size();
      if (triangles > kMaxSceneTriangles)
        fail(objects[i], where,
             "the scene's meshes have " + std::to_string(triangles) + " triangles: at most " +
                 std::to_string(kMaxSceneTriangles));
      if (!names.insert(s.objects.back().name).second)
        fail(objects[i]["name"], where + ".name", "'" + s.objects.back().name + "' is taken by another object");
    }
    return d;
  }

 private:
  std::string name_;
  std::filesystem::path folder_;
  bool files_allowed_ = true;
  TriangleMeshData* uploaded_ = nullptr;  // a client's mesh for the object being read
};

// Parses `text` as YAML and reads it with `read`; every error a SceneFileError naming `name` and the line.
template <class Read>
auto read_text(const std::string& text, const std::string& name, Read read) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw SceneFileError(name + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  try {
    return read(root);
  } catch (const YAML::Exception& e) {
    throw SceneFileError(name + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
}

}  // namespace

SceneDocument parse_scene_document(const std::string& text, const std::string& name) {
  return read_text(text, name, [&](const YAML::Node& root) { return Reader(name).document(root); });
}

Scene parse_scene(const std::string& text, const std::string& name) { return parse_scene_document(text, name).scene; }

SceneDocument load_scene_document(const std::filesystem::path& file) {
  std::string text;
  try {
    text = read_input_file(file, "scene file");
  } catch (const std::runtime_error& e) {
    throw SceneFileError(e.what());
  }
  return parse_scene_document(text, file.string());
}

Scene load_scene_file(const std::filesystem::path& file) { return load_scene_document(file).scene; }

SceneObject parse_scene_object(const std::string& text, const std::string& name,
                               const std::map<std::string, Material>& materials, TriangleMeshData* uploaded) {
  return read_text(text, name, [&](const YAML::Node& root) {
    if (!root.IsDefined() || root.IsNull()) throw SceneFileError(name + ": no object");
    return Reader(name, false, uploaded).object(root, "object", materials);
  });
}

Material parse_material(const std::string& text, const std::string& name,
                        const std::map<std::string, Material>& materials) {
  return read_text(text, name, [&](const YAML::Node& root) {
    if (!root.IsDefined() || root.IsNull()) throw SceneFileError(name + ": no material");
    return Reader(name, false).named_or_in_place(root, "material", materials);
  });
}

}  // namespace hapticd::scene
