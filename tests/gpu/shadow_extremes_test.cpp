// The shadow field at the edges of its inputs (docs/shadow-field.md, "Extremes"): lights at huge
// distance, inside geometry, exactly on a surface, zero and huge intensities, more lights than
// the field keeps. Each answer stays finite and behaves as documented.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "render/renderer.h"
#include "tests/gpu/field_setup.h"
#include "tests/gpu/gpu_test.h"
#include "tests/gpu/shadow_test_support.h"

namespace ddgi::test {
namespace {

constexpr uint32_t kUpdates = 8;

class ShadowExtremesTest : public GpuTest {
 protected:
  // The field's answers at box_on_floor's floor after kUpdates updates with `lights`.
  std::vector<ShadowFieldAnswer> floor_answers(const std::vector<Light>& lights,
                                               ShadowFieldParams params = box_on_floor_grid()) {
    Scene scene = load_repo_scene("box_on_floor.gltf");
    scene.lights = lights;
    ShadowSetup s = make_shadow_setup(context(), scene, params, context().default_backend());
    EXPECT_TRUE(s.field);
    if (!s.field) return {};
    EXPECT_TRUE(s.field->update(kUpdates, DirectMode::kShadowField).ok());
    auto answers = s.field->query(box_floor_points(-2.5f, 3.0f, -2.5f, 2.5f, 0.25f));
    EXPECT_TRUE(answers.ok()) << answers.error().message;
    return answers.ok() ? *answers : std::vector<ShadowFieldAnswer>{};
  }

