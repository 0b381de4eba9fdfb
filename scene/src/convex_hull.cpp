#include "hapticd/scene/convex_hull.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>

namespace hapticd::scene {
namespace {

using Vec = Eigen::Vector3d;

struct Face {
  std::array<std::uint32_t, 3> v{};  // wound outwards
  Vec normal = Vec::Zero();          // unit, outwards
  double offset = 0.0;               // normal . x on the plane
  std::vector<std::uint32_t> outside;
  std::uint64_t visited = 0;  // the point whose visible set last took this face in
  bool alive = true;
  [[nodiscard]] double distance(const Vec& p) const { return normal.dot(p) - offset; }
};

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) { return (static_cast<std::uint64_t>(a) << 32) | b; }

class Hull {
 public:
  Hull(const std::vector<Vec>& points, double tolerance) : p_(points), eps_(tolerance) {}

  // The first tetrahedron from extreme points; false when the set has no volume.
  bool start() {
    const std::size_t n = p_.size();
    std::uint32_t a = 0, b = 0;
    for (std::uint32_t i = 1; i < n; ++i)
      if (p_[i].x() < p_[a].x()) a = i;
    double best = -1.0;
    for (std::uint32_t i = 0; i < n; ++i)
      if (const double d = (p_[i] - p_[a]).squaredNorm(); d > best) best = d, b = i;
    if (std::sqrt(best) <= eps_) return false;
    const Vec ab = (p_[b] - p_[a]).normalized();
    std::uint32_t c = 0;
    best = -1.0;
    for (std::uint32_t i = 0; i < n; ++i)
      if (const double d = (p_[i] - p_[a]).cross(ab).norm(); d > best) best = d, c = i;
    if (best <= eps_) return false;
    const Vec plane = (p_[b] - p_[a]).cross(p_[c] - p_[a]).normalized();
    std::uint32_t d = 0;
    best = -1.0;
    for (std::uint32_t i = 0; i < n; ++i)
      if (const double h = std::abs(plane.dot(p_[i] - p_[a])); h > best) best = h, d = i;
    if (best <= eps_) return false;
    // Wound so that each face looks away from the fourth point.
    if (plane.dot(p_[d] - p_[a]) > 0.0) std::swap(b, c);
    add_face(a, b, c);
    add_face(a, d, b);
    add_face(b, d, c);
    add_face(c, d, a);
    std::vector<std::uint32_t> rest;
    rest.reserve(n);
    for (std::uint32_t i = 0; i < n; ++i)
      if (i != a && i != b && i != c && i != d) rest.push_back(i);
    assign(rest, 0);
    return true;
  }

  void run() {
    for (std::size_t f = 0; f < faces_.size(); ++f) {
      // Faces are appended as they are made: a face's list is worked off once it is reached, or it died before.
      while (faces_[f].alive && !faces_[f].outside.empty()) add_point(f);
    }
  }

  [[nodiscard]] TriangleMeshData mesh() const {
    TriangleMeshData out;
    std::unordered_map<std::uint32_t, std::uint32_t> index;
    for (const Face& f : faces_) {
      if (!f.alive) continue;
      std::array<std::uint32_t, 3> t{};
      for (int k = 0; k < 3; ++k) {
        const auto [it, fresh] = index.emplace(f.v[static_cast<std::size_t>(k)], out.vertices.size());
        if (fresh) out.vertices.push_back(p_[f.v[static_cast<std::size_t>(k)]]);
        t[static_cast<std::size_t>(k)] = it->second;
      }
      out.triangles.push_back(t);
    }
    return out;
  }

 private:
  void add_face(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    Face f;
    f.v = {a, b, c};
    const Vec n = (p_[b] - p_[a]).cross(p_[c] - p_[a]);
    f.normal = n.norm() > 0.0 ? Vec(n.normalized()) : Vec::UnitZ();
    f.offset = f.normal.dot(p_[a]);
    const auto index = static_cast<std::uint32_t>(faces_.size());
    for (int k = 0; k < 3; ++k) edges_[edge_key(f.v[static_cast<std::size_t>(k)], f.v[(k + 1) % 3])] = index;
    faces_.push_back(std::move(f));
  }

