// Field parameters: ranges refused with the field's name, grids fitted to bounds, the by-name
// table the CLI and RPC share.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

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

// One refused value per side of every range (and NaN for floats, which compares false with
// both bounds): the message must name the field and the range a user has to get into.
struct RangeCase {
  const char* field;  // as named by field_param_infos()
  std::function<void(IrradianceFieldParams&)> mutate;
  const char* expected;
};

std::vector<RangeCase> range_cases() {
  const float nan = std::nanf("");
  const float inf = std::numeric_limits<float>::infinity();
  using P = IrradianceFieldParams;
  return {
      {"origin", [=](P& p) { p.origin.x = nan; }, "origin must be finite"},
      {"origin", [=](P& p) { p.origin.z = -inf; }, "origin must be finite"},
      {"spacing", [](P& p) { p.spacing.z = 0.0f; }, "spacing must be finite and > 0"},
      {"spacing", [](P& p) { p.spacing.x = -1.0f; }, "spacing must be finite and > 0"},
      {"spacing", [=](P& p) { p.spacing.y = inf; }, "spacing must be finite and > 0"},
      {"counts", [](P& p) { p.counts.x = 0; }, "counts.x must be in [1, 512] (got 0)"},
      {"counts", [](P& p) { p.counts.y = 0; }, "counts.y must be in [1, 512] (got 0)"},
      {"counts", [](P& p) { p.counts.z = 513; }, "counts.z must be in [1, 512] (got 513)"},
      {"counts",
       [](P& p) {
         p.counts = {512, 512, 512};
       },
       "counts give 134217728 probes; at most 4194304 are allowed"},
      {"rays_per_probe", [](P& p) { p.rays_per_probe = 0; },
       "rays_per_probe must be in [1, 1024] (got 0)"},
      {"rays_per_probe", [](P& p) { p.rays_per_probe = 1025; },
       "rays_per_probe must be in [1, 1024] (got 1025)"},
      {"fixed_rays", [](P& p) { p.fixed_rays = 257; }, "fixed_rays must be in [0, 256] (got 257)"},
      {"fixed_rays", [](P& p) { p.fixed_rays = 7; }, "need fixed_rays >= 8 (got 7)"},
      {"max_ray_distance", [](P& p) { p.max_ray_distance = 0.0f; },
       "max_ray_distance must be in [1e-30, 1e+30]"},
      {"max_ray_distance", [=](P& p) { p.max_ray_distance = inf; },
       "max_ray_distance must be in [1e-30, 1e+30]"},
      {"max_ray_distance", [=](P& p) { p.max_ray_distance = nan; },
       "max_ray_distance must be in [1e-30, 1e+30]"},
      {"irradiance_texels", [](P& p) { p.irradiance_texels = 3; },
       "irradiance_texels must be in [4, 32] (got 3)"},
      {"irradiance_texels", [](P& p) { p.irradiance_texels = 33; },
       "irradiance_texels must be in [4, 32] (got 33)"},
      {"distance_texels", [](P& p) { p.distance_texels = 3; },
       "distance_texels must be in [4, 64] (got 3)"},
      {"distance_texels", [](P& p) { p.distance_texels = 65; },
       "distance_texels must be in [4, 64] (got 65)"},
      {"hysteresis", [](P& p) { p.hysteresis = -0.1f; }, "hysteresis must be in [0, 0.999]"},
      {"hysteresis", [](P& p) { p.hysteresis = 1.0f; }, "hysteresis must be in [0, 0.999]"},
      {"hysteresis", [=](P& p) { p.hysteresis = nan; }, "hysteresis must be in [0, 0.999]"},
      {"distance_hysteresis", [](P& p) { p.distance_hysteresis = -0.1f; },
       "distance_hysteresis must be in [0, 0.999]"},
      {"distance_hysteresis", [](P& p) { p.distance_hysteresis = 1.0f; },
       "distance_hysteresis must be in [0, 0.999]"},
      {"change_threshold", [](P& p) { p.change_threshold = -0.01f; },
       "change_threshold must be in [0, 1]"},
      {"change_threshold", [](P& p) { p.change_threshold = 1.01f; },
       "change_threshold must be in [0, 1]"},
      {"new_distribution_threshold", [](P& p) { p.new_distribution_threshold = -0.01f; },
       "new_distribution_threshold must be in [0, 1]"},
      {"new_distribution_threshold", [](P& p) { p.new_distribution_threshold = 1.01f; },
       "new_distribution_threshold must be in [0, 1]"},
      {"irradiance_gamma", [](P& p) { p.irradiance_gamma = 0.5f; },
       "irradiance_gamma must be in [1, 10]"},
      {"irradiance_gamma", [](P& p) { p.irradiance_gamma = 10.5f; },
       "irradiance_gamma must be in [1, 10]"},
      {"distance_exponent", [](P& p) { p.distance_exponent = 0.5f; },
       "distance_exponent must be in [1, 100]"},
      {"distance_exponent", [](P& p) { p.distance_exponent = 101.0f; },
       "distance_exponent must be in [1, 100]"},
      {"backface_distance_scale", [](P& p) { p.backface_distance_scale = -0.1f; },
       "backface_distance_scale must be in [0, 1]"},
      {"backface_distance_scale", [](P& p) { p.backface_distance_scale = 1.1f; },
       "backface_distance_scale must be in [0, 1]"},
      {"self_shadow_bias", [](P& p) { p.self_shadow_bias = -0.1f; },
       "self_shadow_bias must be in [0, 2]"},
      {"self_shadow_bias", [](P& p) { p.self_shadow_bias = 3.0f; },
       "self_shadow_bias must be in [0, 2]"},
      {"energy_conservation", [](P& p) { p.energy_conservation = -0.1f; },
       "energy_conservation must be in [0, 1]"},
      {"energy_conservation", [](P& p) { p.energy_conservation = 1.5f; },
       "energy_conservation must be in [0, 1]"},
      {"weight_crush_threshold", [](P& p) { p.weight_crush_threshold = -0.1f; },
       "weight_crush_threshold must be in [0, 1]"},
      {"weight_crush_threshold", [](P& p) { p.weight_crush_threshold = 1.5f; },
       "weight_crush_threshold must be in [0, 1]"},
      {"relocation_iterations", [](P& p) { p.relocation_iterations = 17; },
       "relocation_iterations must be in [0, 16] (got 17)"},
      {"probe_offset_limit", [](P& p) { p.probe_offset_limit = -0.01f; },
       "probe_offset_limit must be in [0, 0.49]"},
      {"probe_offset_limit", [](P& p) { p.probe_offset_limit = 0.5f; },
       "probe_offset_limit must be in [0, 0.49]"},
      {"min_frontface_distance", [](P& p) { p.min_frontface_distance = -0.01f; },
       "min_frontface_distance must be in [0, 0.5]"},
      {"min_frontface_distance", [](P& p) { p.min_frontface_distance = 0.51f; },
       "min_frontface_distance must be in [0, 0.5]"},
      {"backface_threshold", [](P& p) { p.backface_threshold = 0.0f; },
       "backface_threshold must be in [1e-06, 1]"},
      {"backface_threshold", [](P& p) { p.backface_threshold = 1.01f; },
       "backface_threshold must be in [1e-06, 1]"},
      {"emitter_samples", [](P& p) { p.emitter_samples = 65; },
       "emitter_samples must be in [0, 64] (got 65)"},
      // 128 blended + 32 fixed rays: a cap below one probe's rays could never trace anything.
      {"max_rays_per_update", [](P& p) { p.max_rays_per_update = 159; },
       "max_rays_per_update must be 0 (no cap) or at least one probe's 160 rays (got 159)"},
  };
}

