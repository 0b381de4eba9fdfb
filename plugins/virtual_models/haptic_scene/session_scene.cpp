#include "session_scene.hpp"

#include <cmath>
#include <stdexcept>

#include "hapticd/scene/mesh.hpp"
#include "hapticd/scene/scene_file.hpp"

namespace hapticd::models {
namespace {
std::size_t triangles_of(const scene::SceneObject& o) {
  return o.shape.mesh ? o.shape.mesh->data().triangles.size() : 0;
}
}  // namespace

ParameterSchema SessionScene::parameter_schema() {
  ParameterSchema s;
  s.string("file",
           "the scene's objects at the start: a scene file (YAML: materials and objects; docs/haptic-scene.md), "
           "relative to the session file; empty: the scene starts empty")
      .default_value(std::string());
  return s;
}

void SessionScene::configure(const Parameters& p, const PluginContext& context) {
  std::filesystem::path file = p.string("file");
  scene::SceneDocument document;
  if (!file.empty()) {
    if (file.is_relative()) file = context.config_directory / file;
    try {
      document = scene::load_scene_document(file);
    } catch (const scene::SceneFileError& e) {
      throw ParameterError("file", e.what());
    }
  }
  triangles_ = 0;
  for (const scene::SceneObject& o : document.scene.objects) triangles_ += triangles_of(o);
  materials_ = std::move(document.materials);
  scene_ = std::make_unique<scene::SharedScene>(std::move(document.scene));
}

std::uint64_t SessionScene::add(std::string_view text) {
  // Parsed and, for a hull, built here on the caller's thread; the scene takes the finished object.
  scene::SceneObject object = [&] {
    try {
      return scene::parse_scene_object(std::string(text), "the object added", materials_);
    } catch (const scene::SceneFileError& e) {
      throw std::invalid_argument(e.what());
    }
  }();
  return add_object(std::move(object));
}

std::uint64_t SessionScene::add_mesh(std::string_view text, std::vector<double> vertices,
                                     std::vector<std::uint32_t> triangles) {
  if (vertices.size() % 3 != 0 || triangles.size() % 3 != 0)
    throw std::invalid_argument("an uploaded mesh's vertices and triangles come three numbers each");
  scene::TriangleMeshData data;
  data.vertices.reserve(vertices.size() / 3);
  for (std::size_t i = 0; i + 2 < vertices.size(); i += 3)
    data.vertices.emplace_back(vertices[i], vertices[i + 1], vertices[i + 2]);
  data.triangles.reserve(triangles.size() / 3);
  for (std::size_t i = 0; i + 2 < triangles.size(); i += 3)
    data.triangles.push_back({triangles[i], triangles[i + 1], triangles[i + 2]});
  vertices = {};
  triangles = {};
  scene::SceneObject object = [&] {
    try {
      return scene::parse_scene_object(std::string(text), "the object added", materials_, &data);
    } catch (const scene::SceneFileError& e) {
      throw std::invalid_argument(e.what());
    }
  }();
  return add_object(std::move(object));
}

std::uint64_t SessionScene::add_object(scene::SceneObject object) {
  const std::size_t triangles = triangles_of(object);
  std::lock_guard lock(mutex_);
  if (triangles_ + triangles > scene::kMaxSceneTriangles)
    throw std::invalid_argument("'" + object.name + "': the scene would have " +
                                std::to_string(triangles_ + triangles) + " triangles, at most " +
                                std::to_string(scene::kMaxSceneTriangles));
  const std::uint64_t uid = scene_->add(std::move(object));
  triangles_ += triangles;
  return uid;
}

void SessionScene::remove(std::string_view name) {
  std::lock_guard lock(mutex_);
  std::size_t triangles = 0;
  for (const scene::SceneObject& o : scene_->snapshot().objects)
    if (o.name == name) triangles = triangles_of(o);
  scene_->remove(name);
  triangles_ -= triangles;
}

void SessionScene::set_material(std::string_view name, std::string_view text) {
  const scene::Material material = [&] {
    try {
      return scene::parse_material(std::string(text), "the material of '" + std::string(name) + "'", materials_);
    } catch (const scene::SceneFileError& e) {
      throw std::invalid_argument(e.what());
    }
  }();
  scene_->set_material(name, material);
}

void SessionScene::move(std::string_view name, const Pose& pose) {
  const double norm = pose.orientation.norm();
  if (!pose.position.allFinite() || !pose.orientation.coeffs().allFinite() || norm < 1e-6)
    throw std::invalid_argument("the pose of '" + std::string(name) +
                                "' is not a pose (a value not finite, or a zero quaternion)");
  scene::PoseUpdate update;
  update.position = pose.position;
  update.orientation = pose.orientation.normalized();
  scene_->move(name, update);
}

std::vector<SceneContact> SessionScene::contacts() {
  std::vector<SceneContact> out;
  for (const scene::DeviceContact& c : scene_->contacts())  // the torque about the object's origin as rendered
    out.push_back({c.device, c.object, c.force, (c.point - c.origin).cross(c.force), c.point});
  return out;
}

std::vector<SceneObjectSummary> SessionScene::objects() const {
  std::vector<SceneObjectSummary> list;
  for (const scene::SceneObject& o : scene_->snapshot().objects) {
    SceneObjectSummary s;
    s.name = o.name;
    s.shape = scene::kind_name(o.shape.kind);
    s.uid = o.uid;
    s.moving = o.moving;
    s.triangles = triangles_of(o);
    s.pose = to_pose(o.pose);
    list.push_back(std::move(s));
  }
  return list;
}

}  // namespace hapticd::models

namespace hapticd::models {

SceneDrawing SessionScene::drawing(std::size_t max_triangles) {
  SceneDrawing d;
  for (const scene::SceneObject& o : scene_->drawn().objects) {
    SceneObjectDrawing x;
    x.name = o.name;
    x.shape = scene::kind_name(o.shape.kind);
    x.moving = o.moving;
    x.pose = to_pose(o.pose);
    switch (o.shape.kind) {
      case scene::ShapeKind::box:
        x.size = 2.0 * o.shape.half_extents;
        break;
      case scene::ShapeKind::sphere:
        x.size = Eigen::Vector3d(o.shape.radius, 0, 0);
        break;
      case scene::ShapeKind::capsule:
      case scene::ShapeKind::cylinder:
        x.size = Eigen::Vector3d(o.shape.radius, 2.0 * o.shape.half_length, 0);
        break;
      case scene::ShapeKind::plane:
        break;
      case scene::ShapeKind::mesh: {
        const scene::TriangleMeshData& m = o.shape.mesh->data();
        x.triangles = m.triangles.size();
        const std::size_t step = max_triangles == 0 ? 0 : (m.triangles.size() + max_triangles - 1) / max_triangles;
        for (std::size_t t = 0; step > 0 && t < m.triangles.size(); t += step)
          for (const std::uint32_t v : m.triangles[t]) x.corners.push_back(m.vertices[v].cast<float>());
        break;
      }
    }
    d.objects.push_back(std::move(x));
  }
  for (const scene::DeviceProxy& p : scene_->proxies())
    d.proxies.push_back({p.device, p.position, p.radius, p.touching});
  return d;
}

}  // namespace hapticd::models