  // Each point goes to the first face from `first` on that it lies outside of; the others are inside.
  void assign(const std::vector<std::uint32_t>& points, std::size_t first) {
    for (std::uint32_t i : points) {
      for (std::size_t f = first; f < faces_.size(); ++f) {
        if (faces_[f].alive && faces_[f].distance(p_[i]) > eps_) {
          faces_[f].outside.push_back(i);
          break;
        }
      }
    }
  }

  void add_point(std::size_t face) {
    // The farthest point outside the face.
    std::vector<std::uint32_t>& out = faces_[face].outside;
    const auto far = std::max_element(out.begin(), out.end(), [&](std::uint32_t x, std::uint32_t y) {
      return faces_[face].distance(p_[x]) < faces_[face].distance(p_[y]);
    });
    const std::uint32_t eye = *far;
    // The faces it sees: connected, found across their edges from this one.
    // (A stamp per face rather than a flag array cleared for every point added.)
    const std::uint64_t stamp = ++visit_;
    std::vector<std::size_t> visible{face};
    faces_[face].visited = stamp;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> horizon;
    for (std::size_t k = 0; k < visible.size(); ++k) {
      const Face& f = faces_[visible[k]];
      for (int e = 0; e < 3; ++e) {
        const std::uint32_t a = f.v[static_cast<std::size_t>(e)], b = f.v[(e + 1) % 3];
        const auto twin = edges_.find(edge_key(b, a));
        if (twin == edges_.end()) {  // (a closed hull has every edge's twin; should it not, the edge is a border)
          horizon.emplace_back(a, b);
          continue;
        }
        const std::size_t g = twin->second;
        if (faces_[g].visited == stamp) continue;
        if (faces_[g].distance(p_[eye]) > eps_) {
          faces_[g].visited = stamp;
          visible.push_back(g);
        } else {
          horizon.emplace_back(a, b);
        }
      }
    }
    // Horizon edges seen twice (from two visible faces) cannot happen: each belongs to one visible face.
    std::vector<std::uint32_t> orphans;
    for (std::size_t v : visible) {
      Face& f = faces_[v];
      f.alive = false;
      for (int e = 0; e < 3; ++e) edges_.erase(edge_key(f.v[static_cast<std::size_t>(e)], f.v[(e + 1) % 3]));
      for (std::uint32_t i : f.outside)
        if (i != eye) orphans.push_back(i);
      f.outside.clear();
      f.outside.shrink_to_fit();
    }
    const std::size_t first = faces_.size();
    for (const auto& [a, b] : horizon) add_face(a, b, eye);
    assign(orphans, first);
  }

  const std::vector<Vec>& p_;
  double eps_;
  std::vector<Face> faces_;
  std::uint64_t visit_ = 0;
  std::unordered_map<std::uint64_t, std::size_t> edges_;  // directed edge -> the alive face that has it
};

}  // namespace

TriangleMeshData convex_hull(const std::vector<Eigen::Vector3d>& points, const std::string& name) {
  if (points.size() < 4)
    throw std::invalid_argument(name + ": a convex hull needs at least 4 points, not " + std::to_string(points.size()));
  if (points.size() > kMaxHullPoints)
    throw std::invalid_argument(name + ": " + std::to_string(points.size()) + " points: a convex hull takes at most " +
                                std::to_string(kMaxHullPoints));
  Eigen::Vector3d low = points.front(), high = points.front();
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite())
      throw std::invalid_argument(name + ": point " + std::to_string(i) + " has a coordinate that is not finite");
    low = low.cwiseMin(points[i]);
    high = high.cwiseMax(points[i]);
  }
  const double extent = (high - low).norm();
  Hull hull(points, std::max(extent * 1e-9, 1e-12));
  if (!hull.start())
    throw std::invalid_argument(name + ": the points have no volume (all on one plane or line): no convex hull");
  hull.run();
  return hull.mesh();
}

}  // namespace hapticd::scene
