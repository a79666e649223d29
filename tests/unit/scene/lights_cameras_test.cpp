// KHR_lights_punctual lights and perspective cameras, placed by their nodes.
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

void expect_near(const glm::vec3& actual, const glm::vec3& expected) {
  EXPECT_NEAR(actual.x, expected.x, 1e-5f);
  EXPECT_NEAR(actual.y, expected.y, 1e-5f);
  EXPECT_NEAR(actual.z, expected.z, 1e-5f);
}

GltfBuilder with_lights(json lights) {
  GltfBuilder b = testing::triangle_builder();
  b.use_extension("KHR_lights_punctual");
  b.doc()["extensions"]["KHR_lights_punctual"]["lights"] = lights;
  return b;
}

int add_light_node(GltfBuilder& b, int light, json node) {
  node["extensions"]["KHR_lights_punctual"]["light"] = light;
  const int index = b.add_node(node);
  b.doc()["scenes"][0]["nodes"].push_back(index);
  return index;
}

TEST(Lights, PunctualLightsArePlacedByTheirNodes) {
  GltfBuilder b =
      with_lights({{{"type", "point"}, {"color", {1, 0.5, 0.25}}, {"intensity", 20}, {"range", 7}},
                   {{"type", "spot"},
                    {"intensity", 100},
                    {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}},
                   {{"type", "directional"}, {"intensity", 3}, {"name", "sun"}}});
  add_light_node(b, 0, {{"translation", {1, 2, 3}}});
  // Turned -90 deg about X: the spot's -Z then points down (-Y).
  const int spot = add_light_node(b, 1, {{"translation", {0, 4, 0}}});
  b.doc()["nodes"][spot]["rotation"] = {-kHalfSqrt2, 0, 0, kHalfSqrt2};
  add_light_node(b, 2, {{"rotation", {0, kHalfSqrt2, 0, kHalfSqrt2}}});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_EQ(scene->lights.size(), 3u);

  const Light& point = scene->lights[0];
  EXPECT_EQ(point.type, LightType::kPoint);
  expect_near(point.position, {1, 2, 3});
  expect_near(point.color, {1, 0.5f, 0.25f});
  EXPECT_FLOAT_EQ(point.intensity, 20.0f);
  EXPECT_FLOAT_EQ(point.range, 7.0f);

  const Light& spot_light = scene->lights[1];
  EXPECT_EQ(spot_light.type, LightType::kSpot);
  expect_near(spot_light.position, {0, 4, 0});
  expect_near(spot_light.direction, {0, -1, 0});
  EXPECT_FLOAT_EQ(spot_light.inner_cone_angle, 0.2f);
  EXPECT_FLOAT_EQ(spot_light.outer_cone_angle, 0.5f);
  EXPECT_FLOAT_EQ(spot_light.range, 0.0f);  // absent: infinite

  const Light& sun = scene->lights[2];
  EXPECT_EQ(sun.type, LightType::kDirectional);
  EXPECT_EQ(sun.name, "sun");
  expect_near(sun.direction, {-1, 0, 0});  // R_y(90) turns -Z into -X
  expect_near(sun.color, {1, 1, 1});
  EXPECT_TRUE(scene->has_any_light());
}

TEST(Lights, SpotDefaultsFollowTheSpec) {
  GltfBuilder b = with_lights({{{"type", "spot"}, {"spot", json::object()}}});
  add_light_node(b, 0, json::object());
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_FLOAT_EQ(scene->lights.at(0).inner_cone_angle, 0.0f);
  EXPECT_NEAR(scene->lights.at(0).outer_cone_angle, M_PI / 4, 1e-6);
}

