// Light leaking through a thin wall (issue 3's acceptance): in the two-room scene with the door
// closed, the wall (2 cm) is far thinner than the probe spacing (0.5 m), yet indirect light in
// the dark room must stay under 1% of the lit room's mean.
#include <gtest/gtest.h>

#include "gi/irradiance_field.h"
#include "render/gpu_scene.h"
#include "scene/gltf_loader.h"
#include "tests/gpu/gpu_test.h"

namespace ddgi::test {
namespace {

// scenes/two_rooms_*.gltf: shell x in [-4.1, 3.9], y in [0, 3], z in [-2, 2]; the shared wall
// spans x in [-0.01, 0.01] with a doorway at z in [-0.45, 0.45], y in [0, 2]; the lit room is
// x < 0. Probes at x = -3.85 + 0.5 i: the nearest are at -0.35 and 0.15, none in the wall.
IrradianceFieldParams two_room_grid() {
  IrradianceFieldParams p;
  p.origin = {-3.85f, 0.25f, -1.75f};
  p.spacing = {0.5f, 0.5f, 0.5f};
  p.counts = {16, 6, 8};
  p.rays_per_probe = 128;
  p.fixed_rays = 0;
  p.hysteresis = 0.8f;
  return p;
}

// Surface points of one room (side -1: lit, +1: dark), concentrated near the shared wall where
// leaks show: the wall itself, the floor and ceiling beside it, and the far walls.
std::vector<IrradianceQuery> room_points(float side) {
  std::vector<IrradianceQuery> q;
  const glm::vec3 wall_normal(side, 0.0f, 0.0f);
  for (float y : {0.3f, 1.0f, 2.5f}) {
    for (float z : {-1.5f, -0.9f, 0.9f, 1.5f}) {  // beside the (closed) door, not on it
      q.push_back({{side * 0.0101f, y, z}, wall_normal, wall_normal});
    }
  }
  for (float x : {0.2f, 0.6f, 1.5f, 3.0f}) {
    for (float z : {-1.2f, 0.0f, 1.2f}) {
      q.push_back({{side * x, 0.0001f, z}, {0, 1, 0}, {0, 1, 0}});
      q.push_back({{side * x, 2.9999f, z}, {0, -1, 0}, {0, -1, 0}});
    }
  }
  return q;
}

float mean_luminance(const std::vector<glm::vec3>& values) {
  double sum = 0.0;
  for (const glm::vec3& v : values) sum += 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z;
  return values.empty() ? 0.0f : static_cast<float>(sum / values.size());
}

class LightLeakTest : public GpuTest {
 protected:
  // Mean field luminance at the lit room's and the dark room's surface points.
  std::pair<float, float> room_means(const std::string& scene_file) {
    auto scene = load_scene(std::string(DDGI_SOURCE_DIR) + "/scenes/" + scene_file);
    EXPECT_TRUE(scene.ok()) << scene.error().message;
    if (!scene.ok()) return {0.0f, 0.0f};
    auto gpu = GpuScene::create(context(), *scene);
    EXPECT_TRUE(gpu.ok()) << gpu.error().message;
    auto field =
        IrradianceField::create(context(), **gpu, two_room_grid(), context().default_backend());
    EXPECT_TRUE(field.ok()) << field.error().message;
    if (!gpu.ok() || !field.ok()) return {0.0f, 0.0f};
    EXPECT_TRUE((*field)->update(16, DirectMode::kTracedShadows).ok());
    auto lit = (*field)->query(room_points(-1.0f));
    auto dark = (*field)->query(room_points(+1.0f));
    EXPECT_TRUE(lit.ok() && dark.ok());
    if (!lit.ok() || !dark.ok()) return {0.0f, 0.0f};
    const float lit_mean = mean_luminance(*lit);
    const float dark_mean = mean_luminance(*dark);
    std::printf("%s: lit room mean %.5f, dark room mean %.7f (%.4f%%)\n", scene_file.c_str(),
                lit_mean, dark_mean, 100.0f * dark_mean / lit_mean);
    return {lit_mean, dark_mean};
  }
};

TEST_F(LightLeakTest, ClosedDoorKeepsTheDarkRoomDark) {
  const auto [lit, dark] = room_means("two_rooms_closed.gltf");
  EXPECT_GT(lit, 0.01f);
  EXPECT_LT(dark, 0.01f * lit);
}

// The same measurement sees light when there is a way for it: with the door open, the dark
// room's points are well above the 1% bound (so the closed-door pass is not a blind metric).
TEST_F(LightLeakTest, OpenDoorLetsLightIn) {
  const auto [lit, dark] = room_means("two_rooms_open.gltf");
  EXPECT_GT(lit, 0.01f);
  EXPECT_GT(dark, 0.02f * lit);
}

}  // namespace
}  // namespace ddgi::test
