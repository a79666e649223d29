// The node hierarchy: transforms composed to exact world positions, scene selection, and
// graphs that are not trees.
#include <cmath>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_support.h"

namespace ddgi {
namespace {

using ::testing::Contains;
using testing::error_of;
using testing::GltfBuilder;
using ::testing::HasSubstr;
using testing::json;
using testing::load_text;

const double kHalfSqrt2 = std::sqrt(0.5);

glm::vec3 world_vertex(const Scene& scene, size_t instance, size_t vertex) {
  const Instance& inst = scene.instances.at(instance);
  const glm::vec3 p =
      scene.meshes.at(static_cast<size_t>(inst.mesh)).primitives.at(0).positions.at(vertex);
  return glm::vec3(inst.transform * glm::vec4(p, 1.0f));
}

void expect_near(const glm::vec3& actual, const glm::vec3& expected) {
  EXPECT_NEAR(actual.x, expected.x, 1e-5f);
  EXPECT_NEAR(actual.y, expected.y, 1e-5f);
  EXPECT_NEAR(actual.z, expected.z, 1e-5f);
}

// triangle_builder's mesh under a parent with its own transform.
GltfBuilder two_level(json parent, json child) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["nodes"] = json::array();
  parent["children"] = {1};
  child["mesh"] = 0;
  b.add_node(parent);
  b.add_node(child);
  b.set_scene({0});
  return b;
}

TEST(Nodes, TrsHierarchyGivesExactWorldPositions) {
  // Parent: T(1,2,3) * R_y(90 deg); child: T(1,0,0) * S(2).
  GltfBuilder b =
      two_level({{"translation", {1, 2, 3}}, {"rotation", {0, kHalfSqrt2, 0, kHalfSqrt2}}},
                {{"translation", {1, 0, 0}}, {"scale", {2, 2, 2}}});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_EQ(scene->instances.size(), 1u);
  EXPECT_EQ(scene->instances[0].node, 1);
  // Vertex (1,0,0): child -> (3,0,0); R_y(90) -> (0,0,-3); + (1,2,3) -> (1,2,0).
  expect_near(world_vertex(*scene, 0, 1), {1, 2, 0});
  // Vertex (0,1,0): child -> (1,2,0); R_y(90) -> (0,2,-1); + (1,2,3) -> (1,4,2).
  expect_near(world_vertex(*scene, 0, 2), {1, 4, 2});
  const Bounds bounds = scene->world_bounds();
  expect_near(bounds.min, {1, 2, 0});
  expect_near(bounds.max, {1, 4, 2});
}

TEST(Nodes, MatrixTransformsAreColumnMajor) {
  GltfBuilder b =
      two_level({{"matrix", {2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 4, 5, 6, 1}}}, json::object());
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  expect_near(world_vertex(*scene, 0, 1), {6, 5, 6});
}

TEST(Nodes, UnnormalizedRotationIsNormalized) {
  GltfBuilder b = two_level({{"rotation", {0, 2 * kHalfSqrt2, 0, 2 * kHalfSqrt2}}}, json::object());
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  expect_near(world_vertex(*scene, 0, 1), {0, 0, -1});
}

TEST(Nodes, DefaultSceneIsChosen) {
  GltfBuilder b = testing::triangle_builder();
  b.add_node({{"mesh", 0}, {"translation", {10, 0, 0}}});
  b.doc()["scenes"].push_back({{"nodes", {1}}});
  b.doc()["scene"] = 1;
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_EQ(scene->instances.size(), 1u);
  EXPECT_EQ(scene->instances[0].node, 1);
  // Without `scene`, scenes[0] is used.
  b.doc().erase("scene");
  scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_EQ(scene->instances.at(0).node, 0);
  b.doc()["scene"] = 2;
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("scene = 2 does not exist (the file has 2 scenes)"));
}