TEST(Lights, InvalidLightsAreRefused) {
  GltfBuilder b = with_lights({{{"type", "area"}}});
  add_light_node(b, 0, json::object());
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("lights[0].type 'area'"));

  b = with_lights({{{"type", "point"}, {"intensity", -1}}});
  add_light_node(b, 0, json::object());
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("lights[0].intensity"));

  b = with_lights(
      {{{"type", "spot"}, {"spot", {{"innerConeAngle", 0.6}, {"outerConeAngle", 0.5}}}}});
  add_light_node(b, 0, json::object());
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("cone angles"));

  // Finite as a double but infinite as the float the Scene stores.
  b = with_lights({{{"type", "point"}, {"intensity", 1e300}}});
  add_light_node(b, 0, json::object());
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("lights[0].intensity must be a finite number"));

  b = with_lights({{{"type", "point"}, {"color", {1, 1}}}});
  add_light_node(b, 0, json::object());
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("lights[0].color has 2 values"));

  b = with_lights({{{"type", "point"}}});
  add_light_node(b, 4, json::object());
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("nodes[1].extensions.KHR_lights_punctual.light = 4 does not exist"));
}

TEST(Lights, LightLimit) {
  GltfBuilder b = with_lights({{{"type", "point"}}});
  add_light_node(b, 0, json::object());
  add_light_node(b, 0, json::object());
  SceneLimits limits;
  limits.max_lights = 1;
  EXPECT_THAT(error_of(load_text(b, limits)), HasSubstr("more than the limit of 1 lights"));
  limits.max_lights = 2;
  EXPECT_TRUE(load_text(b, limits).ok());
}

TEST(Lights, ZeroScaleLightIsSkippedWithAWarning) {
  GltfBuilder b = with_lights({{{"type", "directional"}}});
  add_light_node(b, 0, {{"scale", {0, 0, 0}}});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_TRUE(scene->lights.empty());
  EXPECT_THAT(scene->warnings, Contains(HasSubstr("light skipped")));
}

TEST(Lights, SceneWithoutAnyLightLoadsWithAWarning) {
  Result<Scene> scene = load_text(testing::triangle_builder());
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_FALSE(scene->has_any_light());
  EXPECT_THAT(scene->warnings, Contains(HasSubstr("no light")));
}

TEST(Lights, UnsupportedRequiredExtensionIsRefused) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("extensionsRequired lists 'KHR_draco_mesh_compression'"));
  b.doc()["extensionsRequired"] = {"KHR_lights_punctual", "KHR_mesh_quantization"};
  EXPECT_TRUE(load_text(b).ok());
}

TEST(Cameras, PerspectiveCameraFromItsNode) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["cameras"] = {{{"type", "perspective"},
                         {"name", "main"},
                         {"perspective", {{"yfov", 0.6}, {"znear", 0.05}, {"aspectRatio", 1.5}}}}};
  // Turned 90 deg about Y and scaled unevenly: the basis must come out orthonormal.
  const int node = b.add_node({{"camera", 0},
                               {"translation", {1, 2, 3}},
                               {"rotation", {0, kHalfSqrt2, 0, kHalfSqrt2}},
                               {"scale", {3, 2, 1}}});
  b.doc()["scenes"][0]["nodes"].push_back(node);
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_EQ(scene->cameras.size(), 1u);
  const Camera& camera = scene->cameras[0];
  EXPECT_EQ(camera.name, "main");
  expect_near(camera.position, {1, 2, 3});
  expect_near(camera.forward, {-1, 0, 0});
  expect_near(camera.up, {0, 1, 0});
  EXPECT_FLOAT_EQ(camera.yfov, 0.6f);
  EXPECT_FLOAT_EQ(camera.znear, 0.05f);
}

TEST(Cameras, OrthographicCamerasAreSkippedAndBadOnesRefused) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["cameras"] = {
      {{"type", "orthographic"},
       {"orthographic", {{"xmag", 1}, {"ymag", 1}, {"znear", 0.1}, {"zfar", 10}}}}};
  b.doc()["nodes"][0]["camera"] = 0;
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_TRUE(scene->cameras.empty());
  EXPECT_THAT(scene->warnings, Contains(HasSubstr("orthographic camera skipped")));

  b.doc()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0}, {"znear", 0.1}}}}};
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("cameras[0].perspective.yfov"));
  b.doc()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 1}, {"znear", 0}}}}};
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("cameras[0].perspective.znear"));
}

}  // namespace
}  // namespace ddgi
