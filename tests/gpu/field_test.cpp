// The irradiance field on lavapipe: analytic furnace values, both backends, extremes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "gi/irradiance_field.h"
#include "gpu_scene/gpu_scene.h"
#include "tests/gpu/field_setup.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/procedural.h"
#include "tests/gpu/white_box.h"

namespace ddgi::test {
namespace {

class FieldTest : public GpuTest {};

// Points well inside the furnace box, normals along the six axes.
std::vector<IrradianceQuery> furnace_queries() {
  std::vector<IrradianceQuery> queries;
  const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (glm::vec3 p :
       {glm::vec3(0, 1, 0), glm::vec3(0.4f, 0.6f, -0.3f), glm::vec3(-0.5f, 1.5f, 0.5f)}) {
    for (const glm::vec3& n : axes) queries.push_back({p, n, n});
  }
  return queries;
}

// The largest relative error of any channel of any answer against `expected`.
float worst_relative_error(const std::vector<glm::vec3>& answers, float expected) {
  float worst = 0.0f;
  for (const glm::vec3& m : answers) {
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(m[c] - expected) / expected);
  }
  return worst;
}

// White furnace in the repo's closed white box (scenes/white_box.gltf, albedo and emission set
// in memory): every surface emits Le and reflects rho, so radiance is Le / (1 - rho) everywhere
// and the field's M (the cosine-weighted mean radiance, E / pi) must converge to it.
class FurnaceTest
    : public FieldTest,
      public ::testing::WithParamInterface<std::tuple<float, vk::TraceBackend, ProbeBasis>> {};

TEST_P(FurnaceTest, ConvergesToAnalyticRadiance) {
  const auto [rho, backend, basis] = GetParam();
  const float le = 1.0f;
  IrradianceFieldParams params = white_box_grid();
  params.hysteresis = 0.5f;  // converge in few updates; the bounce series needs ~log(0.01)/log(rho)
  params.basis = basis;
  FieldSetup s = make_field_setup(load_white_box(rho, le), params, backend);
  ASSERT_TRUE(s.field);
  // Each update adds one bounce: after n updates the error is about rho^n.
  const uint32_t updates = static_cast<uint32_t>(std::ceil(std::log(0.002) / std::log(rho))) + 12;
  ASSERT_TRUE(s.field->update(updates, DirectMode::kTracedShadows).ok());
  auto answers = s.field->query(furnace_queries());
  ASSERT_TRUE(answers.ok()) << answers.error().message;
  const float expected = le / (1.0f - rho);
  ASSERT_EQ(answers->size(), 18u);
  const float worst = worst_relative_error(*answers, expected);
  // The acceptance's 2%. Measured worst relative error, the same on both backends: octahedral
  // 1.0e-4 (rho 0.2), 1.7e-3 (0.5), 1.4e-2 (0.8; the update count leaves about rho^n of the
  // series); SH 2.3e-3, 3.1e-3, 1.45e-2 (bands 1-2 of a uniform field are noise, not zero).
  std::printf("basis %s, rho %.1f: worst relative error %.2e\n",
              basis == ProbeBasis::kSh ? "sh" : "octahedral", rho, worst);
  EXPECT_LE(worst, 0.02f) << "rho " << rho << ", expected " << expected;
}

// The same furnace with the probe rays' light traced as paths (probe_bounces) instead of read
// from the previous field: no feedback short of the cap, far beyond where the Russian roulette
// ends the paths, so every update is an unbiased estimate of the whole series, and the probes
// converge as soon as the noise is averaged.
class PathTracedFurnaceTest
    : public FieldTest,
      public ::testing::WithParamInterface<std::tuple<vk::TraceBackend, ProbeBasis>> {};

TEST_P(PathTracedFurnaceTest, ConvergesToAnalyticRadiance) {
  const auto [backend, basis] = GetParam();
  // rho 0.5: the roulette's noise (it keeps 1 / 16 of the paths past the fourth vertex) stays
  // well below the bound; a bias (lost or doubled light) would not.
  const float le = 1.0f, rho = 0.5f;
  IrradianceFieldParams params = white_box_grid();
  params.basis = basis;
  params.probe_bounces = 64;
  params.hysteresis = 0.98f;  // averages the roulette's noise over ~100 updates
  FieldSetup s = make_field_setup(load_white_box(rho, le), params, backend);
  ASSERT_TRUE(s.field);
  // The split update (a benchmark reference) has no path form: refused, naming why.
  const Status split = s.field->set_update_path(FieldUpdatePath::kSplit);
  ASSERT_FALSE(split.ok());
  EXPECT_NE(split.error().message.find("probe_bounces"), std::string::npos);
  ASSERT_TRUE(s.field->update(150, DirectMode::kTracedShadows).ok());
  auto answers = s.field->query(furnace_queries());
  ASSERT_TRUE(answers.ok()) << answers.error().message;
  const float expected = le / (1.0f - rho);
  const float worst = worst_relative_error(*answers, expected);
  double mean = 0.0;
  for (const glm::vec3& m : *answers) mean += (m.r + m.g + m.b) / (3.0 * answers->size());
  std::printf(
      "path-traced update, basis %s: mean %.4f (expected %.4f), worst relative error %.2e\n",
      basis == ProbeBasis::kSh ? "sh" : "octahedral", mean, expected, worst);
  EXPECT_LE(worst, 0.02f);
}

// The pipeline backend (slow on lavapipe) with one basis: the paths are the same code.
INSTANTIATE_TEST_SUITE_P(
    Backends, PathTracedFurnaceTest,
    ::testing::Values(std::make_tuple(vk::TraceBackend::kRayQuery, ProbeBasis::kOctahedral),
                      std::make_tuple(vk::TraceBackend::kRayQuery, ProbeBasis::kSh),
                      std::make_tuple(vk::TraceBackend::kPipeline, ProbeBasis::kSh)));

// Short paths (one or two traced vertices) read the previous field where they end, so the
// bounces past them still arrive: the furnace converges to the whole series, where a path cut
// at its last vertex would stop at Le (1 + rho + ... + rho^N): 1.8 and 2.44 at rho 0.8,
// against 5. Within N <= 4 no roulette runs, and in the furnace every path then carries the
// same light: the error is what the updates leave of the series, as in FurnaceTest.
TEST_F(FieldTest, ShortProbePathsReadTheFieldWhereTheyEnd) {
  const float le = 1.0f, rho = 0.8f;
  for (uint32_t bounces : {1u, 2u}) {
    IrradianceFieldParams params = white_box_grid();
    params.probe_bounces = bounces;
    params.hysteresis = 0.5f;
    FieldSetup s = make_field_setup(load_white_box(rho, le), params, vk::TraceBackend::kRayQuery);
    ASSERT_TRUE(s.field);
    // Each update adds N + 1 bounces of the series.
    const uint32_t updates =
        static_cast<uint32_t>(std::ceil(std::log(0.002) / std::log(rho) / (bounces + 1))) + 12;
    ASSERT_TRUE(s.field->update(updates, DirectMode::kTracedShadows).ok());
    auto answers = s.field->query(furnace_queries());
    ASSERT_TRUE(answers.ok()) << answers.error().message;
    const float expected = le / (1.0f - rho);
    const float worst = worst_relative_error(*answers, expected);
    // Measured worst relative error: 4.9e-3 (1 bounce), 1.6e-3 (2); a cut path: 0.64 and 0.51.
    std::printf("%u traced bounces, %u updates: worst relative error %.2e\n", bounces, updates,
                worst);
    EXPECT_LE(worst, 0.02f) << bounces << " traced bounces, expected " << expected;
  }
}

// The hit-light pass's records exist only where it reads them: a field tracing paths from its
// probe-ray hits holds one record, and turning the paths off (probe_bounces 0, no new grid)
// gives the pass one record per ray again, which the furnace's feedback needs to converge.
TEST_F(FieldTest, HitRecordsFollowProbeBounces) {
  const float le = 1.0f, rho = 0.5f;
  IrradianceFieldParams params = white_box_grid();
  params.hysteresis = 0.5f;
  params.probe_bounces = 64;
  FieldSetup s = make_field_setup(load_white_box(rho, le), params);
  ASSERT_TRUE(s.field);
  const uint64_t with_paths = s.field->gpu_bytes();
  params.probe_bounces = 0;
  ASSERT_TRUE(s.field->set_params(params).ok());
  const uint64_t with_hits = s.field->gpu_bytes();
  const uint64_t records = probe_count(params) * (params.rays_per_probe + params.fixed_rays);
  const uint64_t grown = with_hits - with_paths;
  // Measured: 12272 bytes (768 records of 16 bytes, less the one held before); the estimate
  // that the budget checks moves by the same.
  std::printf("hit records: %llu bytes with paths, %llu without (+%llu)\n",
              (unsigned long long)with_paths, (unsigned long long)with_hits,
              (unsigned long long)grown);
  EXPECT_EQ(grown, (records - 1) * sizeof(gpu::ProbeRayHit));
  IrradianceFieldParams paths = params;
  paths.probe_bounces = 64;
  EXPECT_EQ(field_gpu_bytes(params) - field_gpu_bytes(paths), grown);
  // Each update adds one bounce through the records: 2% of Le / (1 - rho) after ~12 updates.
  ASSERT_TRUE(s.field->update(24, DirectMode::kTracedShadows).ok());
  auto answers = s.field->query(furnace_queries());
  ASSERT_TRUE(answers.ok()) << answers.error().message;
  const float expected = le / (1.0f - rho);
  const float worst = worst_relative_error(*answers, expected);
  std::printf("after paths off: worst relative error %.2e (expected %.3f)\n", worst, expected);
  EXPECT_LE(worst, 0.02f);
}

// The field after several updates (multiple bounces, shadow rays, visibility feedback) is the
// same on both backends: identical rays, identical shading code, so only float rounding of the
// traversal may differ.
TEST_F(FieldTest, BackendsGiveTheSameAtlases) {
  IrradianceFieldParams params;
  params.origin = {-0.75f, 0.25f, -0.75f};
  params.spacing = glm::vec3(0.75f);
  params.counts = {3, 3, 3};
  params.rays_per_probe = 64;
  params.fixed_rays = 8;
  std::vector<float> atlases[2];
  for (int b = 0; b < 2; ++b) {
    FieldSetup s =
        make_field_setup(make_cornell_box(), params,
                         b == 0 ? vk::TraceBackend::kRayQuery : vk::TraceBackend::kPipeline);
    ASSERT_TRUE(s.field);
    ASSERT_TRUE(s.field->update(6, DirectMode::kTracedShadows).ok());
    auto irradiance = s.field->read_irradiance_atlas();
    auto distance = s.field->read_distance_atlas();
    ASSERT_TRUE(irradiance.ok() && distance.ok());
    // Equal atlases mean nothing if both are still the initial state (black, or one value
    // everywhere). Measured on both backends: irradiance (encoded RGB) mean 0.636, range
    // 0 .. 1.536; mean distance mean 0.819, range 0 .. 1.949.
    EXPECT_TRUE(is_nontrivial(irradiance->texels, 0.2, 0.5, 4, 3)) << "irradiance, backend " << b;
    EXPECT_TRUE(is_nontrivial(distance->texels, 0.25, 0.5, 2, 1)) << "mean distance, backend " << b;
    atlases[b] = irradiance->texels;
    atlases[b].insert(atlases[b].end(), distance->texels.begin(), distance->texels.end());
  }
  ASSERT_EQ(atlases[0].size(), atlases[1].size());
  float worst = 0.0f;
  for (size_t i = 0; i < atlases[0].size(); ++i) {
    const float scale = std::max({std::abs(atlases[0][i]), std::abs(atlases[1][i]), 1e-3f});
    worst = std::max(worst, std::abs(atlases[0][i] - atlases[1][i]) / scale);
  }
  EXPECT_LE(worst, 1e-4f);
}

INSTANTIATE_TEST_SUITE_P(
    Albedos, FurnaceTest,
    ::testing::Combine(::testing::Values(0.2f, 0.5f, 0.8f),
                       ::testing::Values(vk::TraceBackend::kRayQuery, vk::TraceBackend::kPipeline),
                       ::testing::Values(ProbeBasis::kOctahedral, ProbeBasis::kSh)));

}  // namespace
}  // namespace ddgi::test
