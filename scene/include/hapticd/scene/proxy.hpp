#pragma once
// The proxy of one device in the haptic scene: a god-object with a radius (Zilles and Salisbury's god-object,
// Ruspini's finite-radius proxy; docs/haptic-scene.md, "The proxy"). The proxy is a sphere that goes where the
// device's point goes (the goal: the handle, or the virtual body in admittance display) as far as the scene lets
// it, never into an object; the device feels a spring (the touched object's stiffness) from its point to the
// proxy, with damping and texture along each contact's normal and Coulomb friction across them.
//
// One update, every cycle:
//   1. the constrained goal: from where the proxy is, the point nearest the goal that satisfies every contact
//      plane (the tangent planes of the objects it touches, several at once: edges, corners, creases - a small
//      quadratic programme solved exactly by an active set), reached by a sweep that stops at the first object on
//      the way (conservative advancement against each object's separating plane: exact for convex shapes, so a
//      thin shell is never passed however fast the hand moves), repeated from there with the new contact;
//   2. friction: the proxy sticks where it is while the tangential offset is within the static cone (mu_s times
//      the depth), else slides and lags the frictionless point by the dynamic cone;
//   3. the force: stiffness x (proxy - goal) + damping and texture along each contact normal, never pulling.
// Real-time safe (update() allocates nothing; configure() does); bounded: at most max_iterations sweeps of at
// most 32 steps over the objects.
#include <Eigen/Core>
#include <array>
#include <vector>

#include "hapticd/scene/scene.hpp"

namespace hapticd::scene {

inline constexpr int kMaxContacts = 16;

struct ProxySettings {
  double radius_m = 0.005;
  int max_iterations = 8;
  // Every material's stiffness is held to this (the device's limit); its damping scaled with it.
  double max_stiffness_n_per_m = 1e9;
  // Meshes: the normal part of the force along the vertex normals interpolated at the contact (a tessellated
  // curve feels smooth) rather than the facet's.
  bool force_shading = true;
};

struct ProxyContact {
  int object = -1;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // the surface point the proxy touches (world)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // the surface's outward normal there
  Eigen::Vector3d force = Eigen::Vector3d::Zero();    // this object's share of the force on the hand
};

struct ProxyState {
  Eigen::Vector3d proxy = Eigen::Vector3d::Zero();  // the proxy's centre (world)
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // on the device's point (world)
  int contact_count = 0;
  std::array<ProxyContact, kMaxContacts> contacts{};
  bool sliding = false;
  int iterations = 0;  // the solve's iterations in this update, the frictionless and the friction pass together: its
                       // work (each a gather and a sweep), at most 2 x max_iterations
};

class GodObject {
 public:
  // Not real-time safe: sizes the per-object flags for `scene` (and for scenes of up to kMaxSceneObjects that
  // rebind() may bring), which must outlive the proxy's use of it.
  void configure(const ProxySettings& settings, const Scene& scene);
  // Real-time safe: renders `scene` from now on (a shared scene's newer version: shared_scene.hpp), keeping the
  // proxy where it is. An object it was leaving out stays left out (by its uid); an object that holds the proxy
  // deeply (made around it) is left out until the proxy has left it, as at reset(). At most kMaxSceneObjects.
  void rebind(const Scene& scene) noexcept;
  // Real-time safe. Starts the proxy at the goal; objects that hold the goal then are left out until it has
  // left them (a device that starts inside an object is not thrown out of it).
  void reset(const Eigen::Vector3d& goal) noexcept;
  // Real-time safe: the proxy after the goal moved to `goal` with `goal_velocity`.
  const ProxyState& update(const Eigen::Vector3d& goal, const Eigen::Vector3d& goal_velocity) noexcept;
  [[nodiscard]] const ProxyState& state() const noexcept { return state_; }
  [[nodiscard]] double stiffness_of(const Material& m) const noexcept;

 private:
  struct Plane {
    Eigen::Vector3d normal;
    double offset;  // normal . x >= offset
    int object;
    SurfacePoint surface;
    Eigen::Vector3d shaded;  // the normal the force is rendered along: a mesh's interpolated vertex normals
  };
  using Planes = std::array<Plane, kMaxContacts>;
  int gather(const Eigen::Vector3d& x, double tolerance, Planes& planes) const noexcept;
  void gather_mesh(std::size_t object, const Eigen::Vector3d& x, double tolerance, Planes& planes,
                   int& count) const noexcept;
  // How far along `u` (unit, world) the proxy at `x` may go, at most `step`, before it meets the mesh `object`.
  [[nodiscard]] double mesh_step(std::size_t object, const Eigen::Vector3d& x, const Eigen::Vector3d& u,
                                 double step) const noexcept;
  [[nodiscard]] static Eigen::Vector3d project(const Eigen::Vector3d& goal, const Planes& planes, int count) noexcept;
  Eigen::Vector3d sweep(const Eigen::Vector3d& from, const Eigen::Vector3d& to, bool& hit) const noexcept;
  // (counts its iterations into `iterations`)
  Eigen::Vector3d solve(const Eigen::Vector3d& start, const Eigen::Vector3d& goal, int& iterations) const noexcept;
  [[nodiscard]] bool skipped(std::size_t object) const noexcept { return ignored_[object] != 0; }

  ProxySettings settings_;
  const Scene* scene_ = nullptr;
  std::vector<char> ignored_;
  std::vector<double> bounds_;
  ProxyState state_;
  double last_stiffness_ = 0.0;
  bool sliding_ = false;
  // Where the proxy would be without friction (the friction cone's centre), kept from one update to the next: the
  // next frictionless solve starts there, not at the proxy - on a dense mesh the proxy held back by friction is
  // many facets from it, and the solve crosses one facet an iteration. At the proxy after reset() and rebind().
  Eigen::Vector3d free_ = Eigen::Vector3d::Zero();
};

}  // namespace hapticd::scene
