// The irradiance field at the extremes the product promises to survive: light intensities
// from 1e-6 to 1e6, scene scales from 1e-3 to 1e4, hysteresis 0 and 0.999, 1 and 1024 rays
// per probe, a 1x1x1 grid, probes exactly on a surface. No NaN or Inf anywhere, and results
// that match the unscaled case where physics says they must.
#include <gtest/gtest.h>

#include <cmath>

#include "gi/irradiance_field.h"
#include "render/gpu_scene.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/procedural.h"

namespace ddgi::test {
namespace {

// A small grid inside the procedural Cornell box (x, z in [-1, 1], y in [0, 2]).
IrradianceFieldParams cornell_grid(float scale = 1.0f) {
  IrradianceFieldParams p;
  p.origin = glm::vec3(-0.75f, 0.25f, -0.75f) * scale;
  p.spacing = glm::vec3(0.75f) * scale;
  p.counts = {3, 3, 3};
  p.rays_per_probe = 64;
  p.fixed_rays = 8;
  p.hysteresis = 0.9f;
  return p;
}

// Surface points of the box (floor, back wall, ceiling, the red and green walls) with their
// normals, scaled.
std::vector<IrradianceQuery> cornell_queries(float scale = 1.0f) {
  const struct {
    glm::vec3 p, n;
  } points[] = {{{-0.5f, 0.001f, 0.6f}, {0, 1, 0}},  {{-0.5f, 1.2f, -0.999f}, {0, 0, 1}},
                {{0.3f, 1.999f, 0.2f}, {0, -1, 0}},  {{-0.999f, 0.8f, 0.3f}, {1, 0, 0}},
                {{0.999f, 1.5f, -0.4f}, {-1, 0, 0}}, {{0.6f, 0.001f, -0.7f}, {0, 1, 0}}};
  std::vector<IrradianceQuery> queries;
  for (const auto& q : points) queries.push_back({q.p * scale, q.n, q.n});
  return queries;
}

class FieldExtremesTest : public GpuTest {
 protected:
  // Runs `updates` updates on `scene` and answers `queries`.
  std::vector<glm::vec3> converge(const Scene& scene, const IrradianceFieldParams& params,
                                  const std::vector<IrradianceQuery>& queries,
                                  uint32_t updates = 24) {
    auto gpu = GpuScene::create(context(), scene);
    EXPECT_TRUE(gpu.ok()) << gpu.error().message;
    if (!gpu.ok()) return {};
    auto field = IrradianceField::create(context(), **gpu, params, vk::TraceBackend::kRayQuery);
    EXPECT_TRUE(field.ok()) << field.error().message;
    if (!field.ok()) return {};
    EXPECT_TRUE((*field)->update(updates, DirectMode::kTracedShadows).ok());
    auto answers = (*field)->query(queries);
    EXPECT_TRUE(answers.ok()) << answers.error().message;
    if (!answers.ok()) return {};
    // Every atlas texel must be finite too, not just the answers.
    for (bool irradiance : {true, false}) {
      auto atlas = irradiance ? (*field)->read_irradiance_atlas() : (*field)->read_distance_atlas();
      EXPECT_TRUE(atlas.ok());
      if (!atlas.ok()) continue;
      for (float v : atlas->texels) {
        if (!std::isfinite(v)) {
          ADD_FAILURE() << "non-finite atlas texel";
          break;
        }
      }
    }
    return std::move(answers).value();
  }
};

void expect_finite_positive(const std::vector<glm::vec3>& values) {
  ASSERT_FALSE(values.empty());
  for (const glm::vec3& v : values) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_TRUE(std::isfinite(v[c]));
      EXPECT_GE(v[c], 0.0f);
    }
  }
}

