// The haptic scene's choice of acceleration structure (docs/haptic-scene.md, "Choosing the mesh library"): the
// candidates - Embree (rtcPointQuery), Bullet (btBvhTriangleMeshShape::processAllTriangles) and FCL (BVHModel
// with OBBRSS, collide against a sphere) - on the one query the proxy asks of a mesh: every triangle within a
// radius of a point (the contact planes within the proxy's radius, the sweep's candidates within radius + step),
// each triangle's exact closest point computed by the same code (scene/triangle.hpp). Meshes: icospheres of 5 cm
// radius at 1 280, 81 920 and 1 310 720 triangles; 20 000 query points where a 5 mm proxy's centre is, 5 to 6 mm
// outside the surface (seeded); query radius 5.5 mm: the proxy's radius and a sweep of 0.5 mm (1 m/s at 2 kHz). Per
// query p50 and p99 (each query timed on the monotonic clock), the build time, and side by side the reference the
// figures are read against: the analytic sphere's closest point for the same points. Every library must find the same
// triangles (checked).
//   scene_mesh_index [LEVELS...]   (icosphere subdivision levels; default 3 6 8)
#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btTriangleCallback.h>
#include <BulletCollision/CollisionShapes/btTriangleIndexVertexArray.h>
#include <embree3/rtcore.h>
#include <fcl/fcl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "hapticd/scene/mesh_file.hpp"
#include "hapticd/scene/shape.hpp"
#include "hapticd/scene/triangle.hpp"

namespace {

using hapticd::scene::closest_on_triangle;
using Clock = std::chrono::steady_clock;

struct Mesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<unsigned, 3>> triangles;
};

Mesh icosphere(int level, double radius) {
  const hapticd::scene::TriangleMeshData data = hapticd::scene::icosphere_mesh(level, radius);
  Mesh m;
  m.vertices = data.vertices;
  for (const auto& t : data.triangles) m.triangles.push_back({t[0], t[1], t[2]});
  return m;
}

// What a near query finds: how many triangles within the radius, and the nearest distance.
struct Found {
  int count = 0;
  double nearest = 1e9;
  void add(const Mesh& m, unsigned tri, const Eigen::Vector3d& p, double radius) {
    const auto& t = m.triangles[tri];
    const double d = (closest_on_triangle(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]).point - p).norm();
    if (d <= radius) {
      ++count;
      nearest = std::min(nearest, d);
    }
  }
};

class EmbreeIndex {
 public:
  explicit EmbreeIndex(const Mesh& m) : mesh_(m) {
    device_ = rtcNewDevice("threads=1");
    scene_ = rtcNewScene(device_);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.vertices.size()));
    for (std::size_t i = 0; i < m.vertices.size(); ++i)
      for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(m.vertices[i][k]);
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), m.triangles.size()));
    for (std::size_t i = 0; i < m.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) idx[3 * i + k] = m.triangles[i][k];
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene_, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene_);
  }
  ~EmbreeIndex() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  Found near(const Eigen::Vector3d& p, double radius) const {
    struct Ctx {
      const Mesh* mesh;
      Eigen::Vector3d p;
      double radius;
      Found found;
    } ctx{&mesh_, p, radius, {}};
    RTCPointQuery q;
    q.x = static_cast<float>(p.x());
    q.y = static_cast<float>(p.y());
    q.z = static_cast<float>(p.z());
    q.radius = static_cast<float>(radius) * 1.0001f;
    q.time = 0.0f;
    RTCPointQueryContext qc;
    rtcInitPointQueryContext(&qc);
    rtcPointQuery(
        scene_, &q, &qc,
        [](RTCPointQueryFunctionArguments* a) {
          auto* c = static_cast<Ctx*>(a->userPtr);
          c->found.add(*c->mesh, a->primID, c->p, c->radius);
          return false;
        },
        &ctx);
    return ctx.found;
  }

 private:
  const Mesh& mesh_;
  RTCDevice device_;
  RTCScene scene_;
};

class BulletIndex {
 public:
  explicit BulletIndex(const Mesh& m) : mesh_(m) {
    for (const auto& v : m.vertices) vertices_.push_back(btVector3(v.x(), v.y(), v.z()));
    for (const auto& t : m.triangles) indices_.insert(indices_.end(), {int(t[0]), int(t[1]), int(t[2])});
    array_ = std::make_unique<btTriangleIndexVertexArray>(static_cast<int>(m.triangles.size()), indices_.data(),
                                                          3 * sizeof(int), static_cast<int>(vertices_.size()),
                                                          &vertices_[0][0], sizeof(btVector3));
    shape_ = std::make_unique<btBvhTriangleMeshShape>(array_.get(), true, true);
  }
  Found near(const Eigen::Vector3d& p, double radius) const {
    struct Callback : btTriangleCallback {
      const Mesh* mesh;
      Eigen::Vector3d p;
      double radius;
      Found found;
      void processTriangle(btVector3*, int, int triangle) override {
        found.add(*mesh, static_cast<unsigned>(triangle), p, radius);
      }
    } cb;
    cb.mesh = &mesh_;
    cb.p = p;
    cb.radius = radius;
    const btVector3 lo(p.x() - radius, p.y() - radius, p.z() - radius),
        hi(p.x() + radius, p.y() + radius, p.z() + radius);
    shape_->processAllTriangles(&cb, lo, hi);
    return cb.found;
  }