  // The linear radiance of a direct-view frame of box_on_floor with `lights`, GI off.
  std::vector<float> direct_frame(const std::vector<Light>& lights, DirectMode mode,
                                  const ShadowFieldParams& params = box_on_floor_grid()) {
    Scene scene = load_repo_scene("box_on_floor.gltf");
    scene.lights = lights;
    auto gpu = GpuScene::create(context(), scene);
    EXPECT_TRUE(gpu.ok()) << gpu.error().message;
    if (!gpu.ok()) return {};
    auto field = ShadowField::create(context(), **gpu, params, context().default_backend());
    EXPECT_TRUE(field.ok()) << field.error().message;
    if (!field.ok()) return {};
    auto renderer =
        Renderer::create(context(), **gpu, nullptr, context().default_backend(), field->get());
    EXPECT_TRUE(renderer.ok()) << renderer.error().message;
    if (!renderer.ok()) return {};
    FrameSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.camera = scene.cameras.at(0);
    settings.view = View::kDirect;
    settings.direct_mode = mode;
    auto frame = render_updated(**renderer, settings, nullptr, field->get(), {0, kUpdates});
    EXPECT_TRUE(frame.ok()) << frame.error().message;
    return frame.ok() ? frame->radiance : std::vector<float>{};
  }
};

bool finite(const std::vector<float>& values) {
  for (float v : values) {
    if (!std::isfinite(v)) return false;
  }
  return !values.empty();
}

float mean_field_visibility(const std::vector<ShadowFieldAnswer>& answers, uint32_t light) {
  double sum = 0.0;
  for (const ShadowFieldAnswer& a : answers) sum += a.field_visibility[light];
  return answers.empty() ? 1.0f : static_cast<float>(sum / answers.size());
}

Light key_light() {
  Light light;
  light.name = "key";
  light.position = {-1.5f, 2.5f, 0.0f};
  light.intensity = 20.0f;
  return light;
}

// A point light 1e20 m away casts the same shadow as a
// directional light from there: its direction survives the squared distance leaving float range
// (lights.glsl measures a scaled copy). Its irradiance underflows to 0; nothing is NaN.
TEST_F(ShadowExtremesTest, LightAtHugeDistanceShadowsLikeTheSun) {
  const glm::vec3 towards = glm::normalize(glm::vec3(-2.0f, 1.2f, 0.4f));  // a low sun
  Light far = key_light();
  far.position = towards * 1e20f;
  far.intensity = 1e30f;
  Light sun = key_light();
  sun.type = LightType::kDirectional;
  sun.direction = -towards;
  sun.intensity = 1.0f;
  const auto far_answers = floor_answers({far});
  const auto sun_answers = floor_answers({sun});
  ASSERT_TRUE(all_finite(far_answers) && all_finite(sun_answers));
  float difference = 0.0f;
  int shadowed = 0;
  for (size_t i = 0; i < far_answers.size(); ++i) {
    difference += std::abs(far_answers[i].field_visibility[0] - sun_answers[i].field_visibility[0]);
    shadowed += far_answers[i].traced_visibility[0] < 0.5f;
  }
  difference /= float(far_answers.size());
  std::printf("far light: error %.4f, sun: error %.4f, far vs sun %.4f, %d shadowed points\n",
              mean_abs_visibility_error(far_answers, 0), mean_abs_visibility_error(sun_answers, 0),
              difference, shadowed);
  EXPECT_GT(shadowed, 10);
  EXPECT_LT(mean_abs_visibility_error(far_answers, 0), 0.04f);
  EXPECT_LT(difference, 0.01f);
  EXPECT_TRUE(finite(direct_frame({far}, DirectMode::kShadowField)));
}

// A light inside the closed cube: every shadow ray from outside hits the cube, so the floor is
// dark in the field as in the traced answer; the frame keeps under 1% of the unshadowed light
// (what is left is the field's blur next to the cube).
TEST_F(ShadowExtremesTest, LightInsideGeometryShadowsEverything) {
  Light inside = key_light();
  inside.position = {0.0f, 0.5f, 0.0f};
  const auto answers = floor_answers({inside});
  ASSERT_TRUE(all_finite(answers));
  float traced = 0.0f;
  for (const ShadowFieldAnswer& a : answers) traced = std::max(traced, a.traced_visibility[0]);
  std::printf("light inside: mean field visibility %.4f, largest traced %.3f\n",
              mean_field_visibility(answers, 0), traced);
  EXPECT_EQ(traced, 0.0f);
  EXPECT_LT(mean_field_visibility(answers, 0), 0.01f);
  const std::vector<float> frame = direct_frame({inside}, DirectMode::kShadowField);
  const std::vector<float> unshadowed = direct_frame({inside}, DirectMode::kUnshadowed);
  ASSERT_TRUE(finite(frame) && finite(unshadowed));
  double sum = 0.0, unshadowed_sum = 0.0;
  for (size_t i = 0; i < frame.size(); ++i) {
    if (i % 4 == 3) continue;  // alpha
    sum += frame[i];
    unshadowed_sum += unshadowed[i];
  }
  std::printf("light inside: frame light %.3g of %.3g unshadowed\n", sum, unshadowed_sum);
  EXPECT_LT(sum, 0.01 * unshadowed_sum);
}

// A light exactly on the floor: the floor sees it at grazing incidence, so neither the field nor
// traced rays light it (visibility 0 where n.l <= 0, in every mode); the cube's face towards it
// is lit. Distances of zero stay finite (the inverse-square law is clamped).
TEST_F(ShadowExtremesTest, LightExactlyOnASurface) {
  Light on_floor = key_light();
  on_floor.position = {1.5f, 0.0f, 0.0f};
  Scene scene = load_repo_scene("box_on_floor.gltf");
  scene.lights = {on_floor};
  ShadowSetup s =
      make_shadow_setup(context(), scene, box_on_floor_grid(), context().default_backend());
  ASSERT_TRUE(s.field);
  ASSERT_TRUE(s.field->update(kUpdates, DirectMode::kShadowField).ok());
  std::vector<ShadowFieldQuery> face;  // the cube's +x face, towards the light
  for (float y = 0.1f; y < 1.0f; y += 0.2f) {
    for (float z = -0.4f; z <= 0.4f; z += 0.2f) {
      ShadowFieldQuery q;
      q.position = {0.5f, y, z};
      q.normal = {1.0f, 0.0f, 0.0f};
      q.to_viewer = q.normal;
      face.push_back(q);
    }
  }
  auto floor = s.field->query(box_floor_points(-2.5f, 3.0f, -2.5f, 2.5f, 0.25f));
  auto lit = s.field->query(face);
  ASSERT_TRUE(floor.ok() && lit.ok());
  ASSERT_TRUE(all_finite(*floor) && all_finite(*lit));
  std::printf("light on the floor: floor visibility %.4f, lit face %.3f (error %.4f)\n",
              mean_field_visibility(*floor, 0), mean_field_visibility(*lit, 0),
              mean_abs_visibility_error(*lit, 0));
  EXPECT_LT(mean_field_visibility(*floor, 0), 0.01f);
  EXPECT_GT(mean_field_visibility(*lit, 0), 0.8f);
  EXPECT_TRUE(finite(direct_frame({on_floor}, DirectMode::kShadowField)));
}

// Visibility is geometry only: a zero-intensity light costs no rays and counts as visible
// (nothing to shadow), and 1e30 W/sr gives exactly the visibility of 20 W/sr. Frames stay finite.
TEST_F(ShadowExtremesTest, ZeroAndHugeIntensities) {
  Light zero = key_light();
  zero.intensity = 0.0f;
  Light huge = key_light();
  huge.intensity = 1e30f;
  const auto zero_answers = floor_answers({zero});
  const auto huge_answers = floor_answers({huge});
  const auto normal_answers = floor_answers({key_light()});
  ASSERT_TRUE(all_finite(zero_answers) && all_finite(huge_answers));
  ASSERT_EQ(huge_answers.size(), normal_answers.size());
  EXPECT_EQ(mean_field_visibility(zero_answers, 0), 1.0f);
  for (size_t i = 0; i < huge_answers.size(); ++i) {
    ASSERT_EQ(huge_answers[i].field_visibility[0], normal_answers[i].field_visibility[0]);
  }
  const std::vector<float> dark = direct_frame({zero}, DirectMode::kShadowField);
  ASSERT_TRUE(finite(dark));
  for (size_t i = 0; i < dark.size(); i += 4) {
    ASSERT_EQ(dark[i] + dark[i + 1] + dark[i + 2], 0.0f);  // black (the floor emits nothing)
  }
  EXPECT_TRUE(finite(direct_frame({huge}, DirectMode::kShadowField)));
}

// Nine lights, eight kept (kShadowMaxLights): the ninth follows the overflow policy. With the
// eight kept ones at zero intensity, the frame is exactly the ninth light's: with traced shadow
// rays as in the shadow-rays mode, or unshadowed as in the unshadowed mode.
TEST_F(ShadowExtremesTest, MoreLightsThanTheFieldKeeps) {
  std::vector<Light> lights(8, key_light());
  for (Light& l : lights) l.intensity = 0.0f;
  lights.push_back(key_light());
  ShadowFieldParams params = box_on_floor_grid();
  params.max_lights = 8;
  for (const ShadowOverflow overflow :
       {ShadowOverflow::kTracedShadows, ShadowOverflow::kUnshadowed}) {
    params.overflow = overflow;
    const std::vector<float> field = direct_frame(lights, DirectMode::kShadowField, params);
    const DirectMode reference_mode = overflow == ShadowOverflow::kTracedShadows
                                          ? DirectMode::kTracedShadows
                                          : DirectMode::kUnshadowed;
    const std::vector<float> reference = direct_frame({key_light()}, reference_mode, params);
    ASSERT_TRUE(finite(field));
    ASSERT_EQ(field.size(), reference.size());
    float worst = 0.0f;
    for (size_t i = 0; i < field.size(); ++i) {
      worst = std::max(worst, std::abs(field[i] - reference[i]) / std::max(reference[i], 1e-3f));
    }
    std::printf("overflow %s: largest relative difference %.2e\n",
                overflow == ShadowOverflow::kTracedShadows ? "shadow-rays" : "unshadowed", worst);
    EXPECT_LT(worst, 1e-5f);
  }
}

}  // namespace
}  // namespace ddgi::test
