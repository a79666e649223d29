// Sidecars (docs/sidecar-format.md): what they add to a scene, and strict validation whose
// errors name the file, the key path and the expectation.
#include <cmath>
#include <filesystem>

#include <ImfRgbaFile.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_support.h"

namespace ddgi {
namespace {

using ::testing::AllOf;
using ::testing::Contains;
using testing::error_of;
using testing::GltfBuilder;
using ::testing::HasSubstr;
using testing::json;
using testing::TempDir;

namespace fs = std::filesystem;

// A 4x2 half-float EXR: pixel (x, y) = (x, y, 0.5), with one negative pixel at (3, 1).
void write_exr(const fs::path& path) {
  fs::create_directories(path.parent_path());
  std::vector<Imf::Rgba> pixels;
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 4; ++x) pixels.emplace_back(float(x), float(y), 0.5f, 1.0f);
  }
  pixels[7].r = -1.0f;
  Imf::RgbaOutputFile file(path.c_str(), 4, 2, Imf::WRITE_RGB);
  file.setFrameBuffer(pixels.data(), 1, 4);
  file.writePixels(2);
}

// A scene with one emissive-less material named "light" beside a sidecar with `sidecar`.
struct SceneWithSidecar {
  TempDir dir;
  fs::path gltf;
  fs::path sidecar;

  explicit SceneWithSidecar(const json& sidecar_json) : SceneWithSidecar(sidecar_json.dump()) {}
  explicit SceneWithSidecar(const std::string& sidecar_text) {
    GltfBuilder b = testing::triangle_builder();
    b.doc()["meshes"][0]["primitives"][0]["material"] =
        b.add_material({{"name", "light"}, {"emissiveFactor", {0.5, 0.5, 0.5}}});
    b.add_material({{"name", "wall"}});
    gltf = dir.write("room.gltf", b.gltf_text());
    sidecar = dir.write("room.ddgi.json", sidecar_text);
  }
  Result<Scene> load() const { return load_scene(gltf.string()); }
};

