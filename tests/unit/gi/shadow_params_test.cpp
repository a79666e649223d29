// Shadow-field parameters without a GPU: the by-name table round-trips, a refused assignment
// list changes nothing, and the fitted grid has probes in front of the surfaces on the scene's
// bounds. Every parameter's range is tested from the table itself
// (tests/unit/gi/param_table_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "gi/shadow_params.h"

namespace ddgi::test {
namespace {

TEST(ShadowParamsTest, DefaultsAreValid) {
  EXPECT_TRUE(validate(ShadowFieldParams{}).ok());
}

// Range errors name the field as well as the parameter.
TEST(ShadowParamsTest, RangeErrorsNameTheShadowField) {
  ShadowFieldParams p;
  p.max_lights = 9;
  const Status status = validate(p);
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().message, "shadow field max_lights must be in [1, 8] (got 9)");
}

TEST(ShadowParamsTest, TableRoundTripsEveryParameter) {
  ShadowFieldParams p;
  ASSERT_TRUE(
      shadow_param_table()
          .apply(p, {"origin=1,2,3", "spacing=0.25,0.5,1", "counts=3,4,5", "rays_per_probe=32",
                     "max_lights=8", "overflow=unshadowed", "split_update=on", "texels=8",
                     "hysteresis=0.5", "weighting=wrap", "sharpening=4", "seed=9"})
          .ok());
  EXPECT_EQ(p.origin, glm::vec3(1, 2, 3));
  EXPECT_EQ(p.counts, glm::ivec3(3, 4, 5));
  EXPECT_EQ(p.max_lights, 8u);
  EXPECT_EQ(p.overflow, ShadowOverflow::kUnshadowed);
  EXPECT_TRUE(p.split_update);
  EXPECT_EQ(p.weighting, ShadowWeighting::kWrap);
  const ParamTable<ShadowFieldParams>& table = shadow_param_table();
  for (const ParamSpec<ShadowFieldParams>& spec : table.specs()) {
    auto text = table.get(p, spec.name);
    ASSERT_TRUE(text.ok()) << spec.name;
    ShadowFieldParams copy;
    ASSERT_TRUE(table.set(copy, spec.name, *text).ok()) << spec.name << "=" << *text;
    EXPECT_EQ(*table.get(copy, spec.name), *text) << spec.name;
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
    const Status status = shadow_param_table().apply(p, bad);
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
