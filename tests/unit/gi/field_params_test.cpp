// Field parameters: the rules across parameters and the wording of range errors, grids fitted to
// bounds, the by-name table the CLI and RPC share. Every parameter's own range is tested from the
// table itself (param_table_test.cpp).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gi/field_params.h"
#include "gi/light_power.h"
#include "scene/gltf_loader.h"

namespace ddgi {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

std::string error_of(const IrradianceFieldParams& p) {
  const Status s = validate(p);
  return s.ok() ? "" : s.error().message;
}

TEST(FieldParams, DefaultsAreValid) {
  EXPECT_EQ(error_of(IrradianceFieldParams{}), "");
}

// The table (field_param_table()) gives every parameter's own range its refused and accepted
// values (param_table_test.cpp). Here: the message of each kind of range, spelled out once, and
// the rules across parameters, which validate() adds to the table's ranges.
struct RangeCase {
  const char* field;
  std::function<void(IrradianceFieldParams&)> mutate;
  const char* expected;
};

std::vector<RangeCase> range_cases() {
  const float nan = std::nanf("");
  const float inf = std::numeric_limits<float>::infinity();
  using P = IrradianceFieldParams;
  return {
      {"origin", [=](P& p) { p.origin.x = nan; }, "origin must be finite"},
      {"spacing", [=](P& p) { p.spacing.y = inf; }, "spacing must be finite and > 0 on every axis"},
      {"counts", [](P& p) { p.counts.y = 0; }, "counts.y must be in [1, 512] (got 0)"},
      {"counts",
       [](P& p) {
         p.counts = {512, 512, 512};
       },
       "counts give 134217728 probes; at most 4194304 are allowed"},
      {"rays_per_probe", [](P& p) { p.rays_per_probe = 1025; },
       "rays_per_probe must be in [1, 1024] (got 1025)"},
      {"max_ray_distance", [=](P& p) { p.max_ray_distance = nan; },
       "max_ray_distance must be in [1e-30, 1e+30] (got nan)"},
      {"backface_threshold", [](P& p) { p.backface_threshold = 0.0f; },
       "backface_threshold must be in [1e-06, 1] (got 0)"},
      {"pixel_paths", [](P& p) { p.pixel_paths = 65; }, "pixel_paths must be in [0, 64] (got 65)"},
      {"pixel_path_vertices", [](P& p) { p.pixel_path_vertices = 0; },
       "pixel_path_vertices must be in [1, 64] (got 0)"},
      {"probe_direct", [](P& p) { p.probe_direct = DirectMode(9); },
       "probe_direct must be frame, shadow-rays, unshadowed, shadow-field or ao (got 9)"},
      {"fixed_rays", [](P& p) { p.fixed_rays = 7; }, "need fixed_rays >= 8 (got 7)"},
      // 128 blended rays (updates do not trace the 32 fixed ones): a cap below one probe's rays
      // could never trace anything.
      {"max_rays_per_update", [](P& p) { p.max_rays_per_update = 127; },
       "max_rays_per_update must be 0 (no cap) or at least one probe's 128 rays (got 127)"},
  };
}

TEST(FieldParams, OutOfRangeValuesNameTheFieldAndRange) {
  for (const RangeCase& c : range_cases()) {
    IrradianceFieldParams p;
    c.mutate(p);
    EXPECT_THAT(error_of(p), HasSubstr(c.expected)) << c.field;
  }
}

// The edges of the rules across parameters are accepted.
TEST(FieldParams, BoundsThemselvesAreAccepted) {
  using P = IrradianceFieldParams;
  const std::vector<std::function<void(P&)>> edges = {
      [](P& p) {
        p.counts = {512, 8, 8};
      },
      [](P& p) {
        p.fixed_rays = 0;
        p.relocation_iterations = 0;
        p.classification = false;
      },
      [](P& p) { p.max_rays_per_update = 128; },
  };
  for (size_t i = 0; i < edges.size(); ++i) {
    IrradianceFieldParams p;
    edges[i](p);
    EXPECT_EQ(error_of(p), "") << "edge case " << i;
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

// Cascades multiply the probes: past the field's probe limit the refusal names the cascades and
// the total, before any atlas is sized.
TEST(FieldParams, CascadesPastTheProbeLimitAreRefused) {
  IrradianceFieldParams p;
  p.counts = {256, 128, 64};  // 2,097,152 probes: at most 2 cascades fit 4,194,304
  p.cascades = 3;
  EXPECT_THAT(error_of(p),
              HasSubstr("cascades=3 of 2097152 probes and 0 static volume(s) make 6291456 probes"));
  p.cascades = 1;
  EXPECT_THAT(error_of(p), Not(HasSubstr("cascades")));
}

// Static volumes add their probes to the limit: the refusal names them.
TEST(FieldParams, StaticVolumesCountTowardsTheProbeLimit) {
  IrradianceFieldParams p;
  p.counts = {256, 128, 64};  // 2,097,152 probes
  p.cascades = 2;             // the limit exactly (refused by the atlas size only)
  EXPECT_THAT(error_of(p), Not(HasSubstr("make")));
  p.static_volumes = {{{0, 0, 0}, {1, 1, 1}, {1, 1, 1}}};
  EXPECT_THAT(error_of(p), HasSubstr("and 1 static volume(s) make 4194305 probes"));
}

// Volumes in blend order, finest first by their largest spacing, probes laid out in that order:
// a static volume finer than the grid comes before it, a coarser one after its cascades, ties go
// to the cascades.
TEST(FieldParams, StaticVolumesTakeTheirPlaceAmongTheCascadesByFineness) {
  IrradianceFieldParams p;
  p.origin = {0, 0, 0};
  p.spacing = {1, 1, 1};
  p.counts = {3, 3, 3};  // 27 probes a cascade: spacings 1 and 2
  p.cascades = 2;
  p.static_volumes = {{{5, 5, 5}, {4, 1, 1}, {2, 2, 2}},             // coarsest (largest spacing 4)
                      {{-1, 0, 0}, {0.5f, 0.25f, 0.5f}, {4, 1, 2}},  // finest
                      {{9, 9, 9}, {2, 2, 2}, {1, 1, 1}}};            // ties with cascade 1
  const std::vector<FieldVolume> v = field_volumes(p);
  ASSERT_EQ(v.size(), 5u);
  EXPECT_EQ(v[0].static_volume, std::optional<uint32_t>(1));
  EXPECT_EQ(v[0].origin, glm::vec3(-1, 0, 0));
  EXPECT_EQ(v[0].counts, glm::ivec3(4, 1, 2));
  EXPECT_FALSE(v[1].static_volume);
  EXPECT_EQ(v[1].cascade, 0u);
  EXPECT_EQ(v[1].spacing, glm::vec3(1));
  EXPECT_FALSE(v[2].static_volume);
  EXPECT_EQ(v[2].cascade, 1u);
  EXPECT_EQ(v[2].origin, glm::vec3(-1));  // around the grid's centre (1, 1, 1)
  EXPECT_EQ(v[3].static_volume, std::optional<uint32_t>(2));
  EXPECT_EQ(v[4].static_volume, std::optional<uint32_t>(0));
  const std::vector<uint32_t> first = {0, 8, 35, 62, 63};
  for (size_t i = 0; i < v.size(); ++i) EXPECT_EQ(v[i].first_probe, first[i]) << i;
  EXPECT_EQ(probe_count(p), 71u);
  // Only the cascades follow the camera.
  p.track_camera = true;
  EXPECT_FALSE(v[0].tracks(p));
  EXPECT_TRUE(v[1].tracks(p));
  EXPECT_TRUE(v[2].tracks(p));
  EXPECT_FALSE(v[4].tracks(p));
}

// The text form: '|' between volumes, origin/spacing/counts each in the grid's own form and
// range; errors name the volume.
TEST(FieldParamTable, StaticVolumesAreReadAndRefusedByVolume) {
  IrradianceFieldParams p;
  const ParamTable<IrradianceFieldParams>& table = field_param_table();
  ASSERT_TRUE(table.apply(p, {"static_volumes=1,2,3/0.5,0.5,0.5/2,3,4"}).ok());
  ASSERT_EQ(p.static_volumes.size(), 1u);
  EXPECT_EQ(p.static_volumes[0].counts, glm::ivec3(2, 3, 4));
  EXPECT_THAT(table.apply(p, {"static_volumes=1,2,3/0.5,0.5,0.5"}).error().message,
              HasSubstr("static_volumes[0] must be origin/spacing/counts (got "
                        "'1,2,3/0.5,0.5,0.5')"));
  EXPECT_THAT(
      table.apply(p, {"static_volumes=0,0,0/1,1,1/1,1,1|0,0,0/1,1,1/2,x,2"}).error().message,
      HasSubstr("static_volumes[1]: counts"));
  EXPECT_THAT(
      table.apply(p, {"static_volumes=0,0,0/1,1,1/1,1,1|0,0,0/1,1,1/0,1,1"}).error().message,
      HasSubstr("static_volumes[1] counts.x must be in [1, 512] (got 0)"));
  EXPECT_THAT(table.apply(p, {"cascades=8", "static_volumes=0,0,0/1,1,1/1,1,1"}).error().message,
              HasSubstr("static_volumes and cascades make more than 8 volumes (1 and 8)"));
  // Refusals left the volume read first; empty text removes it.
  EXPECT_EQ(p.static_volumes.size(), 1u);
  ASSERT_TRUE(table.apply(p, {"static_volumes="}).ok());
  EXPECT_TRUE(p.static_volumes.empty());
}

// A scene's probe_volumes (sidecar) are the default field's static volumes.
TEST(FieldParams, SceneProbeVolumesAreTheDefaultStaticVolumes) {
  Scene scene;
  scene.probe_grid = GridPlacement{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
  scene.probe_volumes = {{{1, 2, 3}, {0.5f, 0.5f, 0.5f}, {4, 5, 6}}};
  const IrradianceFieldParams p = default_field_params(scene);
  ASSERT_EQ(p.static_volumes.size(), 1u);
  EXPECT_EQ(p.static_volumes[0].origin, glm::vec3(1, 2, 3));
  EXPECT_EQ(p.static_volumes[0].counts, glm::ivec3(4, 5, 6));
  EXPECT_EQ(error_of(p), "");
}

// Emitter sampling is on by default exactly where a placed primitive uses an emissive material
// (DefaultEnergyTest shows why); a user's emitter_samples=0 still turns it off.
TEST(FieldParams, EmissiveScenesSampleTheirEmittersByDefault) {
  Scene scene;
  Primitive triangle;
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  triangle.indices = {0, 1, 2};
  triangle.material = 0;
  scene.materials.push_back(Material{});
  scene.meshes.push_back(Mesh{"tri", {triangle}});
  scene.instances.push_back(Instance{"tri", 0, 0});
  EXPECT_EQ(default_field_params(scene).emitter_samples, 0u);  // nothing emits
  scene.materials.push_back(Material{});
  scene.materials.back().emissive = glm::vec3(5.0f);
  EXPECT_EQ(default_field_params(scene).emitter_samples, 0u);  // an emissive material unused
  scene.meshes[0].primitives[0].material = 1;
  IrradianceFieldParams p = default_field_params(scene);
  EXPECT_EQ(p.emitter_samples, kSceneEmitterSamples);
  ASSERT_TRUE(field_param_table().apply(p, {"emitter_samples=0"}).ok());
  EXPECT_EQ(p.emitter_samples, 0u);
}

// A scene of one emissive triangle (legs `leg`, radiance `radiance`) on a square ground of
// side `ground` at y = 0.
Scene emitter_on_ground(float leg, float radiance, float ground) {
  Scene scene;
  scene.materials.push_back(Material{});
  scene.materials.push_back(Material{});
  scene.materials.back().emissive = glm::vec3(radiance);
  Primitive emitter;
  emitter.positions = {{0, 1, 0}, {leg, 1, 0}, {0, 1, leg}};
  emitter.indices = {0, 1, 2};
  emitter.material = 1;
  Primitive plane;
  plane.positions = {
      {-ground / 2, 0, -ground / 2}, {ground / 2, 0, ground / 2}, {ground / 2, 0, -ground / 2}};
  plane.indices = {0, 1, 2};
  plane.material = 0;
  scene.meshes.push_back(Mesh{"emitter", {emitter, plane}});
  scene.instances.push_back(Instance{"emitter", 0, 0});
  return scene;
}

// The light each source puts out, against the analytic values: pi x area x radiance for an
// emitter, 4 pi I for a point light, the cone's solid angle x I for a spot, irradiance x the
// facing area of the bounds for the sun.
TEST(LightPower, EachSourceAgainstItsAnalyticFlux) {
  constexpr double kPi = 3.14159265358979323846;
  Scene scene = emitter_on_ground(0.5f, 8.0f, 10.0f);  // bounds 10 x 1 x 10 m
  scene.lights.push_back(Light{"point", LightType::kPoint, glm::vec3(1.0f), 3.0f});
  Light spot{"spot", LightType::kSpot, glm::vec3(1.0f), 2.0f};
  spot.outer_cone_angle = 0.5f;
  scene.lights.push_back(spot);
  Light sun{"sun", LightType::kDirectional, glm::vec3(1.0f), 4.0f};
  sun.direction = glm::vec3(0.0f, -1.0f, 0.0f);
  scene.lights.push_back(sun);
  const LightPower power = light_power(scene);
  EXPECT_NEAR(power.emitters, kPi * 0.125 * 8.0, 1e-4);
  EXPECT_NEAR(power.punctual, 4.0 * kPi * 3.0 + 2.0 * kPi * (1.0 - std::cos(0.5)) * 2.0, 1e-4);
  EXPECT_NEAR(power.directional, 4.0 * 10.0 * 10.0, 1e-3);
  // A slanted sun meets the 10 x 1 m sides too.
  scene.lights[2].direction = glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f));
  EXPECT_NEAR(light_power(scene).directional, 4.0 * (10.0 * 10.0 + 1.0 * 10.0) / std::sqrt(2.0),
              1e-3);
}

// Emitters are sampled by default only where they carry kEmitterShareToSample of the light: a
// lamp that is the only light, or next to a weaker point light; not a small sign under the sun
// (the street's case: sampling its signs doubled the field time for no visible change).
TEST(FieldParams, EmittersAreSampledWhereTheyLightTheScene) {
  Scene lamp = emitter_on_ground(0.5f, 8.0f, 10.0f);  // pi x 0.125 x 8 = pi W
  EXPECT_EQ(default_field_params(lamp).emitter_samples, kSceneEmitterSamples);
  // A point light of 4 pi x 2.25 = 9 pi W: the lamp's share is 10%, sampled.
  lamp.lights.push_back(Light{"point", LightType::kPoint, glm::vec3(1.0f), 2.25f});
  EXPECT_NEAR(light_power(lamp).emitters / light_power(lamp).total(), 0.1, 1e-4);
  EXPECT_EQ(default_field_params(lamp).emitter_samples, kSceneEmitterSamples);
  // 4 pi x 12.25 = 49 pi W: 2%, carried by the field.
  lamp.lights[0].intensity = 12.25f;
  EXPECT_EQ(default_field_params(lamp).emitter_samples, 0u);
  // A 0.5 m sign under a sun of irradiance 3 over 100 x 100 m: 3.14 W against 30 kW.
  Scene street = emitter_on_ground(0.5f, 8.0f, 100.0f);
  Light sun{"sun", LightType::kDirectional, glm::vec3(1.0f), 3.0f};
  sun.direction = glm::vec3(0.0f, -1.0f, 0.0f);
  street.lights.push_back(sun);
  EXPECT_FALSE(emitters_worth_sampling(street));
  EXPECT_EQ(default_field_params(street).emitter_samples, 0u);
}

// The rule on the repository's scenes: the emitter-lit ones keep sampling (their light is the
// emitters'), the street's signs under the sun do not. Measured shares beside each.
TEST(FieldParams, RepoScenesSampleEmittersWhereTheyAreTheLight) {
  if (!std::filesystem::exists(DDGI_SHARED_SCENES_DIR)) GTEST_SKIP() << "no ../shared/scenes";
  auto share = [](const char* name) -> std::optional<double> {
    Result<Scene> scene = load_scene(std::string(DDGI_REPO_SCENES_DIR) + "/" + name);
    EXPECT_TRUE(scene.ok()) << name << ": " << scene.error().message;
    if (!scene.ok()) return std::nullopt;
    const LightPower power = light_power(*scene);
    const double s = power.total() > 0.0 ? power.emitters / power.total() : 0.0;
    std::printf("%s: emitters %.4g W of %.4g W (share %.4g)\n", name, power.emitters, power.total(),
                s);
    EXPECT_EQ(emitters_worth_sampling(*scene), s >= kEmitterShareToSample) << name;
    return s;
  };
  for (const char* lit_by_emitters :
       {"cornell_kajiya.ddgi.json", "veach_ajar.ddgi.json", "modern_hall.ddgi.json"}) {
    EXPECT_GE(share(lit_by_emitters).value_or(0.0), kEmitterShareToSample) << lit_by_emitters;
  }
  EXPECT_LT(share("street.ddgi.json").value_or(1.0), kEmitterShareToSample);
  share("staircase.ddgi.json");  // printed: emitters beside a sun
  share("cornell_nvpro.ddgi.json");
}

// A scene of a cube (side `cube`, on y 0 .. cube) on a square ground plane of side `ground`.
Scene cube_on_ground(float cube, float ground) {
  Scene scene;
  scene.materials.push_back(Material{});
  Primitive box;
  box.positions = {{-cube / 2, 0, -cube / 2}, {cube / 2, cube, cube / 2}, {cube / 2, 0, -cube / 2}};
  box.indices = {0, 1, 2};
  Primitive plane;
  plane.positions = {
      {-ground / 2, 0, -ground / 2}, {ground / 2, 0, ground / 2}, {ground / 2, 0, -ground / 2}};
  plane.indices = {0, 1, 2};
  scene.meshes.push_back(Mesh{"cube", {box}});
  scene.meshes.push_back(Mesh{"ground", {plane}});
  scene.instances.push_back(Instance{"cube", 0, 0});
  scene.instances.push_back(Instance{"ground", 1, 1});
  return scene;
}

// The default grid skips a ground plane only where fitting the whole would space probes wider
// than the objects on it are large: lights_punctual's proportions (a 2 m cube on 157 m; the whole
// gives 4.6 m) get a grid over the cube and 2 m of ground around it, box_on_floor's (1 m on 8 m;
// the whole gives 0.5 m) keep the whole floor. Planted: the spacing test inverted fails both.
TEST(FieldParams, DefaultGridSkipsOnlyAGroundItCannotResolve) {
  const IrradianceFieldParams far = default_field_params(cube_on_ground(2.0f, 157.0f));
  const glm::vec3 far_last = far.origin + far.spacing * (glm::vec3(far.counts) - 1.0f);
  EXPECT_NEAR(far.origin.x - far.spacing.x / 2, -3.0f, 1e-4f);  // cell-centred over -3 .. 3
  EXPECT_NEAR(far_last.x + far.spacing.x / 2, 3.0f, 1e-4f);
  EXPECT_LT(far.spacing.x, 1.0f);
  EXPECT_GE(far.counts.y, 2);  // layers between the ground and the cube's top
  const IrradianceFieldParams near = default_field_params(cube_on_ground(1.0f, 8.0f));
  Bounds floor;
  floor.grow({-4, 0, -4});
  floor.grow({4, 1, 4});
  EXPECT_EQ(near, fit_grid_to_bounds(floor));
  EXPECT_NEAR(near.spacing.x, 0.5f, 1e-4f);
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
  // A distinct value for every member, none of them its default: a name wired to another member
  // of its type (hysteresis and distance_hysteresis, say) shows as a mismatch.
  const std::vector<std::pair<std::string, std::string>> values = {
      {"origin", "1,2,3"},
      {"spacing", "0.25,0.5,0.75"},
      {"counts", "3,5,7"},
      {"track_camera", "true"},
      {"cascades", "3"},
      {"cascade_spacing_ratio", "2.5"},
      {"static_volumes", "-1,0,2.5/0.25,0.25,0.5/4,2,3|0,0,0/4,4,4/2,2,2"},
      {"rays_per_probe", "64"},
      {"fixed_rays", "16"},
      {"max_ray_distance", "100"},
      {"basis", "sh"},
      {"sh_window", "3.5"},
      {"irradiance_texels", "6"},
      {"distance_texels", "12"},
      {"hysteresis", "0.9"},
      {"distance_hysteresis", "0.8"},
      {"change_threshold", "0.3"},
      {"new_distribution_threshold", "0.7"},
      {"irradiance_gamma", "4"},
      {"distance_exponent", "40"},
      {"backface_distance_scale", "0.15"},
      {"self_shadow_bias", "0.35"},
      {"probe_bounces", "3"},
      {"energy_conservation", "0.95"},
      {"weight_crush_threshold", "0.1"},
      {"relocation_iterations", "3"},
      {"classification", "false"},
      {"probe_offset_limit", "0.4"},
      {"min_frontface_distance", "0.2"},
      {"backface_threshold", "0.45"},
      {"max_rays_per_update", "1000"},
      {"settle_threshold", "0.02"},
      {"hot_updates", "12"},
      {"maintenance_rate", "0.25"},
      {"emitter_samples", "2"},
      {"pixel_paths", "3"},
      {"pixel_path_vertices", "5"},
      {"probe_direct", "ao"},
      {"seed", "11"},
  };
  IrradianceFieldParams expected;
  expected.origin = {1, 2, 3};
  expected.spacing = {0.25f, 0.5f, 0.75f};
  expected.counts = {3, 5, 7};
  expected.track_camera = true;
  expected.cascades = 3;
  expected.cascade_spacing_ratio = 2.5f;
  expected.static_volumes = {{{-1, 0, 2.5f}, {0.25f, 0.25f, 0.5f}, {4, 2, 3}},
                             {{0, 0, 0}, {4, 4, 4}, {2, 2, 2}}};
  expected.rays_per_probe = 64;
  expected.fixed_rays = 16;
  expected.max_ray_distance = 100.0f;
  expected.basis = ProbeBasis::kSh;
  expected.sh_window = 3.5f;
  expected.irradiance_texels = 6;
  expected.distance_texels = 12;
  expected.hysteresis = 0.9f;
  expected.distance_hysteresis = 0.8f;
  expected.change_threshold = 0.3f;
  expected.new_distribution_threshold = 0.7f;
  expected.irradiance_gamma = 4.0f;
  expected.distance_exponent = 40.0f;
  expected.backface_distance_scale = 0.15f;
  expected.self_shadow_bias = 0.35f;
  expected.probe_bounces = 3;
  expected.energy_conservation = 0.95f;
  expected.weight_crush_threshold = 0.1f;
  expected.relocation_iterations = 3;
  expected.classification = false;
  expected.probe_offset_limit = 0.4f;
  expected.min_frontface_distance = 0.2f;
  expected.backface_threshold = 0.45f;
  expected.max_rays_per_update = 1000;
  expected.settle_threshold = 0.02f;
  expected.hot_updates = 12;
  expected.maintenance_rate = 0.25f;
  expected.emitter_samples = 2;
  expected.pixel_paths = 3;
  expected.pixel_path_vertices = 5;
  expected.probe_direct = DirectMode::kAmbientOcclusion;
  expected.seed = 11;

  const ParamTable<IrradianceFieldParams>& table = field_param_table();
  IrradianceFieldParams p;
  for (const auto& [name, value] : values) {
    ASSERT_TRUE(table.set(p, name, value).ok()) << name << "=" << value;
  }
  // Every member was set (a member missing from the table would keep its default) ...
  EXPECT_TRUE(p == expected);
  for (const ParamSpec<IrradianceFieldParams>& spec : table.specs()) {
    // ... through the member its name stands for ...
    EXPECT_EQ(*table.get(p, spec.name), *table.get(expected, spec.name)) << spec.name;
    // ... and writing back what was read changes nothing.
    IrradianceFieldParams copy;
    ASSERT_TRUE(table.set(copy, spec.name, *table.get(p, spec.name)).ok()) << spec.name;
    EXPECT_EQ(*table.get(copy, spec.name), *table.get(p, spec.name)) << spec.name;
  }
  EXPECT_EQ(values.size(), table.specs().size());
}

TEST(FieldParamTable, AssignmentsApplyThenValidate) {
  IrradianceFieldParams p;
  ASSERT_TRUE(
      field_param_table().apply(p, {"counts=3,2,1", "hysteresis=0.5", "spacing=1,2,3"}).ok());
  EXPECT_EQ(p.counts, glm::ivec3(3, 2, 1));
  EXPECT_FLOAT_EQ(p.hysteresis, 0.5f);
  EXPECT_EQ(p.spacing, glm::vec3(1, 2, 3));
}

TEST(FieldParamTable, BadAssignmentsLeaveParamsUnchanged) {
  IrradianceFieldParams p;
  const IrradianceFieldParams before = p;
  EXPECT_THAT(field_param_table().apply(p, {"hysteresis=0.5", "hysteresis=2"}).error().message,
              HasSubstr("hysteresis must be in [0, 0.999]"));
  EXPECT_THAT(field_param_table().apply(p, {"no_such=1"}).error().message,
              HasSubstr("unknown field parameter 'no_such'"));
  EXPECT_THAT(field_param_table().apply(p, {"counts=1,2"}).error().message,
              HasSubstr("counts needs 3 comma-separated values"));
  EXPECT_THAT(field_param_table().apply(p, {"rays_per_probe=12x"}).error().message,
              HasSubstr("not an integer"));
  EXPECT_THAT(field_param_table().apply(p, {"hysteresis"}).error().message,
              HasSubstr("is not name=value"));
  EXPECT_THAT(field_param_table().apply(p, {"self_shadow_bias=inf"}).error().message,
              HasSubstr("not"));
  EXPECT_EQ(p.hysteresis, before.hysteresis);
  EXPECT_EQ(p.counts, before.counts);
}

TEST(FieldParamTable, ProbeDirectNamesADirectModeOrTheFrames) {
  IrradianceFieldParams p;
  EXPECT_EQ(*field_param_table().get(p, "probe_direct"), "frame");
  ASSERT_TRUE(field_param_table().set(p, "probe_direct", "shadow-field").ok());
  EXPECT_EQ(p.probe_direct, DirectMode::kShadowField);
  EXPECT_EQ(*field_param_table().get(p, "probe_direct"), "shadow-field");
  ASSERT_TRUE(field_param_table().set(p, "probe_direct", "frame").ok());
  EXPECT_FALSE(p.probe_direct.has_value());
  EXPECT_THAT(field_param_table().set(p, "probe_direct", "rays").error().message,
              HasSubstr("probe_direct must be frame, shadow-rays, unshadowed, shadow-field or ao "
                        "(got 'rays')"));
}

}  // namespace
}  // namespace ddgi
