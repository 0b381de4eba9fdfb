#include "hapticd/scene/mesh.hpp"

#include <embree3/rtcore.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <unordered_map>

namespace hapticd::scene {
namespace {

// One Embree device for the process: builds run on the calling thread (off the loop).
RTCDevice shared_device() {
  static std::mutex mutex;
  static RTCDevice device = nullptr;
  const std::lock_guard lock(mutex);
  if (device == nullptr) {
    device = rtcNewDevice("threads=1,set_affinity=0");
    if (device == nullptr) throw std::runtime_error("the mesh library (Embree) could not start");
  }
  return device;
}

}  // namespace

struct MeshShape::Index {
  RTCScene scene = nullptr;
  ~Index() {
    if (scene != nullptr) rtcReleaseScene(scene);
  }
};

MeshShape::~MeshShape() = default;

std::shared_ptr<const MeshShape> MeshShape::build(TriangleMeshData data, const std::string& name) {
  auto fail = [&](const std::string& what) { throw std::invalid_argument("mesh '" + name + "': " + what); };
  if (data.vertices.size() > kMaxMeshVertices)
    fail(std::to_string(data.vertices.size()) + " vertices: at most " + std::to_string(kMaxMeshVertices));
  if (data.triangles.size() > kMaxMeshTriangles)
    fail(std::to_string(data.triangles.size()) + " triangles: at most " + std::to_string(kMaxMeshTriangles));
  for (std::size_t i = 0; i < data.vertices.size(); ++i)
    if (!data.vertices[i].allFinite()) fail("vertex " + std::to_string(i) + " is not finite");
  std::shared_ptr<MeshShape> mesh(new MeshShape());
  std::vector<std::array<std::uint32_t, 3>> kept;
  kept.reserve(data.triangles.size());
  double extent = 0.0;
  for (const auto& v : data.vertices) extent = std::max(extent, v.cwiseAbs().maxCoeff());
  const double tiny_area = 1e-18 * std::max(1e-6, extent * extent);
  for (std::size_t i = 0; i < data.triangles.size(); ++i) {
    const auto& t = data.triangles[i];
    for (std::uint32_t k : t)
      if (k >= data.vertices.size())
        fail("triangle " + std::to_string(i) + " names vertex " + std::to_string(k) + " of " +
             std::to_string(data.vertices.size()));
    const Eigen::Vector3d n =
        (data.vertices[t[1]] - data.vertices[t[0]]).cross(data.vertices[t[2]] - data.vertices[t[0]]);
    if (0.5 * n.norm() <= tiny_area) {
      ++mesh->dropped_;
      continue;
    }
    kept.push_back(t);
  }
  if (kept.empty()) fail("no triangle with an area");
  data.triangles = std::move(kept);
  // Angle-weighted vertex normals (Thuermer and Wuethrich): smooth across a tessellated curve, flat faces kept flat.
  mesh->normals_.assign(data.vertices.size(), Eigen::Vector3d::Zero());
  mesh->face_normals_.reserve(data.triangles.size());
  mesh->balls_.reserve(data.triangles.size());
  for (const auto& t : data.triangles) {
    const Eigen::Vector3d a = data.vertices[t[0]], b = data.vertices[t[1]], c = data.vertices[t[2]];
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    mesh->face_normals_.push_back(n);
    const Eigen::Vector3d centre = (a + b + c) / 3.0;
    mesh->balls_.push_back(Ball{centre, std::max({(a - centre).norm(), (b - centre).norm(), (c - centre).norm()})});
    const Eigen::Vector3d p[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e1 = (p[(k + 1) % 3] - p[k]).normalized(), e2 = (p[(k + 2) % 3] - p[k]).normalized();
      mesh->normals_[t[static_cast<std::size_t>(k)]] += std::acos(std::clamp(e1.dot(e2), -1.0, 1.0)) * n;
    }
  }
  for (auto& n : mesh->normals_) {
    const double length = n.norm();
    n = length > 0.0 ? Eigen::Vector3d(n / length) : Eigen::Vector3d::UnitZ();
  }
  for (const auto& v : data.vertices) mesh->bounding_radius_ = std::max(mesh->bounding_radius_, v.norm());
  // Each edge's neighbour across it: convex (the neighbour's far corner below this face's plane) or a border.
  {
    std::unordered_map<std::uint64_t, std::pair<std::uint32_t, int>> first;  // edge -> (triangle, its edge)
    first.reserve(data.triangles.size() * 2);
    mesh->convex_.assign(data.triangles.size(), {true, true, true});
    const double tolerance = 1e-9 * std::max(1e-3, mesh->bounding_radius_);
    auto bends_away = [&](std::uint32_t t, std::uint32_t other, int other_edge) {
      const std::uint32_t far = data.triangles[other][static_cast<std::size_t>((other_edge + 2) % 3)];
      return mesh->face_normals_[t].dot(data.vertices[far] - data.vertices[data.triangles[t][0]]) < -tolerance;
    };
    for (std::uint32_t t = 0; t < data.triangles.size(); ++t)
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t a = data.triangles[t][static_cast<std::size_t>(e)];
        const std::uint32_t b = data.triangles[t][static_cast<std::size_t>((e + 1) % 3)];
        const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
        const auto [it, fresh] = first.try_emplace(key, t, e);
        if (fresh) continue;
        const auto [u, ue] = it->second;
        mesh->convex_[t][static_cast<std::size_t>(e)] = bends_away(t, u, ue);
        mesh->convex_[u][static_cast<std::size_t>(ue)] = bends_away(u, t, e);
      }
  }

