// What one field update writes into the atlases, read back texel by texel: back-face hits
// (2021 paper, sec. 4.1), the one-texel octahedral borders, and the scrubbing that keeps NaN
// and Inf out of the persistent history.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/gtc/matrix_transform.hpp>

#include "gi/irradiance_field.h"
#include "gpu_scene/gpu_scene.h"
#include "tests/gpu/field_setup.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/procedural.h"

namespace ddgi::test {
namespace {

class FieldInternalsTest : public GpuTest {};

// Texel (x, y) of channel c of an atlas read back from the GPU.
float texel(const IrradianceField::AtlasImage& atlas, uint32_t x, uint32_t y, uint32_t c) {
  return atlas.texels[(size_t(y) * atlas.width + x) * atlas.channels + c];
}

// One probe at the centre of a 2 m cube, seeing it from inside, in two scenes with the same
// geometry: the white box's inward walls (front faces) and a solid cube's outward faces (back
// faces). Both emit Le = 1 with albedo 0. Probe management is off so that the probe inside
// the solid is traced like any other (classification would switch it Off).
IrradianceFieldParams one_probe_in_the_cube(float backface_distance_scale) {
  IrradianceFieldParams p;
  p.origin = {0.0f, 1.0f, 0.0f};
  p.spacing = glm::vec3(2.0f);  // visibility range 1.5 * |spacing| = 5.2 m: no clamping
  p.counts = {1, 1, 1};
  p.rays_per_probe = 64;
  p.fixed_rays = 0;
  p.relocation_iterations = 0;
  p.classification = false;
  p.backface_distance_scale = backface_distance_scale;
  return p;
}

Scene solid_cube() {
  Scene scene;
  scene.source = "solid emissive cube";
  const int m = add_material(scene, glm::vec3(0.0f), glm::vec3(1.0f), "emitter");
  add_box(scene,
          glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.0f, 0.0f)) *
              glm::scale(glm::mat4(1.0f), glm::vec3(2.0f)),
          m);
  return scene;
}

// Back faces carry no light and their distance is shortened to backface_distance_scale of the
// hit distance. The front-face scene, traced with the same rays (same seed, same update), gives
// the unscaled distances to compare with, texel by texel.
TEST_F(FieldInternalsTest, BackFaceHitsCarryNoLightAndScaledDistance) {
  FieldSetup front =
      make_field_setup(make_white_furnace_box(0.0f, 1.0f), one_probe_in_the_cube(0.2f));
  ASSERT_TRUE(front.field);
  ASSERT_TRUE(front.field->update(1, DirectMode::kTracedShadows).ok());
  auto front_irradiance = front.field->read_irradiance_atlas();
  auto front_distance = front.field->read_distance_atlas();
  ASSERT_TRUE(front_irradiance.ok() && front_distance.ok());

  const uint32_t n_irr = front.field->params().irradiance_texels;
  const uint32_t n_dist = front.field->params().distance_texels;
  for (uint32_t y = 1; y <= n_irr; ++y) {
    for (uint32_t x = 1; x <= n_irr; ++x) {
      // Radiance 1 from every direction: M = 1, encoded 1^(1/gamma) = 1.
      ASSERT_NEAR(texel(*front_irradiance, x, y, 0), 1.0f, 1e-5f) << x << "," << y;
    }
  }

  for (float scale : {0.2f, 0.5f}) {
    FieldSetup back = make_field_setup(solid_cube(), one_probe_in_the_cube(scale));
    ASSERT_TRUE(back.field);
    ASSERT_TRUE(back.field->update(1, DirectMode::kTracedShadows).ok());
    auto irradiance = back.field->read_irradiance_atlas();
    auto distance = back.field->read_distance_atlas();
    ASSERT_TRUE(irradiance.ok() && distance.ok());
    // Every texel's RGB, borders included (alpha is a constant 1): the emitting cube is seen
    // only from behind.
    float brightest = 0.0f;
    for (size_t i = 0; i < irradiance->texels.size(); ++i) {
      if (i % 4 != 3) brightest = std::max(brightest, std::abs(irradiance->texels[i]));
    }
    EXPECT_EQ(brightest, 0.0f) << "back faces must carry no radiance (scale " << scale << ")";

    float worst_mean = 0.0f, worst_square = 0.0f;
    for (uint32_t y = 1; y <= n_dist; ++y) {
      for (uint32_t x = 1; x <= n_dist; ++x) {
        const float d = texel(*front_distance, x, y, 0), d2 = texel(*front_distance, x, y, 1);
        // From the cube's centre every direction hits a wall between 1 and sqrt(3) m away.
        ASSERT_GE(d, 0.99f);
        ASSERT_LE(d, 1.74f);
        worst_mean = std::max(worst_mean, std::abs(texel(*distance, x, y, 0) / (scale * d) - 1));
        worst_square =
            std::max(worst_square, std::abs(texel(*distance, x, y, 1) / (scale * scale * d2) - 1));
      }
    }
    // Measured: 3.0e-7 / 3.6e-7 at scale 0.2, exactly 0 at 0.5.
    EXPECT_LE(worst_mean, 1e-4f) << "mean distance, scale " << scale;
    EXPECT_LE(worst_square, 1e-4f) << "mean squared distance, scale " << scale;
  }
}

