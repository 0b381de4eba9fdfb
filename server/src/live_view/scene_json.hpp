#pragma once
// The pieces of a foxglove.SceneUpdate message the live view writes (docs/live-view.md): entities in the world frame
// and their primitives - spheres, cubes, cylinders - as JSON text appended to a string. Shared by the devices'
// scenes (device_view) and the engines' worlds (world_view).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <initializer_list>
#include <string>

#include "hapticd/spatial.hpp"

namespace hapticd::server::live_view::scene_json {

struct Rgba {
  double r, g, b, a;
};
void append_colour(std::string& out, const Rgba& c);
void append_pose(std::string& out, const Eigen::Vector3d& p, const Eigen::Quaterniond& q);
void append_pose(std::string& out, const Pose& p);

// An entity in the world frame: begin_entity opens it (after a ',' unless first), the caller adds its primitive lists
// (",\"spheres\":[...]") and empty_lists the others, end_entity closes it. `metadata`: the entity's key/value
// pairs, already as JSON objects separated by commas ("" none).
void begin_entity(std::string& out, bool first, std::uint64_t time_ns, const std::string& id,
                  const std::string& metadata = {});
void end_entity(std::string& out);
void empty_lists(std::string& out, std::initializer_list<const char*> names);

// Primitives (each after a ',' unless first). A sphere of a diameter at a point; a cylinder from a to b; a
// primitive of a pose and a full size (a sphere's size its three diameters: an ellipsoid; a cylinder's z its length).
void append_sphere(std::string& out, bool first, const Eigen::Vector3d& centre, double diameter, const Rgba& c);
void append_cylinder(std::string& out, bool first, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double diameter,
                     const Rgba& c);
void append_sized(std::string& out, bool first, const Pose& pose, const Eigen::Vector3d& size, const Rgba& c,
                  bool cylinder = false);

}  // namespace hapticd::server::live_view::scene_json