TEST(Sidecar, EverythingItCanSay) {
  SceneWithSidecar s(json{
      {"camera",
       {{"position", {0, 1, 3.5}}, {"target", {0, 1, 0}}, {"up", {0, 2, 0}}, {"yfov_degrees", 40}}},
      {"environment", {{"color", {0.1, 0.2, 0.3}}, {"intensity", 2}, {"rotation_degrees", 90}}},
      {"lights",
       {{{"type", "point"},
         {"name", "key"},
         {"position", {0, 1.9, 0}},
         {"intensity", 5},
         {"radius", 0.05}},
        {{"type", "spot"},
         {"position", {0, 2, 0}},
         {"direction", {0, -2, 0}},
         {"inner_cone_degrees", 20},
         {"outer_cone_degrees", 30},
         {"color", {1, 0.5, 0}}},
        {{"type", "directional"}, {"direction", {0, 0, -3}}, {"intensity", 3}}}},
      {"materials",
       {{"light",
         {{"emissive", {1, 1, 1}},
          {"emissive_strength", 17},
          {"base_color", {0.2, 0.2, 0.2, 1}},
          {"transmission", 0.5},
          {"double_sided", true}}}}},
      {"probe_grid",
       {{"origin", {-1, 0, -1}}, {"spacing", {0.5, 0.5, 0.5}}, {"counts", {5, 6, 7}}}},
      {"probe_volumes",
       {{{"origin", {-0.5, 0.25, -0.5}}, {"spacing", {0.25, 0.25, 0.5}}, {"counts", {3, 4, 2}}},
        {{"origin", {-4, 0, -4}}, {"spacing", {2, 2, 2}}, {"counts", {5, 3, 5}}}}}});
  Result<Scene> scene = s.load();
  ASSERT_TRUE(scene.ok()) << error_of(scene);

  ASSERT_EQ(scene->cameras.size(), 1u);
  const Camera& camera = scene->cameras[0];
  EXPECT_EQ(camera.position, glm::vec3(0, 1, 3.5f));
  EXPECT_EQ(camera.forward, glm::vec3(0, 0, -1));
  EXPECT_EQ(camera.up, glm::vec3(0, 1, 0));
  EXPECT_NEAR(camera.yfov, 40.0 * M_PI / 180.0, 1e-6);

  EXPECT_EQ(scene->environment.color, glm::vec3(0.1f, 0.2f, 0.3f));
  EXPECT_FLOAT_EQ(scene->environment.intensity, 2.0f);
  EXPECT_NEAR(scene->environment.rotation_y, M_PI / 2, 1e-6);
  EXPECT_FALSE(scene->environment.image.has_value());

  ASSERT_EQ(scene->lights.size(), 3u);
  EXPECT_EQ(scene->lights[0].name, "key");
  EXPECT_EQ(scene->lights[0].position, glm::vec3(0, 1.9f, 0));
  EXPECT_FLOAT_EQ(scene->lights[0].radius, 0.05f);
  EXPECT_EQ(scene->lights[1].type, LightType::kSpot);
  EXPECT_EQ(scene->lights[1].direction, glm::vec3(0, -1, 0));
  EXPECT_NEAR(scene->lights[1].inner_cone_angle, 20.0 * M_PI / 180.0, 1e-6);
  EXPECT_NEAR(scene->lights[1].outer_cone_angle, 30.0 * M_PI / 180.0, 1e-6);
  EXPECT_EQ(scene->lights[1].color, glm::vec3(1, 0.5f, 0));
  EXPECT_EQ(scene->lights[2].type, LightType::kDirectional);
  EXPECT_EQ(scene->lights[2].direction, glm::vec3(0, 0, -1));

  const Material& light = scene->materials.at(0);
  EXPECT_EQ(light.emissive, glm::vec3(17.0f));
  EXPECT_EQ(light.base_color, glm::vec4(0.2f, 0.2f, 0.2f, 1.0f));
  EXPECT_FLOAT_EQ(light.transmission, 0.5f);
  EXPECT_TRUE(light.double_sided);
  EXPECT_EQ(scene->materials.at(1).emissive, glm::vec3(0.0f));  // "wall" untouched

  ASSERT_TRUE(scene->probe_grid.has_value());
  EXPECT_EQ(scene->probe_grid->origin, glm::vec3(-1, 0, -1));
  EXPECT_EQ(scene->probe_grid->spacing, glm::vec3(0.5f));
  EXPECT_EQ(scene->probe_grid->counts, glm::ivec3(5, 6, 7));
  ASSERT_EQ(scene->probe_volumes.size(), 2u);
  EXPECT_EQ(scene->probe_volumes[0].origin, glm::vec3(-0.5f, 0.25f, -0.5f));
  EXPECT_EQ(scene->probe_volumes[0].spacing, glm::vec3(0.25f, 0.25f, 0.5f));
  EXPECT_EQ(scene->probe_volumes[0].counts, glm::ivec3(3, 4, 2));
  EXPECT_EQ(scene->probe_volumes[1].origin, glm::vec3(-4.0f, 0.0f, -4.0f));
  EXPECT_EQ(scene->probe_volumes[1].counts, glm::ivec3(5, 3, 5));
}

TEST(Sidecar, EmissiveStrengthAloneScalesTheGltfFactor) {
  SceneWithSidecar s(json{{"materials", {{"light", {{"emissive_strength", 4}}}}}});
  Result<Scene> scene = s.load();
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_EQ(scene->materials.at(0).emissive, glm::vec3(2.0f));
}

TEST(Sidecar, CameraGoesFirstBeforeTheGltfCameras) {
  TempDir dir;
  GltfBuilder b = testing::triangle_builder();
  b.doc()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 1}, {"znear", 0.1}}}}};
  b.doc()["nodes"][0]["camera"] = 0;
  const fs::path gltf = dir.write("a.gltf", b.gltf_text());
  dir.write("a.ddgi.json",
            json{{"camera", {{"position", {0, 0, 0}}, {"target", {1, 0, 0}}}}}.dump());
  Result<Scene> scene = load_scene(gltf.string());
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_EQ(scene->cameras.size(), 2u);
  EXPECT_EQ(scene->cameras[0].forward, glm::vec3(1, 0, 0));
  EXPECT_NEAR(scene->cameras[0].yfov, M_PI / 4, 1e-6);  // the default 45 degrees
  EXPECT_FLOAT_EQ(scene->cameras[1].yfov, 1.0f);
}