// Where border texel (x, y) of an n x n octahedral map (x or y is -1 or n, relative to the
// first interior texel) takes its value from: the octahedral map folds over each edge, so a
// texel just past an edge is its mirror image along that edge, and a corner is the opposite
// corner (Cigolle et al. 2014; the 2019 paper's one-texel border).
glm::ivec2 border_source(glm::ivec2 t, int n) {
  if (t.x < 0 || t.x >= n) {
    t.x = t.x < 0 ? 0 : n - 1;
    t.y = n - 1 - t.y;
  }
  if (t.y < 0 || t.y >= n) {
    t.y = t.y < 0 ? 0 : n - 1;
    t.x = n - 1 - t.x;
  }
  return t;
}

// Checks every border texel of every probe's tile in `atlas` against its mirrored interior
// texel; returns how many interior texels differ from their tile's first one (so the caller
// can tell that the comparison was not between equal values everywhere).
int check_borders(const IrradianceField::AtlasImage& atlas, uint32_t probes, uint32_t n,
                  uint32_t tiles_per_row, const char* what) {
  const uint32_t tile = n + 2;
  int varied = 0;
  for (uint32_t p = 0; p < probes; ++p) {
    const glm::ivec2 origin(int((p % tiles_per_row) * tile) + 1,
                            int((p / tiles_per_row) * tile) + 1);
    for (int y = -1; y <= int(n); ++y) {
      for (int x = -1; x <= int(n); ++x) {
        const bool border = x < 0 || y < 0 || x >= int(n) || y >= int(n);
        for (uint32_t c = 0; c < atlas.channels; ++c) {
          const float v = texel(atlas, uint32_t(origin.x + x), uint32_t(origin.y + y), c);
          if (!border) {
            if (v != texel(atlas, uint32_t(origin.x), uint32_t(origin.y), c)) ++varied;
            continue;
          }
          const glm::ivec2 s = border_source({x, y}, int(n));
          const float expected =
              texel(atlas, uint32_t(origin.x + s.x), uint32_t(origin.y + s.y), c);
          // A copy: exactly equal.
          if (v != expected) {
            ADD_FAILURE() << what << " probe " << p << " border (" << x << ", " << y << ") channel "
                          << c << " is " << v << ", its source (" << s.x << ", " << s.y << ") "
                          << expected;
            return varied;
          }
        }
      }
    }
  }
  return varied;
}

