// The two update paths give the same field: the fused one (field_trace lights each ray where it
// lands, field_blend blends a probe per workgroup and writes its borders) against the split
// one kept as its reference (surfels, a shade pass with a second glass ray, per-texel blends,
// a borders pass). Atlases after several updates are compared texel by texel in scenes with
// what the ray code treats specially: thin glass (also more layers than the payload keeps),
// alpha-masked cut-outs, punctual lights, emitters (also sampled), the shadow field, probe
// management, the ray budget's window, 1 to 1024 rays per probe, and uneven map sizes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "gi/gi_stack.h"
#include "gi/irradiance_field.h"
#include "scene/gltf_loader.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/procedural.h"

namespace ddgi::test {
namespace {

const std::string kRepo = DDGI_SOURCE_DIR;

// The Cornell box (a point light) with a glass pane, a stack of four panes (probe rays through it
// cross more glass than the payload keeps), a half cut-out quad and an emitting panel.
Scene materials_room() {
  Scene scene = make_cornell_box();
  Material glass;
  glass.base_color = glm::vec4(0.9f, 0.6f, 0.3f, 1.0f);
  glass.transmission = 1.0f;
  glass.double_sided = true;
  scene.materials.push_back(glass);
  const int glass_material = static_cast<int>(scene.materials.size()) - 1;
  add_quad(scene, {-0.9f, 0.2f, 0.3f}, {0.9f, 0.2f, 0.3f}, {0.9f, 1.8f, 0.3f}, {-0.9f, 1.8f, 0.3f},
           glass_material);
  for (int i = 0; i < 4; ++i) {
    const float y = 1.3f + 0.08f * static_cast<float>(i);
    add_quad(scene, {-0.9f, y, -0.9f}, {0.0f, y, -0.9f}, {0.0f, y, 0.0f}, {-0.9f, y, 0.0f},
             glass_material);
  }

  Texture half_cut;  // 2x2: alpha 0 on the left column, 255 on the right
  half_cut.width = half_cut.height = 2;
  half_cut.rgba8 = {255, 255, 255, 0, 200, 200, 255, 255, 255, 255, 255, 0, 200, 200, 255, 255};
  scene.textures.push_back(half_cut);
  Material cut;
  cut.base_color_texture = static_cast<int>(scene.textures.size()) - 1;
  cut.alpha_mode = AlphaMode::kMask;
  cut.alpha_cutoff = 0.5f;
  cut.double_sided = true;
  scene.materials.push_back(cut);
  add_quad(scene, {0.2f, 0.1f, -0.5f}, {0.9f, 0.1f, -0.5f}, {0.9f, 0.9f, -0.5f},
           {0.2f, 0.9f, -0.5f}, static_cast<int>(scene.materials.size()) - 1);

  const int emitter = add_material(scene, glm::vec3(0.0f), glm::vec3(2.0f, 1.5f, 1.0f));
  add_quad(scene, {-0.99f, 0.8f, -0.3f}, {-0.99f, 0.8f, 0.3f}, {-0.99f, 1.2f, 0.3f},
           {-0.99f, 1.2f, -0.3f}, emitter);
  return scene;
}

// 4 x 4 x 4 probes over the 2 m room.
IrradianceFieldParams room_field(uint32_t rays) {
  IrradianceFieldParams p;
  p.origin = {-0.75f, 0.25f, -0.75f};
  p.spacing = glm::vec3(0.5f);
  p.counts = {4, 4, 4};
  p.rays_per_probe = rays;
  return p;
}

struct Atlases {
  IrradianceField::AtlasImage irradiance;
  IrradianceField::AtlasImage distance;
  bool ok = false;
};

// A stack over `scene` whose field takes `path`, after `updates` updates of both fields.
Atlases updated_atlases(const Scene& scene, const GiStackOptions& options, FieldUpdatePath path,
                        uint32_t updates) {
  Atlases a;
  auto gi = GiStack::create(gpu_context(), scene, options);
  EXPECT_TRUE(gi.ok()) << gi.error().message;
  if (!gi.ok()) return a;
  const Status set = (*gi)->field()->set_update_path(path);
  EXPECT_TRUE(set.ok()) << set.error().message;
  const Status run = (*gi)->update(updates);
  EXPECT_TRUE(run.ok()) << run.error().message;
  auto irradiance = (*gi)->field()->read_irradiance_atlas();
  auto distance = (*gi)->field()->read_distance_atlas();
  EXPECT_TRUE(irradiance.ok() && distance.ok());
  if (!set.ok() || !run.ok() || !irradiance.ok() || !distance.ok()) return a;
  a.irradiance = std::move(irradiance).value();
  a.distance = std::move(distance).value();
  a.ok = true;
  return a;
}

// How far apart two atlases are: the largest difference of a value, relative to the largest
// value of either.
double max_relative_difference(const IrradianceField::AtlasImage& a,
                               const IrradianceField::AtlasImage& b) {
  if (a.texels.size() != b.texels.size() || a.texels.empty()) return 1e30;
  double scale = 0.0, largest = 0.0;
  for (size_t i = 0; i < a.texels.size(); ++i) {
    scale = std::max({scale, std::abs(double(a.texels[i])), std::abs(double(b.texels[i]))});
    largest = std::max(largest, std::abs(double(a.texels[i]) - double(b.texels[i])));
  }
  return largest / scale;
}

// Tolerance: the split path keeps the surfel's normals oct-packed (16 bits per axis) between its
// passes, which moves shading normals, cosines and shadow-ray origins by ~1e-5; the glass
// products are taken in another order. Measured (lavapipe, both backends): at most 2.5e-5 of
// the atlas's largest value (one ray per probe; 2.4e-6 at 64 rays), printed per case. Allowed:
// 1e-3. A wrong texel, ray or border is off by 0.1 to 1 (a planted border fault: 0.86).
constexpr double kPathTolerance = 1e-3;

// Fused and split atlases of one configuration agree, and are not trivially equal.
void expect_same_atlases(const char* name, const Atlases& fused, const Atlases& split) {
  ASSERT_TRUE(fused.ok && split.ok);
  // Not trivially equal: lit (RGB of the encoded irradiance) and with distances that vary.
  EXPECT_TRUE(is_nontrivial(fused.irradiance.texels, 0.01, 0.1, 4, 3));
  EXPECT_TRUE(is_nontrivial(fused.distance.texels, 0.05, 0.2, 2, 1));
  const double irradiance = max_relative_difference(fused.irradiance, split.irradiance);
  const double distance = max_relative_difference(fused.distance, split.distance);
  std::printf("%s: largest difference: irradiance %.2e, distance %.2e (of the largest value)\n",
              name, irradiance, distance);
  EXPECT_LE(irradiance, kPathTolerance);
  EXPECT_LE(distance, kPathTolerance);
}

struct PathCase {
  const char* name;
  uint32_t rays = 64;
  uint32_t updates = 3;
  DirectMode direct = DirectMode::kTracedShadows;
  uint32_t emitter_samples = 0;
  uint64_t max_rays_per_update = 0;  // 0: every probe every update
  bool probe_management = true;
  uint32_t irradiance_texels = 8, distance_texels = 16;
  vk::TraceBackend backend = vk::TraceBackend::kRayQuery;
};

class FieldUpdatePathTest : public GpuTest, public ::testing::WithParamInterface<PathCase> {};

TEST_P(FieldUpdatePathTest, FusedAndSplitGiveTheSameAtlases) {
  const PathCase& c = GetParam();
  GiStackOptions options;
  options.direct_mode = c.direct;
  options.backend = c.backend;
  options.field = room_field(c.rays);
  options.field.emitter_samples = c.emitter_samples;
  options.field.max_rays_per_update = c.max_rays_per_update;
  options.field.irradiance_texels = c.irradiance_texels;
  options.field.distance_texels = c.distance_texels;
  if (!c.probe_management) {
    options.field.relocation_iterations = 0;
    options.field.classification = false;
  }
  const Scene scene = materials_room();
  const Atlases fused = updated_atlases(scene, options, FieldUpdatePath::kFused, c.updates);
  const Atlases split = updated_atlases(scene, options, FieldUpdatePath::kSplit, c.updates);
  expect_same_atlases(c.name, fused, split);
}

PathCase make_case(const char* name) {
  PathCase c;
  c.name = name;
  return c;
}

std::vector<PathCase> path_cases() {
  std::vector<PathCase> cases;
  cases.push_back(make_case("traced_shadows"));
  cases.push_back(make_case("pipeline"));
  cases.back().backend = vk::TraceBackend::kPipeline;
  cases.push_back(make_case("one_ray"));
  cases.back().rays = 1;
  cases.back().updates = 8;
  cases.push_back(make_case("1024_rays"));  // sixteen 64-ray shared-memory chunks per probe
  cases.back().rays = 1024;
  cases.back().updates = 2;
  cases.push_back(make_case("emitter_sampling"));
  cases.back().emitter_samples = 2;
  cases.push_back(make_case("shadow_field"));
  cases.back().direct = DirectMode::kShadowField;
  cases.push_back(make_case("budget_window"));  // 10 probes per update, wrapping around
  cases.back().max_rays_per_update = 10 * 64;
  cases.back().updates = 9;
  // More irradiance than distance texels, neither a multiple of the 64-invocation workgroup.
  cases.push_back(make_case("uneven_maps"));
  cases.back().irradiance_texels = 12;
  cases.back().distance_texels = 6;
  cases.push_back(make_case("no_probe_management"));
  cases.back().probe_management = false;
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Cases, FieldUpdatePathTest, ::testing::ValuesIn(path_cases()),
                         [](const auto& test) { return std::string(test.param.name); });

// A real scene with glass and alpha masks (LivingRoom, through its sidecar) on a small grid.
TEST_F(FieldUpdatePathTest, FusedAndSplitAgreeInTheLivingRoom) {
  if (!std::filesystem::exists(kRepo + "/../shared/scenes")) GTEST_SKIP() << "no ../shared/scenes";
  auto scene = load_scene(kRepo + "/scenes/living_room.ddgi.json");
  ASSERT_TRUE(scene.ok()) << scene.error().message;
  auto options =
      fitted_gi_options(*scene, true, DirectMode::kTracedShadows,
                        {"counts=6,3,6", "rays_per_probe=64"}, {}, vk::TraceBackend::kRayQuery);
  ASSERT_TRUE(options.ok()) << options.error().message;
  const Atlases fused = updated_atlases(*scene, *options, FieldUpdatePath::kFused, 2);
  const Atlases split = updated_atlases(*scene, *options, FieldUpdatePath::kSplit, 2);
  expect_same_atlases("living_room", fused, split);
}

}  // namespace
}  // namespace ddgi::test
