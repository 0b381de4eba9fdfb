// The scene file (scene/scene_file.hpp): a good file gives its objects with their shapes, sizes, poses and
// materials; every kind of mistake is refused with the file, the line and the key named.
#include "hapticd/scene/scene_file.hpp"

#include <gtest/gtest.h>

#include <string>

namespace hapticd::scene {
namespace {

std::string error_of(const std::string& text) {
  try {
    (void)parse_scene(text, "s.yaml");
  } catch (const SceneFileError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneFile, AGoodFileGivesEveryObjectItsShapePoseAndMaterial) {
  const Scene s = parse_scene(R"(materials:
  wood: {stiffness: 3000, damping: 8, static_friction: 0.5, dynamic_friction: 0.3, texture_amplitude: 0.0002, texture_period: 0.003}
objects:
  - {name: floor, shape: plane, position: [0, 0, -0.1]}
  - {name: wall, shape: plane, position: [0.1, 0, 0], normal: [-1, 0, 0], material: wood}
  - {name: table, shape: box, size: [0.4, 0.2, 0.02], position: [0, 0, -0.05], rpy_deg: [0, 0, 90], material: wood}
  - {name: ball, shape: sphere, radius: 0.03, material: {stiffness: 1000}}
  - {name: bar, shape: capsule, radius: 0.01, length: 0.1, quaternion: [1, 0, 0, 0]}
  - {name: post, shape: cylinder, radius: 0.02, length: 0.08}
)",
                              "s.yaml");
  ASSERT_EQ(s.objects.size(), 6u);
  EXPECT_EQ(s.objects[1].name, "wall");
  EXPECT_TRUE((s.objects[1].pose.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d(-1, 0, 0)));
  EXPECT_EQ(s.objects[1].material.stiffness_n_per_m, 3000);
  EXPECT_EQ(s.objects[2].shape.half_extents, Eigen::Vector3d(0.2, 0.1, 0.01));
  EXPECT_TRUE((s.objects[2].pose.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_EQ(s.objects[3].material.stiffness_n_per_m, 1000);
  EXPECT_EQ(s.objects[4].shape.half_length, 0.05);
  EXPECT_EQ(s.objects[5].shape.kind, ShapeKind::cylinder);
  EXPECT_EQ(s.objects[0].material.stiffness_n_per_m, Material{}.stiffness_n_per_m);
}

TEST(SceneFile, EveryMistakeNamesTheFileTheLineAndTheKey) {
  struct Case {
    const char* text;
    const char* expected;
  };
  const Case cases[] = {
      {"objects:\n  - {name: a, shape: sphere}\n", "s.yaml:2: objects[0].radius: missing"},
      {"objects:\n  - {name: a, shape: sphere, radius: 0}\n", "s.yaml:2: objects[0].radius: must be positive"},
      {"objects:\n  - {name: a, shape: sphere, radius: .nan}\n", "objects[0].radius: must be finite"},
      {"objects:\n  - {name: a, shape: cone, radius: 1}\n", "objects[0].shape: 'cone' is not"},
      {"objects:\n  - {name: a, shape: box, size: [1, 1]}\n", "objects[0].size: must be a list of 3 numbers"},
      {"objects:\n  - {name: a, shape: box, size: [1, 1, 1], radius: 2}\n", "objects[0].radius: a box has no radius"},
      {"objects:\n  - {name: a, shape: plane, colour: red}\n", "s.yaml:2: objects[0].colour: unknown key"},
      {"objects:\n  - {name: a, shape: plane, material: steel}\n", "objects[0].material: no material 'steel'"},
      {"objects:\n  - {name: a, shape: plane}\n  - {name: a, shape: plane}\n",
       "s.yaml:3: objects[1].name: 'a' is taken"},
      {"materials:\n  m: {stiffness: 1, static_friction: 0.2, dynamic_friction: 0.5}\nobjects: []\n",
       "s.yaml:2: materials.m.dynamic_friction: must not exceed static_friction"},
      {"objects:\n  - {name: a, shape: plane, normal: [0, 0, 0]}\n", "objects[0].normal: must not be zero"},
      {"objects:\n  - {name: a, shape: plane, normal: [0, 0, 1], rpy_deg: [0, 0, 0]}\n", "give one of"},
      {"objects: [\n", "s.yaml:"},
      {"", "the scene file is empty"},
      {"things: []\n", "scene.things: unknown key"},
      {"objects:\n  - {name: a, shape: convex_hull, points: [[0, 0, 0]], upload: a}\n",
       "s.yaml:2: objects[0].upload: names no upload here"},
      {"objects:\n  - {name: a, shape: mesh, file: a.obj, upload: a}\n", "objects[0].upload: names no upload here"},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(c.text);
    EXPECT_NE(e.find(c.expected), std::string::npos) << c.text << " -> " << e;
  }
}

TEST(SceneFile, MoreObjectsThanTheCapAreRefused) {
  std::string text = "objects:\n";
  for (std::size_t i = 0; i <= kMaxSceneObjects; ++i) text += "  - {name: o" + std::to_string(i) + ", shape: plane}\n";
  EXPECT_NE(error_of(text).find("at most 1024"), std::string::npos) << error_of(text);
}

}  // namespace
}  // namespace hapticd::scene