 private:
  const Mesh& mesh_;
  btAlignedObjectArray<btVector3> vertices_;
  std::vector<int> indices_;
  std::unique_ptr<btTriangleIndexVertexArray> array_;
  std::unique_ptr<btBvhTriangleMeshShape> shape_;
};

class FclIndex {
 public:
  explicit FclIndex(const Mesh& m) : mesh_(m) {
    std::vector<fcl::Vector3d> v(m.vertices.begin(), m.vertices.end());
    std::vector<fcl::Triangle> t;
    for (const auto& tri : m.triangles) t.emplace_back(tri[0], tri[1], tri[2]);
    auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
    model->beginModel();
    model->addSubModel(v, t);
    model->endModel();
    object_ = std::make_unique<fcl::CollisionObjectd>(model);
  }
  Found near(const Eigen::Vector3d& p, double radius) const {
    fcl::CollisionObjectd ball(std::make_shared<fcl::Sphered>(radius), fcl::Transform3d(Eigen::Translation3d(p)));
    fcl::CollisionRequestd request(100000, false);
    fcl::CollisionResultd result;
    fcl::collide(&ball, object_.get(), request, result);
    Found found;
    for (std::size_t i = 0; i < result.numContacts(); ++i) {
      const fcl::Contactd& c = result.getContact(i);
      found.add(mesh_, static_cast<unsigned>(c.o1 == object_->collisionGeometry().get() ? c.b1 : c.b2), p, radius);
    }
    return found;
  }

 private:
  const Mesh& mesh_;
  std::unique_ptr<fcl::CollisionObjectd> object_;
};

struct Figures {
  double p50_us, p99_us;
};

template <class Query>
Figures time_queries(const std::vector<Eigen::Vector3d>& points, Query&& q, std::vector<Found>* out) {
  std::vector<double> us;
  us.reserve(points.size());
  for (const auto& p : points) {
    const auto t0 = Clock::now();
    Found f = q(p);
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
    if (out) out->push_back(f);
  }
  std::sort(us.begin(), us.end());
  return {us[us.size() / 2], us[us.size() * 99 / 100]};
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> levels;
  for (int i = 1; i < argc; ++i) levels.push_back(std::atoi(argv[i]));
  if (levels.empty()) levels = {3, 6, 8};
  const double radius = 0.05, query = 0.0055;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), gap(0.005, 0.006);
  std::vector<Eigen::Vector3d> points;
  while (points.size() < 20000) {
    Eigen::Vector3d d(unit(rng), unit(rng), unit(rng));
    if (d.norm() < 0.1 || d.norm() > 1.0) continue;
    points.push_back(d.normalized() * (radius + gap(rng)));
  }
  const hapticd::scene::Shape sphere{hapticd::scene::ShapeKind::sphere, radius, 0.0, {}, nullptr};
  std::printf(
      "| triangles | library | build (ms) | near query p50 (us) | p99 (us) | p50 / analytic sphere | triangles found "
      "|\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (int level : levels) {
    const Mesh mesh = icosphere(level, radius);
    const Figures reference = time_queries(
        points,
        [&](const Eigen::Vector3d& p) {
          Found f;
          f.nearest = hapticd::scene::closest_point(sphere, p).distance;
          f.count = f.nearest <= query ? 1 : 0;
          return f;
        },
        nullptr);
    std::vector<Found> first;
    auto report = [&](const char* name, auto& index, double build_ms) {
      std::vector<Found> found;
      const Figures f = time_queries(
          points, [&](const Eigen::Vector3d& p) { return index.near(p, query); }, &found);
      if (first.empty()) {
        first = found;
      } else {
        for (std::size_t i = 0; i < found.size(); ++i)
          if (found[i].count != first[i].count) {
            int brute = 0;
            for (unsigned t = 0; t < mesh.triangles.size(); ++t) {
              Found b;
              b.add(mesh, t, points[i], query);
              brute += b.count;
            }
            std::fprintf(stderr, "%s finds %d triangles near point %zu, the first library %d, all of them %d\n", name,
                         found[i].count, i, first[i].count, brute);
            std::exit(1);
          }
      }
      double mean = 0.0;
      for (const auto& x : found) mean += x.count / static_cast<double>(found.size());
      std::printf("| %zu | %s | %.1f | %.2f | %.2f | %.1f | %.1f |\n", mesh.triangles.size(), name, build_ms, f.p50_us,
                  f.p99_us, f.p50_us / reference.p50_us, mean);
      std::fflush(stdout);
    };
    auto build = [](auto make) {
      const auto t0 = Clock::now();
      auto index = make();
      return std::make_pair(std::move(index), std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    };
    {
      auto [index, ms] = build([&] { return std::make_unique<EmbreeIndex>(mesh); });
      report("Embree 3.13 (point query)", *index, ms);
    }
    {
      auto [index, ms] = build([&] { return std::make_unique<BulletIndex>(mesh); });
      report("Bullet 3.24 (BVH, triangles in a box)", *index, ms);
    }
    {
      auto [index, ms] = build([&] { return std::make_unique<FclIndex>(mesh); });
      report("FCL 0.7 (OBBRSS, sphere collide)", *index, ms);
    }
    std::printf("| %zu | (analytic sphere, the reference) | - | %.3f | %.3f | 1 | - |\n", mesh.triangles.size(),
                reference.p50_us, reference.p99_us);
  }
  return 0;
}