TEST(FieldParams, OutOfRangeValuesNameTheFieldAndRange) {
  for (const RangeCase& c : range_cases()) {
    IrradianceFieldParams p;
    c.mutate(p);
    EXPECT_THAT(error_of(p), HasSubstr(c.expected)) << c.field;
  }
}

// The values just inside every range are accepted, so the refusals above are the bounds and
// not something stricter.
TEST(FieldParams, BoundsThemselvesAreAccepted) {
  using P = IrradianceFieldParams;
  const std::vector<std::function<void(P&)>> edges = {
      [](P& p) {
        p.counts = {1, 1, 1};
      },
      [](P& p) {
        p.counts = {512, 8, 8};
      },
      [](P& p) { p.rays_per_probe = 1; },
      [](P& p) { p.rays_per_probe = 1024; },
      [](P& p) { p.fixed_rays = 256; },
      [](P& p) {
        p.fixed_rays = 0;
        p.relocation_iterations = 0;
        p.classification = false;
      },
      [](P& p) { p.max_ray_distance = 1e-30f; },
      [](P& p) { p.irradiance_texels = 4; },
      [](P& p) { p.irradiance_texels = 32; },
      [](P& p) { p.distance_texels = 4; },
      [](P& p) { p.distance_texels = 64; },
      [](P& p) { p.hysteresis = 0.0f; },
      [](P& p) { p.hysteresis = 0.999f; },
      [](P& p) { p.distance_hysteresis = 0.999f; },
      [](P& p) { p.change_threshold = 0.0f; },
      [](P& p) { p.new_distribution_threshold = 1.0f; },
      [](P& p) { p.irradiance_gamma = 1.0f; },
      [](P& p) { p.irradiance_gamma = 10.0f; },
      [](P& p) { p.distance_exponent = 100.0f; },
      [](P& p) { p.backface_distance_scale = 0.0f; },
      [](P& p) { p.self_shadow_bias = 2.0f; },
      [](P& p) { p.energy_conservation = 0.0f; },
      [](P& p) { p.weight_crush_threshold = 1.0f; },
      [](P& p) { p.relocation_iterations = 16; },
      [](P& p) { p.probe_offset_limit = 0.49f; },
      [](P& p) { p.min_frontface_distance = 0.5f; },
      [](P& p) { p.backface_threshold = 1.0f; },
      [](P& p) { p.emitter_samples = 64; },
      [](P& p) { p.max_rays_per_update = 160; },
  };
  for (size_t i = 0; i < edges.size(); ++i) {
    IrradianceFieldParams p;
    edges[i](p);
    EXPECT_EQ(error_of(p), "") << "edge case " << i;
  }
}