TEST(Sidecar, EnvironmentImageFromExr) {
  TempDir dir;
  write_exr(dir.path() / "sky" / "env.exr");
  const fs::path gltf = dir.write("a.gltf", testing::triangle_builder().gltf_text());
  dir.write("a.ddgi.json",
            json{{"environment", {{"image", "sky/env.exr"}, {"intensity", 3}}}}.dump());
  Result<Scene> scene = load_scene(gltf.string());
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_TRUE(scene->environment.image.has_value());
  const EnvironmentImage& image = *scene->environment.image;
  EXPECT_EQ(image.width, 4u);
  EXPECT_EQ(image.height, 2u);
  // Row 1, column 2: (2, 1, 0.5).
  EXPECT_FLOAT_EQ(image.rgb[(1 * 4 + 2) * 3 + 0], 2.0f);
  EXPECT_FLOAT_EQ(image.rgb[(1 * 4 + 2) * 3 + 1], 1.0f);
  EXPECT_FLOAT_EQ(image.rgb[(1 * 4 + 2) * 3 + 2], 0.5f);
  EXPECT_FLOAT_EQ(image.rgb[(1 * 4 + 3) * 3 + 0], 0.0f);  // the negative value, zeroed
  EXPECT_THAT(scene->warnings, Contains(HasSubstr("1 negative or non-finite")));
  EXPECT_FLOAT_EQ(scene->environment.intensity, 3.0f);
  EXPECT_TRUE(scene->has_any_light());

  SceneLimits limits;
  limits.max_environment_width = 3;
  EXPECT_THAT(error_of(load_scene(gltf.string(), limits)),
              AllOf(HasSubstr("a.ddgi.json: environment.image"), HasSubstr("4x2 is outside")));
  dir.write("a.ddgi.json", json{{"environment", {{"image", "sky/none.exr"}}}}.dump());
  EXPECT_THAT(error_of(load_scene(gltf.string())),
              AllOf(HasSubstr("environment.image"), HasSubstr("no such file")));
  dir.write("sky/bad.exr", std::string("not an exr at all"));
  dir.write("a.ddgi.json", json{{"environment", {{"image", "sky/bad.exr"}}}}.dump());
  EXPECT_THAT(error_of(load_scene(gltf.string())), HasSubstr("cannot read the EXR image"));
}

TEST(Sidecar, LoadedDirectlyItNamesItsScene) {
  TempDir dir;
  dir.write("scenes/shared/room.gltf", testing::triangle_builder().gltf_text());
  const fs::path sidecar = dir.write(
      "config/room.ddgi.json",
      json{{"scene", "../scenes/shared/room.gltf"}, {"environment", {{"color", {1, 1, 1}}}}}
          .dump());
  Result<Scene> scene = load_scene(sidecar.string());
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_EQ(scene->environment.color, glm::vec3(1.0f));
  EXPECT_THAT(scene->source, HasSubstr("room.gltf"));

  const fs::path no_scene = dir.write("config/none.ddgi.json", std::string("{}"));
  EXPECT_THAT(error_of(load_scene(no_scene.string())),
              AllOf(HasSubstr("none.ddgi.json"), HasSubstr("scene: required")));
  const fs::path not_gltf = dir.write("config/obj.ddgi.json", json{{"scene", "x.obj"}}.dump());
  EXPECT_THAT(error_of(load_scene(not_gltf.string())), HasSubstr("expected a .gltf or .glb"));
}

TEST(Sidecar, BesideAGltfItMayOnlyNameThatGltf) {
  SceneWithSidecar same(json{{"scene", "room.gltf"}});
  EXPECT_TRUE(same.load().ok()) << error_of(same.load());
  SceneWithSidecar other(json{{"scene", "other.gltf"}});
  EXPECT_THAT(error_of(other.load()), HasSubstr("sits beside"));
}

struct BadSidecar {
  json sidecar;
  const char* expected_message;
};

class SidecarErrors : public ::testing::TestWithParam<BadSidecar> {};

TEST_P(SidecarErrors, NameFileKeyAndExpectation) {
  SceneWithSidecar s(GetParam().sidecar);
  Result<Scene> scene = s.load();
  ASSERT_FALSE(scene.ok());
  EXPECT_THAT(error_of(scene),
              AllOf(HasSubstr(s.sidecar.string()), HasSubstr(GetParam().expected_message)));
}

