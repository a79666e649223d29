// Field parameters: ranges refused with the field's name, grids fitted to bounds, the by-name
// table the CLI and RPC share.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "gi/field_param_table.h"
#include "gi/field_params.h"

namespace ddgi {
namespace {

using ::testing::HasSubstr;

std::string error_of(const IrradianceFieldParams& p) {
  const Status s = validate(p);
  return s.ok() ? "" : s.error().message;
}

TEST(FieldParams, DefaultsAreValid) {
  EXPECT_EQ(error_of(IrradianceFieldParams{}), "");
}

TEST(FieldParams, OutOfRangeValuesNameTheFieldAndRange) {
  struct Case {
    void (*mutate)(IrradianceFieldParams&);
    const char* expected;
  };
  const Case cases[] = {
      {[](IrradianceFieldParams& p) { p.rays_per_probe = 0; },
       "rays_per_probe must be in [1, 1024]"},
      {[](IrradianceFieldParams& p) { p.rays_per_probe = 1025; },
       "rays_per_probe must be in [1, 1024]"},
      {[](IrradianceFieldParams& p) { p.hysteresis = 1.0f; }, "hysteresis must be in [0, 0.999]"},
      {[](IrradianceFieldParams& p) { p.hysteresis = -0.1f; }, "hysteresis must be in [0, 0.999]"},
      {[](IrradianceFieldParams& p) { p.irradiance_gamma = 0.5f; }, "irradiance_gamma"},
      {[](IrradianceFieldParams& p) { p.distance_texels = 65; }, "distance_texels"},
      {[](IrradianceFieldParams& p) { p.counts.y = 0; }, "counts.y must be in [1, 512]"},
      {[](IrradianceFieldParams& p) {
         p.counts = {512, 512, 512};
       },
       "probes; at most 4194304"},
      {[](IrradianceFieldParams& p) { p.spacing.z = 0.0f; }, "spacing must be finite and > 0"},
      {[](IrradianceFieldParams& p) { p.origin.x = std::nanf(""); }, "origin must be finite"},
      {[](IrradianceFieldParams& p) { p.energy_conservation = 1.5f; }, "energy_conservation"},
      {[](IrradianceFieldParams& p) { p.self_shadow_bias = 3.0f; }, "self_shadow_bias"},
      {[](IrradianceFieldParams& p) { p.max_ray_distance = 0.0f; }, "max_ray_distance"},
  };
  for (const Case& c : cases) {
    IrradianceFieldParams p;
    c.mutate(p);
    EXPECT_THAT(error_of(p), HasSubstr(c.expected));
  }
}

TEST(FieldParams, AtlasThatWouldNotFitIsRefused) {
  IrradianceFieldParams p;
  p.counts = {128, 128, 64};  // 1M probes: 18-texel distance tiles need a 18432-texel atlas
  EXPECT_THAT(error_of(p), HasSubstr("atlas would be"));
  p.distance_texels = 8;
  p.irradiance_texels = 4;
  EXPECT_EQ(error_of(p), "");
}

TEST(FieldParams, FittedGridIsCellCentredInsideTheBounds) {
  Bounds b;
  b.grow({-1, 0, -1});
  b.grow({1, 2, 1});
  const IrradianceFieldParams p = fit_grid_to_bounds(b, 512);
  EXPECT_EQ(p.counts, glm::ivec3(8, 8, 8));
  EXPECT_FLOAT_EQ(p.spacing.x, 0.25f);
  EXPECT_FLOAT_EQ(p.origin.x, -1.0f + 0.125f);            // half a cell in
  EXPECT_FLOAT_EQ(p.origin.y + 7 * p.spacing.y, 1.875f);  // last probe half a cell from the top
  EXPECT_EQ(error_of(p), "");
}

TEST(FieldParams, FlatAndEmptyBoundsGiveValidGrids) {
  Bounds flat;
  flat.grow({0, 0, 0});
  flat.grow({10, 0, 10});
  const IrradianceFieldParams p = fit_grid_to_bounds(flat);
  EXPECT_EQ(p.counts.y, 1);
  EXPECT_EQ(error_of(p), "");
  EXPECT_EQ(error_of(fit_grid_to_bounds(Bounds{})), "");
}

TEST(FieldParamTable, SetsAndGetsEveryParameterByName) {
  for (const FieldParamInfo& info : field_param_infos()) {
    IrradianceFieldParams p;
    auto value = get_field_param(p, info.name);
    ASSERT_TRUE(value.ok()) << info.name;
    // Writing back what was read changes nothing.
    ASSERT_TRUE(set_field_param(p, info.name, *value).ok()) << info.name << "=" << *value;
    EXPECT_EQ(*get_field_param(p, info.name), *value) << info.name;
  }
}

TEST(FieldParamTable, AssignmentsApplyThenValidate) {
  IrradianceFieldParams p;
  ASSERT_TRUE(apply_field_assignments(p, {"counts=3,2,1", "hysteresis=0.5", "spacing=1,2,3"}).ok());
  EXPECT_EQ(p.counts, glm::ivec3(3, 2, 1));
  EXPECT_FLOAT_EQ(p.hysteresis, 0.5f);
  EXPECT_EQ(p.spacing, glm::vec3(1, 2, 3));
}

TEST(FieldParamTable, BadAssignmentsLeaveParamsUnchanged) {
  IrradianceFieldParams p;
  const IrradianceFieldParams before = p;
  EXPECT_THAT(apply_field_assignments(p, {"hysteresis=0.5", "hysteresis=2"}).error().message,
              HasSubstr("hysteresis must be in [0, 0.999]"));
  EXPECT_THAT(apply_field_assignments(p, {"no_such=1"}).error().message,
              HasSubstr("unknown field parameter 'no_such'"));
  EXPECT_THAT(apply_field_assignments(p, {"counts=1,2"}).error().message,
              HasSubstr("counts needs 3 comma-separated values"));
  EXPECT_THAT(apply_field_assignments(p, {"rays_per_probe=12x"}).error().message,
              HasSubstr("not an integer"));
  EXPECT_THAT(apply_field_assignments(p, {"hysteresis"}).error().message,
              HasSubstr("is not name=value"));
  EXPECT_THAT(apply_field_assignments(p, {"self_shadow_bias=inf"}).error().message,
              HasSubstr("not"));
  EXPECT_EQ(p.hysteresis, before.hysteresis);
  EXPECT_EQ(p.counts, before.counts);
}

TEST(FieldParamTable, ProbeDirectNamesADirectModeOrTheFrames) {
  IrradianceFieldParams p;
  EXPECT_EQ(*get_field_param(p, "probe_direct"), "frame");
  ASSERT_TRUE(set_field_param(p, "probe_direct", "shadow-field").ok());
  EXPECT_EQ(p.probe_direct, DirectMode::kShadowField);
  EXPECT_EQ(*get_field_param(p, "probe_direct"), "shadow-field");
  ASSERT_TRUE(set_field_param(p, "probe_direct", "frame").ok());
  EXPECT_FALSE(p.probe_direct.has_value());
  EXPECT_THAT(set_field_param(p, "probe_direct", "rays").error().message,
              HasSubstr("probe_direct must be frame, shadow-rays, unshadowed, shadow-field or ao "
                        "(got 'rays')"));
}

}  // namespace
}  // namespace ddgi
