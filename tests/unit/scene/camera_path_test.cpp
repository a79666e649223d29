// Camera paths (scene/camera_path.h): the pose between keyframes against hand-computed values,
// the repository's street walk read whole, and refusals that name what is wrong.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "scene/camera_path.h"
#include "test_support.h"

namespace ddgi {
namespace {

using ::testing::AllOf;
using testing::error_of;
using ::testing::HasSubstr;
using testing::json;
using testing::to_bytes;

Result<CameraPath> parse(const json& document) {
  return parse_camera_path(to_bytes(document.dump()), "walk.path.json");
}

json keyframe(double time, std::vector<float> position, std::vector<float> target) {
  return {{"time", time}, {"position", position}, {"target", target}};
}

TEST(CameraPath, PoseIsLinearBetweenKeyframesAndClampedOutside) {
  const Result<CameraPath> path =
      parse({{"keyframes",
              {keyframe(0, {0, 1, 0}, {1, 1, 0}), keyframe(10, {10, 1, 0}, {10, 1, 5}),
               keyframe(12, {10, 1, 2}, {10, 1, 5})}}});
  ASSERT_TRUE(path.ok()) << error_of(path);
  EXPECT_DOUBLE_EQ(path->duration(), 12.0);
  // At 2.5 s, a quarter of the first segment: position (2.5, 1, 0), target (3.25, 1, 1.25).
  const CameraPose quarter = path->pose_at(2.5);
  EXPECT_NEAR(quarter.position.x, 2.5f, 1e-6f);
  EXPECT_NEAR(quarter.target.x, 3.25f, 1e-6f);
  EXPECT_NEAR(quarter.target.z, 1.25f, 1e-6f);
  // Half the second segment: position (10, 1, 1).
  EXPECT_NEAR(path->pose_at(11.0).position.z, 1.0f, 1e-6f);
  // Exactly on a keyframe, and outside the path: that keyframe.
  EXPECT_EQ(path->pose_at(10.0).position, glm::vec3(10, 1, 0));
  EXPECT_EQ(path->pose_at(-3.0).position, glm::vec3(0, 1, 0));
  EXPECT_EQ(path->pose_at(99.0).position, glm::vec3(10, 1, 2));
  // The camera looks from the position at the target, up +Y: at 2.5 s along (0.75, 0, 1.25).
  const Camera camera = path->camera_at(2.5, 0.7f);
  const glm::vec3 forward = glm::normalize(glm::vec3(0.75f, 0.0f, 1.25f));
  EXPECT_NEAR(glm::distance(camera.forward, forward), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(camera.up, glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
  EXPECT_FLOAT_EQ(camera.yfov, 0.7f);
}

TEST(CameraPath, TheStreetWalkReads) {
  const Result<CameraPath> path =
      read_camera_path(std::filesystem::path(DDGI_REPO_SCENES_DIR) / "street.path.json");
  ASSERT_TRUE(path.ok()) << error_of(path);
  EXPECT_EQ(path->scene, "street.ddgi.json");
  ASSERT_EQ(path->keyframes.size(), 9u);
  // Along the street at 1.4 m/s: 184 m in 131.429 s.
  EXPECT_NEAR(path->keyframes[1].time, 184.0 / 1.4, 1e-3);
  EXPECT_EQ(path->pose_at(0.0).position, glm::vec3(-180.0f, 1.7f, 0.0f));
  EXPECT_NEAR(path->pose_at(path->duration()).position.x, 180.0f, 1e-4f);
}

struct BadPath {
  json document;
  std::string message;
};

class CameraPathErrors : public ::testing::TestWithParam<BadPath> {};

TEST_P(CameraPathErrors, AreRefusedNamingFileAndKey) {
  const Result<CameraPath> path = parse(GetParam().document);
  ASSERT_FALSE(path.ok());
  EXPECT_THAT(error_of(path), AllOf(HasSubstr("walk.path.json: "), HasSubstr(GetParam().message)));
}

const json kStart = keyframe(0, {0, 0, 0}, {1, 0, 0});

INSTANTIATE_TEST_SUITE_P(
    CameraPath, CameraPathErrors,
    ::testing::Values(
        BadPath{{{"scene", "s.gltf"}}, "keyframes: missing"},
        BadPath{{{"keyframes", {kStart}}, {"speed", 1}}, "speed: unknown key"},
        BadPath{{{"keyframes", {kStart}}}, "keyframes: expected an array of 2 to 100000"},
        BadPath{
            {{"keyframes", {keyframe(1, {0, 0, 0}, {1, 0, 0}), keyframe(2, {1, 0, 0}, {2, 0, 0})}}},
            "keyframes[0].time: the first keyframe must be at time 0"},
        BadPath{{{"keyframes", {kStart, keyframe(0, {1, 0, 0}, {2, 0, 0})}}},
                "keyframes[1].time: must be later than the keyframe before it"},
        BadPath{{{"keyframes", {kStart, keyframe(-1, {1, 0, 0}, {2, 0, 0})}}},
                "keyframes[1].time: expected a number in [0, 1000000], got -1"},
        BadPath{{{"keyframes", {kStart, {{"time", 1}, {"position", {1, 0, 0}}}}}},
                "keyframes[1].target: missing"},
        BadPath{{{"keyframes", {kStart, keyframe(1, {1, 0}, {2, 0, 0})}}},
                "keyframes[1].position: expected an array of 3 numbers"},
        // The view turns from +x to -x: halfway the camera would look at its own position.
        BadPath{{{"keyframes", {kStart, keyframe(1, {1, 0, 0}, {0, 0, 0})}}},
                "keyframes[0] to [1]: the camera would look straight up or down, or at its own"},
        // Straight up at a keyframe.
        BadPath{{{"keyframes", {kStart, keyframe(1, {1, 0, 0}, {1, 5, 0})}}},
                "keyframes[0] to [1]: the camera would look straight up or down"},
        BadPath{{{"description", 3}, {"keyframes", {kStart, kStart}}},
                "description: expected a string, got 3"}));

TEST(CameraPath, RepeatedKeysAreRefused) {
  const std::string text =
      R"({"keyframes": [{"time": 0, "time": 1, "position": [0,0,0], "target": [1,0,0]}]})";
  const Result<CameraPath> path = parse_camera_path(to_bytes(text), "walk.path.json");
  EXPECT_THAT(error_of(path), HasSubstr("key 'time' appears twice"));
}

}  // namespace
}  // namespace ddgi