  RTCDevice device = shared_device();
  mesh->index_ = std::make_unique<Index>();
  mesh->index_->scene = rtcNewScene(device);
  // Medium quality: no spatial splits, so a query meets each triangle once.
  rtcSetSceneBuildQuality(mesh->index_->scene, RTC_BUILD_QUALITY_MEDIUM);
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                        3 * sizeof(float), data.vertices.size()));
  auto* idx = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                  3 * sizeof(std::uint32_t), data.triangles.size()));
  if (v == nullptr || idx == nullptr) {
    rtcReleaseGeometry(g);
    fail("the mesh library could not allocate its buffers");
  }
  for (std::size_t i = 0; i < data.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) v[3 * i + static_cast<std::size_t>(k)] = static_cast<float>(data.vertices[i][k]);
  for (std::size_t i = 0; i < data.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k)
      idx[3 * i + static_cast<std::size_t>(k)] = data.triangles[i][static_cast<std::size_t>(k)];
  rtcCommitGeometry(g);
  rtcAttachGeometry(mesh->index_->scene, g);
  rtcReleaseGeometry(g);
  rtcCommitScene(mesh->index_->scene);
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE) fail("the mesh library could not build its structure");
  mesh->data_ = std::move(data);
  return mesh;
}

// The culling radius around `p` for an exact radius: widened for the single-precision structure (it culls, the
// exact test in double precision decides).
float MeshShape::culling_radius(const Eigen::Vector3d& p, double radius) const noexcept {
  return static_cast<float>(radius * 1.0001 + 1e-6 * (1.0 + bounding_radius_ + p.norm()));
}

// Runs Embree's point query about `p` with `callback` for each triangle in reach (its user pointer `context`).
void MeshShape::query(const Eigen::Vector3d& p, double radius, bool (*callback)(RTCPointQueryFunctionArguments*),
                      void* context) const noexcept {
  RTCPointQuery q;
  q.x = static_cast<float>(p.x());
  q.y = static_cast<float>(p.y());
  q.z = static_cast<float>(p.z());
  q.radius = culling_radius(p, radius);
  q.time = 0.0f;
  RTCPointQueryContext pc;
  rtcInitPointQueryContext(&pc);
  rtcPointQuery(index_->scene, &q, &pc, callback, context);
}