// Irradiance is linear in the light's intensity; the field's perceptual encoding and relative
// hysteresis thresholds must not change that. Same seed, same rays: ratios match closely.
TEST_F(FieldExtremesTest, LightIntensityScalesLinearlyFrom1eMinus6To1e6) {
  const std::vector<IrradianceQuery> queries = cornell_queries();
  Scene base = make_cornell_box();
  const std::vector<glm::vec3> reference = converge(base, cornell_grid(), queries);
  expect_finite_positive(reference);
  for (float factor : {1e-6f, 1e6f}) {
    Scene scene = base;
    scene.lights[0].intensity *= factor;
    const std::vector<glm::vec3> scaled = converge(scene, cornell_grid(), queries);
    expect_finite_positive(scaled);
    for (size_t i = 0; i < reference.size() && i < scaled.size(); ++i) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(scaled[i][c] / factor, reference[i][c], 1e-3f * reference[i][c] + 1e-9f)
            << "query " << i << " channel " << c << " at intensity x" << factor;
      }
    }
  }
}

// The same box at 1e-3 and 1e4 times the size (lights scaled so irradiance is unchanged,
// probe spacing scaled with it) gives the same irradiance at corresponding points.
TEST_F(FieldExtremesTest, SceneScaleFrom1eMinus3To1e4MatchesUnscaled) {
  const std::vector<glm::vec3> reference =
      converge(make_cornell_box(), cornell_grid(), cornell_queries());
  expect_finite_positive(reference);
  for (float scale : {1e-3f, 1e4f}) {
    Scene scene = make_cornell_box();
    scale_scene(scene, scale);
    const std::vector<glm::vec3> scaled =
        converge(scene, cornell_grid(scale), cornell_queries(scale));
    expect_finite_positive(scaled);
    for (size_t i = 0; i < reference.size() && i < scaled.size(); ++i) {
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(scaled[i][c], reference[i][c], 0.02f * reference[i][c] + 1e-4f)
            << "query " << i << " channel " << c << " at scale " << scale;
      }
    }
  }
}

TEST_F(FieldExtremesTest, HysteresisZeroAndMaximum) {
  for (float h : {0.0f, 0.999f}) {
    IrradianceFieldParams params = cornell_grid();
    params.hysteresis = h;
    params.distance_hysteresis = h;
    const std::vector<glm::vec3> values =
        converge(make_cornell_box(), params, cornell_queries(), 8);
    expect_finite_positive(values);
    // The first update has no history to keep, so even 0.999 starts from a real value.
    float total = 0.0f;
    for (const glm::vec3& v : values) total += v.x + v.y + v.z;
    EXPECT_GT(total, 0.0f) << "hysteresis " << h;
  }
}

// 1 ray per probe is as noisy as it gets but stays finite; 1024 rays converge to what 256 rays
// converge to (measured spread between seeds at 256 rays: about 5% per point, so the test
// compares the sum over all points with a 10% tolerance).
TEST_F(FieldExtremesTest, SmallestAndLargestRaysPerProbe) {
  IrradianceFieldParams one = cornell_grid();
  one.rays_per_probe = 1;
  expect_finite_positive(converge(make_cornell_box(), one, cornell_queries(), 16));

  IrradianceFieldParams many = cornell_grid();
  many.rays_per_probe = 1024;
  IrradianceFieldParams fewer = many;
  fewer.rays_per_probe = 256;
  const std::vector<glm::vec3> a = converge(make_cornell_box(), many, cornell_queries(), 32);
  const std::vector<glm::vec3> b = converge(make_cornell_box(), fewer, cornell_queries(), 32);
  expect_finite_positive(a);
  float sum_a = 0.0f, sum_b = 0.0f;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    sum_a += a[i].x + a[i].y + a[i].z;
    sum_b += b[i].x + b[i].y + b[i].z;
  }
  EXPECT_NEAR(sum_a, sum_b, 0.1f * sum_a);
}

TEST_F(FieldExtremesTest, SingleProbeGrid) {
  IrradianceFieldParams params = cornell_grid();
  params.origin = {0.0f, 1.0f, 0.0f};
  params.counts = {1, 1, 1};
  const std::vector<glm::vec3> values = converge(make_cornell_box(), params, cornell_queries());
  expect_finite_positive(values);
}

// A grid whose bottom layer lies exactly in the floor plane (y = 0).
TEST_F(FieldExtremesTest, ProbesExactlyOnASurface) {
  IrradianceFieldParams params = cornell_grid();
  params.origin = {-0.75f, 0.0f, -0.75f};
  expect_finite_positive(converge(make_cornell_box(), params, cornell_queries()));
}

}  // namespace
}  // namespace ddgi::test