INSTANTIATE_TEST_SUITE_P(
    Sidecar, SidecarErrors,
    ::testing::Values(
        BadSidecar{{{"cammera", json::object()}}, "cammera: unknown key (expected one of: scene"},
        BadSidecar{{{"camera", {{"position", {0, 0, 0}}, {"target", {0, 0, 1}}, {"fov", 3}}}},
                   "camera.fov: unknown key"},
        BadSidecar{
            {{"camera", {{"position", {0, 0}}, {"target", {0, 0, 1}}}}},
            "camera.position: expected an array of 3 numbers, each a finite number, got [0,0]"},
        BadSidecar{{{"camera", {{"position", {0, 0, 1}}, {"target", {0, 0, 1}}}}},
                   "camera: 'position' and 'target' must differ"},
        BadSidecar{{{"camera", {{"position", {0, 0, 0}}, {"target", {0, 1, 0}}}}},
                   "camera: 'up' must not be parallel"},
        BadSidecar{
            {{"camera", {{"position", {0, 0, 0}}, {"target", {1, 0, 0}}, {"yfov_degrees", 180}}}},
            "camera.yfov_degrees: expected a number in (0, 179], got 180"},
        BadSidecar{{{"camera", {{"target", {1, 0, 0}}}}}, "'position' and 'target' are required"},
        BadSidecar{{{"environment", {{"color", {1, -1, 0}}}}},
                   "environment.color: expected an array of 3 numbers, each a finite number >= 0"},
        BadSidecar{{{"environment", {{"color", {1, 1, 1}}, {"image", "a.exr"}}}},
                   "give 'color' or 'image', not both"},
        BadSidecar{{{"environment", {{"image", "sky.hdr"}}}},
                   "environment.image: expected an .exr"},
        BadSidecar{{{"environment", {{"image", "/abs/sky.exr"}}}},
                   "environment.image: expected a path relative to the sidecar's folder"},
        BadSidecar{{{"environment", {{"intensity", -1}}}},
                   "environment.intensity: expected a finite number >= 0, got -1"},
        BadSidecar{{{"lights", json::object()}}, "lights: expected an array of lights"},
        BadSidecar{{{"lights", {{{"type", "area"}}}}},
                   "lights[0].type: expected \"point\", \"spot\" or \"directional\""},
        BadSidecar{{{"lights", {{{"type", "point"}}}}}, "lights[0]: 'position' is required"},
        BadSidecar{
            {{"lights", {{{"type", "point"}, {"position", {0, 0, 0}}, {"direction", {0, 0, 1}}}}}},
            "lights[0].direction: unknown key"},
        BadSidecar{{{"lights", {{{"type", "directional"}, {"direction", {0, 0, 0}}}}}},
                   "lights[0].direction: expected a non-zero direction"},
        BadSidecar{{{"lights",
                     {{{"type", "spot"},
                       {"position", {0, 0, 0}},
                       {"direction", {0, 0, 1}},
                       {"inner_cone_degrees", 40},
                       {"outer_cone_degrees", 30}}}}},
                   "lights[0]: inner_cone_degrees (40) must be less than outer_cone_degrees (30)"},
        BadSidecar{{{"lights", {{{"type", "point"}, {"position", {0, 0, 0}}, {"intensity", "x"}}}}},
                   "lights[0].intensity: expected a finite number >= 0, got \"x\""},
        BadSidecar{{{"materials", {{"nosuch", {{"emissive", {1, 1, 1}}}}}}},
                   "materials.nosuch: no material with this name"},
        BadSidecar{
            {{"materials", {{"light", {{"base_color", {2, 0, 0, 1}}}}}}},
            "materials.light.base_color: expected an array of 4 numbers, each a number in [0, 1]"},
        BadSidecar{{{"materials", {{"light", {{"double_sided", 1}}}}}},
                   "materials.light.double_sided: expected true or false"},
        BadSidecar{{{"materials", {{"light", {{"glow", 1}}}}}},
                   "materials.light.glow: unknown key"},
        BadSidecar{{{"probe_grid",
                     {{"origin", {0, 0, 0}}, {"spacing", {1, 0, 1}}, {"counts", {2, 2, 2}}}}},
                   "probe_grid.spacing: expected an array of 3 numbers, each a finite number > 0"},
        BadSidecar{{{"probe_grid",
                     {{"origin", {0, 0, 0}}, {"spacing", {1, 1, 1}}, {"counts", {2, 2.5, 2}}}}},
                   "probe_grid.counts: expected an array of 3 integers, each in [1, 512]"},
        BadSidecar{{{"probe_grid",
                     {{"origin", {0, 0, 0}}, {"spacing", {1, 1, 1}}, {"counts", {2, 513, 2}}}}},
                   "probe_grid.counts"},
        BadSidecar{{{"probe_grid",
                     {{"origin", {1e300, 0, 0}}, {"spacing", {1, 1, 1}}, {"counts", {2, 2, 2}}}}},
                   "probe_grid.origin: expected an array of 3 numbers, each a finite number"},
        BadSidecar{{{"lights", {{{"type", "directional"}, {"direction", {3e38, 3e38, 0}}}}}},
                   "lights[0].direction: expected a non-zero direction of finite length"},
        BadSidecar{{{"probe_grid", {{"origin", {0, 0, 0}}}}},
                   "probe_grid: 'origin', 'spacing' and 'counts' are all required"},
        BadSidecar{{{"probe_volumes",
                     {{{"origin", {0, 0, 0}}, {"spacing", {1, 1, 1}}, {"counts", {2, 2, 2}}},
                      {{"origin", {0, 0, 0}}, {"spacing", {1, -1, 1}}, {"counts", {2, 2, 2}}}}}},
                   "probe_volumes[1].spacing: expected an array of 3 numbers, each a finite "
                   "number > 0"},
        BadSidecar{{{"probe_volumes", {{"origin", {0, 0, 0}}}}},
                   "probe_volumes: expected an array of at most 7 grids"},
        BadSidecar{{{"probe_volumes", json::array({json{{"origin", {0, 0, 0}}, {"size", 1}}})}},
                   "probe_volumes[0].size: unknown key"},
        BadSidecar{{{"probe_volumes", json::array({1, 2, 3, 4, 5, 6, 7, 8})}},
                   "probe_volumes: expected an array of at most 7 grids (the field holds one more: "
                   "its own grid), got"},
        BadSidecar{json::array(), "(top level): expected an object"}));