void MeshShape::for_each_near(const Eigen::Vector3d& p, double radius, NearFunction f, void* context) const noexcept {
  for_each_ahead(p, radius, Eigen::Vector3d::Zero(), f, context);
}

void MeshShape::for_each_ahead(const Eigen::Vector3d& p, double radius, const Eigen::Vector3d& u, NearFunction f,
                               void* context) const noexcept {
  struct Query {
    const MeshShape* mesh;
    Eigen::Vector3d p, u;
    double radius;
    NearFunction f;
    void* context;
  } q{this, p, u, radius, f, context};
  query(
      p, radius,
      [](RTCPointQueryFunctionArguments* args) {
        auto* q = static_cast<Query*>(args->userPtr);
        const Ball& b = q->mesh->balls_[args->primID];
        if (q->mesh->beyond(args->primID, q->p, q->radius) || (b.centre - q->p).dot(q->u) + b.radius <= 0.0)
          return false;  // out of reach, or wholly behind the way
        const auto& t = q->mesh->data_.triangles[args->primID];
        const auto& v = q->mesh->data_.vertices;
        const TrianglePoint c = closest_on_triangle(q->p, v[t[0]], v[t[1]], v[t[2]]);
        if ((c.point - q->p).squaredNorm() <= q->radius * q->radius) q->f(q->context, Near{args->primID, c});
        return false;
      },
      &q);
}

bool MeshShape::nearest(const Eigen::Vector3d& p, double max_distance, Near& out) const noexcept {
  struct Query {
    const MeshShape* mesh;
    Eigen::Vector3d p;
    double best;
    Near* out;
    bool found;
  } q{this, p, max_distance, &out, false};
  query(
      p, max_distance,
      [](RTCPointQueryFunctionArguments* args) {
        auto* q = static_cast<Query*>(args->userPtr);
        if (q->mesh->beyond(args->primID, q->p, q->best)) return false;
        const auto& t = q->mesh->data_.triangles[args->primID];
        const auto& v = q->mesh->data_.vertices;
        const TrianglePoint c = closest_on_triangle(q->p, v[t[0]], v[t[1]], v[t[2]]);
        const double d = (c.point - q->p).norm();
        if (d > q->best) return false;
        q->best = d;
        *q->out = Near{args->primID, c};
        q->found = true;
        const float shrunk = q->mesh->culling_radius(q->p, d);
        if (shrunk < args->query->radius) {
          args->query->radius = shrunk;
          return true;
        }
        return false;
      },
      &q);
  return q.found;
}

Eigen::Vector3d MeshShape::shaded_normal(std::uint32_t triangle, const Eigen::Vector3d& barycentric) const noexcept {
  const auto& t = data_.triangles[triangle];
  const Eigen::Vector3d n =
      barycentric[0] * normals_[t[0]] + barycentric[1] * normals_[t[1]] + barycentric[2] * normals_[t[2]];
  const double length = n.norm();
  return length > 1e-12 ? Eigen::Vector3d(n / length) : face_normals_[triangle];
}

bool MeshShape::own_contact(std::uint32_t triangle, const Eigen::Vector3d& b) const noexcept {
  const auto& convex = convex_[triangle];
  // Edge k runs from corner k to corner k + 1: the point is on it when the third corner's weight is zero.
  const bool on_ab = b[2] == 0.0, on_bc = b[0] == 0.0, on_ca = b[1] == 0.0;
  if (!on_ab && !on_bc && !on_ca) return true;
  return (on_ab && convex[0]) || (on_bc && convex[1]) || (on_ca && convex[2]);
}

Eigen::Vector3d MeshShape::face_normal(std::uint32_t triangle) const noexcept { return face_normals_[triangle]; }

}  // namespace hapticd::scene
