// The scene's gate (server/src/gate/scene_gate.hpp) on mesh uploads, with a scene that only counts what reaches it:
// the uploads held together stay within their caps (a client cannot make the server hold more than 2 million
// vertices and triangles in uploads, however it splits them), at most four at once, the parts in order, and the
// uploads end with the claim.
#include "gate/scene_gate.hpp"

#include <gtest/gtest.h>

namespace hapticd::server {
namespace {

class CountingScene final : public SceneService {
 public:
  void configure(const Parameters&, const PluginContext&) override {}
  scene::SharedScene& shared() noexcept override { std::abort(); }
  std::uint64_t add(std::string_view) override { return ++adds; }
  std::uint64_t add_mesh(std::string_view, std::vector<double> v, std::vector<std::uint32_t> t) override {
    vertices = v.size() / 3;
    triangles = t.size() / 3;
    return ++adds;
  }
  void remove(std::string_view) override {}
  void set_material(std::string_view, std::string_view) override {}
  void move(std::string_view, const Pose&) override {}
  [[nodiscard]] std::vector<SceneObjectSummary> objects() const override { return {}; }
  [[nodiscard]] std::vector<SceneContact> contacts() override { return {}; }
  [[nodiscard]] SceneDrawing drawing(std::size_t) override { return {}; }
  std::uint64_t adds = 0;
  std::size_t vertices = 0, triangles = 0;
};

struct Rig {
  CountingScene scene;
  SceneGate gate{scene};
  Sender owner{PeerId::socket(1), 0};
  std::int64_t now = 1'000'000'000;
  std::vector<double> vertices;
  std::vector<std::uint32_t> triangles;
  SceneGate::Reply part(std::string_view name, int part, int parts, std::size_t n_vertices, std::size_t n_triangles) {
    vertices.assign(3 * n_vertices, 0.5);
    triangles.assign(3 * n_triangles, 0);
    SceneGate::Edit e;
    e.op = SceneGate::Op::upload;
    e.upload = name;
    e.part = part;
    e.parts = parts;
    e.vertices = vertices;
    e.triangles = triangles;
    return gate.apply(e, owner, "engine", now += 1'000'000);
  }
  SceneGate::Reply add(std::string_view upload) {
    SceneGate::Edit e;
    e.op = SceneGate::Op::add;
    e.text = R"({"name": "m", "shape": "mesh", "upload": "m"})";
    e.upload = upload;
    return gate.apply(e, owner, "engine", now += 100'000'000);
  }
  SceneGate::Reply op(SceneGate::Op o) {
    SceneGate::Edit e;
    e.op = o;
    return gate.apply(e, owner, "engine", now += 1'000'000);
  }
};

TEST(SceneGate, UploadsHeldTogetherStayWithinTheirCaps) {
  Rig rig;
  ASSERT_TRUE(rig.op(SceneGate::Op::claim).accepted);
  // Three uploads of 600 000 vertices each are held; a fourth that would pass 2 million is dropped, the others kept.
  for (const char* name : {"a", "b", "c"}) ASSERT_TRUE(rig.part(name, 0, 1, 600'000, 10).accepted) << name;
  const SceneGate::Reply over = rig.part("d", 0, 2, 300'000, 10);
  EXPECT_FALSE(over.accepted);
  EXPECT_NE(over.message.find("more than 2000000 vertices"), std::string::npos) << over.message;
  ASSERT_TRUE(rig.add("a").accepted);  // the others are still there, whole
  EXPECT_EQ(rig.scene.vertices, 600'000u);
  // Taken: the room it held is free again.
  EXPECT_TRUE(rig.part("d", 0, 2, 300'000, 10).accepted);
  EXPECT_TRUE(rig.part("d", 1, 2, 300'000, 10).accepted);
  EXPECT_TRUE(rig.add("d").accepted);
  EXPECT_EQ(rig.scene.vertices, 600'000u);
  EXPECT_EQ(rig.scene.triangles, 20u);
}

TEST(SceneGate, AtMostFourUploadsInOrderEndingWithTheClaim) {
  Rig rig;
  ASSERT_TRUE(rig.op(SceneGate::Op::claim).accepted);
  for (const char* name : {"a", "b", "c", "d"}) ASSERT_TRUE(rig.part(name, 0, 3, 3, 1).accepted) << name;
  EXPECT_FALSE(rig.part("e", 0, 1, 3, 1).accepted);  // a fifth
  EXPECT_FALSE(rig.part("a", 2, 3, 3, 1).accepted);  // part 2 before 1: "a" is dropped
  EXPECT_FALSE(rig.part("a", 1, 3, 3, 1).accepted);  // and so its part 1 has nothing to follow
  EXPECT_FALSE(rig.add("b").accepted);               // not finished
  EXPECT_TRUE(rig.part("b", 1, 3, 3, 1).accepted);
  EXPECT_TRUE(rig.part("b", 2, 3, 3, 1).accepted);
  EXPECT_TRUE(rig.add("b").accepted);
  EXPECT_EQ(rig.scene.vertices, 9u);
  EXPECT_FALSE(rig.add("b").accepted);  // taken once
  ASSERT_TRUE(rig.part("c", 1, 3, 3, 1).accepted);
  ASSERT_TRUE(rig.part("c", 2, 3, 3, 1).accepted);
  ASSERT_TRUE(rig.op(SceneGate::Op::release).accepted);
  ASSERT_TRUE(rig.op(SceneGate::Op::claim).accepted);
  EXPECT_FALSE(rig.add("c").accepted);  // ended with the claim
  EXPECT_EQ(rig.scene.adds, 1u);
}

}  // namespace
}  // namespace hapticd::server
