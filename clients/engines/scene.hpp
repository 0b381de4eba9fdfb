#pragma once
// The example impedance-type engine's virtual world: rigid objects (a wall, a box, a sphere) and the proxy
// ("god object") that stays on their surface while the device's handle penetrates. Positions are relative to
// the device's start pose. Header-only so the engine and the tests share it.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace hapticd::examples {

struct Wall {  // half-space: free where (x - point) . normal >= 0
  Eigen::Vector3d point, normal;
};
struct Box {  // axis-aligned, solid
  Eigen::Vector3d centre, half_size;
};
struct Sphere {
  Eigen::Vector3d centre;
  double radius;
};

struct Scene {
  std::vector<Wall> walls;
  std::vector<Box> boxes;
  std::vector<Sphere> spheres;

  // The proxy for a handle at x: x itself in free space, else the nearest point on the surface of what it is
  // inside (a few passes settle contacts with two objects).
  [[nodiscard]] Eigen::Vector3d proxy(const Eigen::Vector3d& x) const {
    Eigen::Vector3d p = x;
    for (int pass = 0; pass < 4; ++pass) {
      bool moved = false;
      for (const Wall& w : walls) {
        const double d = (p - w.point).dot(w.normal);
        if (d < 0.0) {
          p -= d * w.normal;
          moved = true;
        }
      }
      for (const Box& b : boxes) {
        const Eigen::Vector3d r = p - b.centre;
        if ((r.cwiseAbs().array() < b.half_size.array()).all()) {
          Eigen::Index axis = 0;
          (b.half_size - r.cwiseAbs()).minCoeff(&axis);  // leave through the nearest face
          p[axis] = b.centre[axis] + std::copysign(b.half_size[axis], r[axis]);
          moved = true;
        }
      }
      for (const Sphere& s : spheres) {
        const Eigen::Vector3d r = p - s.centre;
        const double n = r.norm();
        if (n < s.radius) {
          p = s.centre + (n > 1e-12 ? Eigen::Vector3d(r / n) : Eigen::Vector3d::UnitZ()) * s.radius;
          moved = true;
        }
      }
      if (!moved) break;
    }
    return p;
  }

  // The proxy's velocity for a handle at x moving with v whose proxy is p: the handle's velocity in free space;
  // on a surface the part along the surface (the proxy slides with the handle, it does not enter).
  [[nodiscard]] static Eigen::Vector3d proxy_velocity(const Eigen::Vector3d& x, const Eigen::Vector3d& p,
                                                      const Eigen::Vector3d& v) {
    const Eigen::Vector3d out = p - x;
    if (out.norm() < 1e-12) return v;
    const Eigen::Vector3d n = out.normalized();
    return v - v.dot(n) * n;
  }

  // Which object the handle at x is in contact with ("" none).
  [[nodiscard]] std::string contact(const Eigen::Vector3d& x) const {
    for (const Wall& w : walls)
      if ((x - w.point).dot(w.normal) < 0.0) return "wall";
    for (const Box& b : boxes)
      if (((x - b.centre).cwiseAbs().array() < b.half_size.array()).all()) return "box";
    for (const Sphere& s : spheres)
      if ((x - s.centre).norm() < s.radius) return "sphere";
    return "";
  }
};

// The demo's scene relative to the start position (mm): a wall at x = +30 facing -x; a 40 mm cube centred
// at (30, -55, 0), its top face at y = -35; a sphere of radius 25 centred at (-30, -35, 0). A push along +x
// from the start meets the wall; from there a push along -y lands on the cube; from there a push along -x
// meets the sphere.
inline Scene demo_scene() {
  Scene s;
  s.walls.push_back({Eigen::Vector3d(0.03, 0.0, 0.0), Eigen::Vector3d(-1.0, 0.0, 0.0)});
  s.boxes.push_back({Eigen::Vector3d(0.03, -0.055, 0.0), Eigen::Vector3d(0.02, 0.02, 0.02)});
  s.spheres.push_back({Eigen::Vector3d(-0.030, -0.035, 0.0), 0.025});
  return s;
}

}  // namespace hapticd::examples