TEST(Nodes, WithoutScenesEveryRootNodeIsUsed) {
  GltfBuilder b = testing::triangle_builder();
  b.doc().erase("scenes");
  b.doc().erase("scene");
  b.add_node({{"mesh", 0}});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_EQ(scene->instances.size(), 2u);
  EXPECT_THAT(scene->warnings, Contains(HasSubstr("no scenes")));
}

TEST(Nodes, CyclesAreRefused) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["nodes"] = {{{"children", {1}}}, {{"children", {0}}, {"mesh", 0}}};
  b.set_scene({});
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("nodes[0] is part of a cycle"));
  b.doc()["nodes"] = {{{"children", {0}}, {"mesh", 0}}};
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("nodes[0] lists itself as a child"));
}

TEST(Nodes, NodeWithTwoParentsIsRefused) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["nodes"] = {{{"children", {2}}}, {{"children", {2}}}, {{"mesh", 0}}};
  b.set_scene({0, 1});
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("nodes[2] has two parents (nodes[0] and nodes[1])"));
  b.doc()["nodes"] = {{{"children", {1, 1}}}, {{"mesh", 0}}};
  b.set_scene({0});
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("nodes[0].children lists nodes[1] twice"));
}

TEST(Nodes, SceneRootsMustBeRootsAndUnique) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["nodes"] = {{{"children", {1}}}, {{"mesh", 0}}};
  b.set_scene({0, 1});
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("scenes[0].nodes lists nodes[1], which is a child of nodes[0]"));
  b.set_scene({0, 0});
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("scenes[0].nodes lists nodes[0] twice"));
}

TEST(Nodes, DepthLimit) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["nodes"] = json::array();
  for (int i = 0; i < 5; ++i) b.add_node(i < 4 ? json{{"children", {i + 1}}} : json{{"mesh", 0}});
  b.set_scene({0});
  SceneLimits limits;
  limits.max_node_depth = 4;
  Result<Scene> scene = load_text(b, limits);
  EXPECT_THAT(error_of(scene), HasSubstr("deeper than 4 levels"));
  limits.max_node_depth = 5;
  EXPECT_TRUE(load_text(b, limits).ok());
}

TEST(Nodes, BadReferencesAndTransformsAreRefused) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["nodes"][0]["mesh"] = 3;
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("nodes[0].mesh = 3 does not exist (the file has 1 meshes)"));
  b = testing::triangle_builder();
  b.doc()["nodes"][0]["camera"] = 0;
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("nodes[0].camera = 0 does not exist"));
  b = testing::triangle_builder();
  b.doc()["nodes"][0]["children"] = {4};
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("nodes[0].children[0] = 4 does not exist"));
  b = testing::triangle_builder();
  b.doc()["scenes"][0]["nodes"] = {-1};
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("scenes[0].nodes[0]: expected a non-negative integer index, got -1"));
  b = testing::triangle_builder();
  b.doc()["nodes"][0]["matrix"] = {1, 0, 0};
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("nodes[0].matrix has 3 values"));
  b = testing::triangle_builder();
  b.doc()["nodes"][0]["rotation"] = {0, 0, 0, 0};
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("nodes[0].rotation is a zero quaternion"));
  b = testing::triangle_builder();
  b.doc()["nodes"][0]["scale"] = {1e300, 1, 1};
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("nodes[0].scale contains a value that is not finite"));
  // Each scale fits a float; their product does not.
  b = two_level({{"scale", {1e30, 1, 1}}}, {{"scale", {1e30, 1, 1}}});
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("nodes[1]: the world transform is not finite"));
}

TEST(Nodes, InstanceLimit) {
  GltfBuilder b = testing::triangle_builder();
  b.add_node({{"mesh", 0}});
  b.set_scene({0, 1});
  SceneLimits limits;
  limits.max_instances = 1;
  EXPECT_THAT(error_of(load_text(b, limits)), HasSubstr("limit of 1 mesh instances"));
}

}  // namespace
}  // namespace ddgi