// After updates in the lit Cornell box (every probe's maps vary), each one-texel border equals
// the mirrored interior texel, in both atlases. The atlas sizes follow the documented layout.
TEST_F(FieldInternalsTest, BordersMirrorTheInteriorTexels) {
  IrradianceFieldParams params;
  params.origin = {-0.6f, 0.4f, -0.6f};
  params.spacing = glm::vec3(0.6f);
  params.counts = {3, 2, 3};  // 18 probes: a 5-wide tile row, the last row partly empty
  params.rays_per_probe = 64;
  params.fixed_rays = 8;
  params.irradiance_texels = 6;
  params.distance_texels = 10;
  FieldSetup s = make_field_setup(make_cornell_box(), params);
  ASSERT_TRUE(s.field);
  ASSERT_TRUE(s.field->update(3, DirectMode::kTracedShadows).ok());
  auto irradiance = s.field->read_irradiance_atlas();
  auto distance = s.field->read_distance_atlas();
  ASSERT_TRUE(irradiance.ok() && distance.ok());
  const uint32_t probes = 18, tiles_per_row = 5;  // ceil(sqrt(18))
  EXPECT_EQ(irradiance->width, tiles_per_row * 8);
  EXPECT_EQ(irradiance->height, 4u * 8);
  EXPECT_EQ(distance->width, tiles_per_row * 12);
  EXPECT_EQ(distance->height, 4u * 12);
  ASSERT_EQ(irradiance->channels, 4u);
  ASSERT_EQ(distance->channels, 2u);
  const int varied_irradiance = check_borders(*irradiance, probes, 6, tiles_per_row, "irradiance");
  const int varied_distance = check_borders(*distance, probes, 10, tiles_per_row, "distance");
  // Measured: 1890 of 2592 irradiance and 3564 of 3600 distance values differ from their
  // tile's first texel.
  EXPECT_GT(varied_irradiance, int(probes) * 6 * 6);
  EXPECT_GT(varied_distance, int(probes) * 10 * 10);
}

// An emitter of radiance 1e38 (finite, FLT_MAX is 3.4e38): a texel's weighted sum over the
// rays that see it overflows to Inf in fp32 as soon as a few rays hit it, and feeding such
// texels back through the walls' albedo does it again. The update's scrubbing must keep every
// atlas texel and every answer finite and non-negative, on both backends.
TEST_F(FieldInternalsTest, OverflowingRadianceNeverEntersTheAtlases) {
  Scene scene = make_cornell_box();
  const int hot = add_material(scene, glm::vec3(0.0f), glm::vec3(1e38f), "overflowing emitter");
  add_quad(scene, {-0.4f, 1.98f, 0.4f}, {-0.4f, 1.98f, -0.4f}, {0.4f, 1.98f, -0.4f},
           {0.4f, 1.98f, 0.4f}, hot);
  IrradianceFieldParams params;
  params.origin = {-0.6f, 0.4f, -0.6f};
  params.spacing = glm::vec3(0.6f);
  params.counts = {3, 3, 3};
  params.rays_per_probe = 64;
  params.fixed_rays = 8;
  params.hysteresis = 0.5f;
  for (vk::TraceBackend backend : {vk::TraceBackend::kRayQuery, vk::TraceBackend::kPipeline}) {
    FieldSetup s = make_field_setup(scene, params, backend);
    ASSERT_TRUE(s.field);
    ASSERT_TRUE(s.field->update(4, DirectMode::kTracedShadows).ok());
    int bad = 0, huge = 0;
    for (bool irradiance : {true, false}) {
      auto atlas = irradiance ? s.field->read_irradiance_atlas() : s.field->read_distance_atlas();
      ASSERT_TRUE(atlas.ok());
      for (float v : atlas->texels) {
        if (!std::isfinite(v) || v < 0.0f) ++bad;
        // Encoded irradiance of a texel that saw the emitter: (> 1e36)^(1/5) > 1.5e7.
        if (irradiance && v > 1e7f) ++huge;
      }
    }
    EXPECT_EQ(bad, 0) << "non-finite or negative atlas texels, backend "
                      << vk::backend_name(backend);
    // The emitter really is in the atlases (not skipped), so the overflow did happen nearby.
    // Measured: 7858 such values on both backends. With the scrubbing in the irradiance blend
    // removed, 349 non-finite texels appear and this test fails.
    EXPECT_GT(huge, 0);
    auto answers = s.field->query({{{0.0f, 0.001f, 0.0f}, {0, 1, 0}, {0, 1, 0}},
                                   {{0.0f, 1.0f, -0.999f}, {0, 0, 1}, {0, 0, 1}}});
    ASSERT_TRUE(answers.ok()) << answers.error().message;
    for (const glm::vec3& m : *answers) {
      for (int c = 0; c < 3; ++c) EXPECT_TRUE(std::isfinite(m[c]) && m[c] >= 0.0f) << m[c];
    }
  }
}

}  // namespace
}  // namespace ddgi::test
