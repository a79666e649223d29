// Shadow-field parameters without a GPU: every range is enforced with the parameter's name in
// the message, the by-name table round-trips, a refused assignment list changes nothing, and the
// fitted grid has probes in front of the surfaces on the scene's bounds.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "gi/shadow_params.h"
#include "gi/shadow_params_table.h"

namespace ddgi::test {
namespace {

TEST(ShadowParamsTest, DefaultsAreValid) {
  EXPECT_TRUE(validate(ShadowFieldParams{}).ok());
}

TEST(ShadowParamsTest, OutOfRangeValuesNameTheParameter) {
  struct Case {
    std::string name;
    std::function<void(ShadowFieldParams&)> break_it;
  };
  const std::vector<Case> cases = {
      {"origin", [](ShadowFieldParams& p) { p.origin.x = std::nanf(""); }},
      {"spacing", [](ShadowFieldParams& p) { p.spacing.y = 0.0f; }},
      {"counts.z", [](ShadowFieldParams& p) { p.counts.z = 0; }},
      {"counts",
       [](ShadowFieldParams& p) {
         p.counts = {256, 256, 256};
       }},
      {"rays_per_probe", [](ShadowFieldParams& p) { p.rays_per_probe = 0; }},
      {"max_lights", [](ShadowFieldParams& p) { p.max_lights = 9; }},
      {"max_ray_distance", [](ShadowFieldParams& p) { p.max_ray_distance = -1.0f; }},
      {"ao_distance", [](ShadowFieldParams& p) { p.ao_distance = 0.0f; }},
      {"texels", [](ShadowFieldParams& p) { p.texels = 65; }},
      {"hysteresis", [](ShadowFieldParams& p) { p.hysteresis = 1.0f; }},
      {"visibility_exponent", [](ShadowFieldParams& p) { p.visibility_exponent = 0.5f; }},
      {"distance_exponent", [](ShadowFieldParams& p) { p.distance_exponent = 2000.0f; }},
      {"backface_distance_scale", [](ShadowFieldParams& p) { p.backface_distance_scale = 2.0f; }},
      {"normal_bias", [](ShadowFieldParams& p) { p.normal_bias = -0.1f; }},
      {"view_bias", [](ShadowFieldParams& p) { p.view_bias = 1.5f; }},
      {"sharpening", [](ShadowFieldParams& p) { p.sharpening = 0.5f; }},
      {"weight_crush_threshold", [](ShadowFieldParams& p) { p.weight_crush_threshold = 2.0f; }},
  };
  for (const Case& c : cases) {
    ShadowFieldParams p;
    c.break_it(p);
    const Status status = validate(p);
    ASSERT_FALSE(status.ok()) << c.name;
    EXPECT_NE(status.error().message.find(c.name), std::string::npos)
        << c.name << ": " << status.error().message;
  }
}

TEST(ShadowParamsTest, TableRoundTripsEveryParameter) {
  ShadowFieldParams p;
  ASSERT_TRUE(apply_shadow_assignments(
                  p, {"origin=1,2,3", "spacing=0.25,0.5,1", "counts=3,4,5", "rays_per_probe=32",
                      "max_lights=8", "overflow=unshadowed", "split_update=on", "texels=8",
                      "hysteresis=0.5", "weighting=wrap", "sharpening=4", "seed=9"})
                  .ok());
  EXPECT_EQ(p.origin, glm::vec3(1, 2, 3));
  EXPECT_EQ(p.counts, glm::ivec3(3, 4, 5));
  EXPECT_EQ(p.max_lights, 8u);
  EXPECT_EQ(p.overflow, ShadowOverflow::kUnshadowed);
  EXPECT_TRUE(p.split_update);
  EXPECT_EQ(p.weighting, ShadowWeighting::kWrap);
  for (const ShadowParamInfo& info : shadow_param_infos()) {
    auto text = get_shadow_param(p, info.name);
    ASSERT_TRUE(text.ok()) << info.name;
    ShadowFieldParams copy;
    ASSERT_TRUE(set_shadow_param(copy, info.name, *text).ok()) << info.name << "=" << *text;
    EXPECT_EQ(*get_shadow_param(copy, info.name), *text) << info.name;
  }
}

TEST(ShadowParamsTest, RefusedAssignmentsChangeNothing) {
  ShadowFieldParams p;
  p.texels = 8;
  for (const std::vector<std::string>& bad :
       std::vector<std::vector<std::string>>{{"texels=32", "no_such=1"},
                                             {"texels=32", "weighting=sine"},
                                             {"texels=32", "hysteresis"},
                                             {"texels=32", "max_lights=0"},
                                             {"counts=1,2"}}) {
    const Status status = apply_shadow_assignments(p, bad);
    EXPECT_FALSE(status.ok()) << bad.back();
    EXPECT_EQ(p.texels, 8u);
  }
}

// box_on_floor's bounds (8 x 1 x 8 m): layers half a cell below the floor and above the cube.
TEST(ShadowParamsTest, FittedGridHasProbesOutsideTheBounds) {
  Bounds bounds;
  bounds.grow({-4.0f, 0.0f, -4.0f});
  bounds.grow({4.0f, 1.0f, 4.0f});
  const ShadowFieldParams p = fit_shadow_grid(bounds, 512);
  ASSERT_TRUE(validate(p).ok());
  for (int axis = 0; axis < 3; ++axis) {
    const float first = p.origin[axis];
    const float last = p.origin[axis] + p.spacing[axis] * float(p.counts[axis] - 1);
    EXPECT_LT(first, bounds.min[axis]) << axis;
    EXPECT_GT(last, bounds.max[axis]) << axis;
  }
  // A flat scene gets one layer on each side of its plane.
  Bounds flat;
  flat.grow({-1.0f, 0.0f, -1.0f});
  flat.grow({1.0f, 0.0f, 1.0f});
  const ShadowFieldParams f = fit_shadow_grid(flat, 64);
  EXPECT_EQ(f.counts.y, 2);
  EXPECT_LT(f.origin.y, 0.0f);
  EXPECT_GT(f.origin.y + f.spacing.y, 0.0f);
}

}  // namespace
}  // namespace ddgi::test