TEST(Sidecar, LightLimitCountsGltfAndSidecarLights) {
  SceneWithSidecar s(json{{"lights",
                           {{{"type", "point"}, {"position", {0, 0, 0}}},
                            {{"type", "point"}, {"position", {0, 1, 0}}}}}});
  SceneLimits limits;
  limits.max_lights = 1;
  EXPECT_THAT(error_of(load_scene(s.gltf.string(), limits)),
              AllOf(HasSubstr("room.ddgi.json: lights"), HasSubstr("limit of 1 lights")));
}

TEST(Sidecar, RepeatedKeysAndBadJsonAreRefused) {
  SceneWithSidecar repeated(
      std::string(R"({"environment": {"color": [1, 1, 1]}, "environment": {"color": [0, 0, 0]}})"));
  EXPECT_THAT(error_of(repeated.load()),
              AllOf(HasSubstr("room.ddgi.json"), HasSubstr("key 'environment' appears twice")));
  SceneWithSidecar broken(std::string(R"({"camera": )"));
  EXPECT_THAT(error_of(broken.load()),
              AllOf(HasSubstr("room.ddgi.json"), HasSubstr("invalid JSON")));
  SceneWithSidecar deep(std::string(200, '[') + std::string(200, ']'));
  EXPECT_THAT(error_of(deep.load()), HasSubstr("deeper than 64 levels"));
}

TEST(Sidecar, LivingRoomLitBySky19) {
  const fs::path shared(DDGI_SHARED_SCENES_DIR);
  const fs::path gltf = shared / "LivingRoom" / "LivingRoom.gltf";
  if (!fs::exists(gltf)) GTEST_SKIP() << "no LivingRoom";
  TempDir dir;
  const fs::path sidecar = dir.write(
      "living.ddgi.json",
      json{{"scene", fs::relative(gltf, dir.path()).string()},
           {"environment",
            {{"image",
              fs::relative(shared / "LivingRoom/textures/sky19.exr", dir.path()).string()}}}}
          .dump());
  Result<Scene> scene = load_scene(sidecar.string());
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_TRUE(scene->environment.image.has_value());
  EXPECT_EQ(scene->environment.image->width, 2048u);
  EXPECT_EQ(scene->environment.image->height, 1024u);
  EXPECT_TRUE(scene->has_any_light());
  EXPECT_THAT(scene->warnings, ::testing::Not(Contains(HasSubstr("no light"))));
}

}  // namespace
}  // namespace ddgi