// A parameter added to the by-name table without a range case here fails this test. Only
// `classification` (true/false), `seed` (any 32-bit value) and `probe_direct` (a mode by name,
// FieldParamTable.ProbeDirectNamesADirectModeOrTheFrames) have no out-of-range values.
TEST(FieldParams, EveryNamedParameterHasARangeCase) {
  const std::vector<RangeCase> cases = range_cases();
  for (const FieldParamInfo& info : field_param_infos()) {
    if (info.name == "classification" || info.name == "seed" || info.name == "probe_direct") {
      continue;
    }
    const bool covered = std::any_of(cases.begin(), cases.end(),
                                     [&](const RangeCase& c) { return info.name == c.field; });
    EXPECT_TRUE(covered) << info.name << " has no out-of-range case";
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
  // Every member gets a value of its own, equal to no other member's and to no default (all
  // exact in binary, so the text reads back unchanged): a name wired to the wrong member then
  // writes or reads a value that gives it away. (Round-tripping the defaults missed a swap of
  // hysteresis and distance_hysteresis: both are 0.97.)
  const std::vector<std::pair<std::string, std::string>> values = {
      {"origin", "0.125,0.25,0.375"},
      {"spacing", "1.5,1.75,2.25"},
      {"counts", "3,5,7"},
      {"rays_per_probe", "96"},
      {"fixed_rays", "24"},
      {"max_ray_distance", "1000"},
      {"irradiance_texels", "6"},
      {"distance_texels", "12"},
      {"hysteresis", "0.875"},
      {"distance_hysteresis", "0.9375"},
      {"change_threshold", "0.3125"},
      {"new_distribution_threshold", "0.6875"},
      {"irradiance_gamma", "4.5"},
      {"distance_exponent", "40"},
      {"backface_distance_scale", "0.0625"},
      {"self_shadow_bias", "1.25"},
      {"energy_conservation", "0.96875"},
      {"weight_crush_threshold", "0.15625"},
      {"relocation_iterations", "9"},
      {"classification", "false"},
      {"probe_offset_limit", "0.4375"},
      {"min_frontface_distance", "0.34375"},
      {"backface_threshold", "0.5625"},
      {"max_rays_per_update", "100000"},
      {"emitter_samples", "11"},
      {"probe_direct", "unshadowed"},
      {"seed", "17"}};
  ASSERT_EQ(values.size(), field_param_infos().size()) << "a parameter without a value here";
  IrradianceFieldParams p;
  for (const auto& [name, text] : values) {
    ASSERT_TRUE(set_field_param(p, name, text).ok()) << name << "=" << text;
  }
  // Each name wrote its own member...
  EXPECT_EQ(p.origin, glm::vec3(0.125f, 0.25f, 0.375f));
  EXPECT_EQ(p.spacing, glm::vec3(1.5f, 1.75f, 2.25f));
  EXPECT_EQ(p.counts, glm::ivec3(3, 5, 7));
  EXPECT_EQ(p.rays_per_probe, 96u);
  EXPECT_EQ(p.fixed_rays, 24u);
  EXPECT_EQ(p.max_ray_distance, 1000.0f);
  EXPECT_EQ(p.irradiance_texels, 6u);
  EXPECT_EQ(p.distance_texels, 12u);
  EXPECT_EQ(p.hysteresis, 0.875f);
  EXPECT_EQ(p.distance_hysteresis, 0.9375f);
  EXPECT_EQ(p.change_threshold, 0.3125f);
  EXPECT_EQ(p.new_distribution_threshold, 0.6875f);
  EXPECT_EQ(p.irradiance_gamma, 4.5f);
  EXPECT_EQ(p.distance_exponent, 40.0f);
  EXPECT_EQ(p.backface_distance_scale, 0.0625f);
  EXPECT_EQ(p.self_shadow_bias, 1.25f);
  EXPECT_EQ(p.energy_conservation, 0.96875f);
  EXPECT_EQ(p.weight_crush_threshold, 0.15625f);
  EXPECT_EQ(p.relocation_iterations, 9u);
  EXPECT_FALSE(p.classification);
  EXPECT_EQ(p.probe_offset_limit, 0.4375f);
  EXPECT_EQ(p.min_frontface_distance, 0.34375f);
  EXPECT_EQ(p.backface_threshold, 0.5625f);
  EXPECT_EQ(p.max_rays_per_update, 100000u);
  EXPECT_EQ(p.emitter_samples, 11u);
  EXPECT_EQ(p.probe_direct, DirectMode::kUnshadowed);
  EXPECT_EQ(p.seed, 17u);
  // ...and reads it back as the same text.
  for (const auto& [name, text] : values) {
    auto value = get_field_param(p, name);
    ASSERT_TRUE(value.ok()) << name;
    EXPECT_EQ(*value, text) << name;
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
