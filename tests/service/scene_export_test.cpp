// ExportScene (the session's scene as binary glTF, for clients that draw it themselves): read
// back through the project's own glTF loader, the export is the session's scene as it is now —
// every instance's world-space vertices (one of them moved by SetInstanceTransform), the
// materials, and the session's lights (one updated, one added) with their ids. Images survive:
// PNG (used alpha) exactly, JPEG within a stated tolerance. Unknown sessions are NOT_FOUND.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "rpc/probe_download.h"
#include "scene/gltf_loader.h"
#include "service/scene_export.h"
#include "tests/service/service_fixture.h"

namespace ddgi::test {
namespace {

// Every world-space vertex of every instance, in instance order.
std::vector<glm::vec3> world_vertices(const Scene& scene) {
  std::vector<glm::vec3> out;
  for (const Instance& instance : scene.instances) {
    for (const Primitive& p : scene.meshes[size_t(instance.mesh)].primitives) {
      for (uint32_t index : p.indices) {
        out.push_back(glm::vec3(instance.transform * glm::vec4(p.positions[index], 1.0f)));
      }
    }
  }
  return out;
}

v1::Vec3 vec3(float x, float y, float z) {
  v1::Vec3 v;
  v.set_x(x);
  v.set_y(y);
  v.set_z(z);
  return v;
}

float largest_distance(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  float worst = 0.0f;
  for (size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    worst = std::max(worst, glm::length(a[i] - b[i]));
  }
  return worst;
}

class SceneExportTest : public ServiceTest {
 protected:
  // Exports of the slow scene below take over a minute in the sanitizer build with the suite
  // sharded on two cores (CI): calls wait this long.
  static constexpr double kExportDeadlineSeconds = 240.0;

  Scene export_session(const std::string& session, std::string* glb) {
    v1::ExportSceneRequest request;
    request.set_session_id(session);
    v1::SceneMetadata metadata;
    const grpc::Status status = fetch_scene(
        *stub_, [this] { return context(kExportDeadlineSeconds); }, request, &metadata, glb);
    EXPECT_TRUE(status.ok()) << status.error_message();
    EXPECT_EQ(metadata.total_bytes(), glb->size());
    auto loaded = load_glb_from_memory(
        std::span(reinterpret_cast<const uint8_t*>(glb->data()), glb->size()), "export");
    EXPECT_TRUE(loaded.ok()) << (loaded.ok() ? "" : loaded.error().message);
    return loaded.ok() ? std::move(*loaded) : Scene{};
  }
};

TEST_F(SceneExportTest, TheExportIsTheSessionsSceneAsItIsNow) {
  const std::string session = create_session("cornell_box");
  auto original = load_scene(std::string(DDGI_TEST_SCENE_ROOT) + "/cornell_box.gltf");
  ASSERT_TRUE(original.ok());

  // Move instance 2 by (0.25, 0, -0.1); move and brighten light 0; add a spot light.
  const glm::vec3 shift(0.25f, 0.0f, -0.1f);
  glm::mat4 moved = original->instances[2].transform;
  moved[3] += glm::vec4(shift, 0.0f);
  v1::SetInstanceTransformRequest move;
  move.set_session_id(session);
  move.set_instance_index(2);
  for (int i = 0; i < 16; ++i) move.mutable_transform()->add_m(moved[i / 4][i % 4]);
  v1::InstanceReply moved_reply;
  ASSERT_TRUE(stub_->SetInstanceTransform(context().get(), move, &moved_reply).ok());
  v1::UpdateLightRequest update;
  update.set_session_id(session);
  update.set_light_id(0);
  update.mutable_light()->set_intensity(5.0f);
  *update.mutable_light()->mutable_position() = vec3(0.2f, 1.7f, 0.1f);
  v1::LightReply light_reply;
  ASSERT_TRUE(stub_->UpdateLight(context().get(), update, &light_reply).ok());
  v1::AddLightRequest add;
  add.set_session_id(session);
  add.mutable_light()->set_type(v1::LIGHT_TYPE_SPOT);
  add.mutable_light()->set_intensity(2.0f);
  add.mutable_light()->set_outer_cone_degrees(30.0f);
  *add.mutable_light()->mutable_position() = vec3(-0.5f, 1.5f, 0.5f);
  *add.mutable_light()->mutable_direction() = vec3(0.0f, -1.0f, 0.0f);
  ASSERT_TRUE(stub_->AddLight(context().get(), add, &light_reply).ok());

  std::string glb;
  const Scene exported = export_session(session, &glb);
  ASSERT_EQ(exported.instances.size(), original->instances.size());
  Scene expected = *original;
  expected.instances[2].transform = moved;
  const std::vector<glm::vec3> got = world_vertices(exported);
  ASSERT_EQ(got.size(), world_vertices(expected).size());
  const float error = largest_distance(got, world_vertices(expected));
  const float control = largest_distance(got, world_vertices(*original));  // the unmoved file
  std::printf("world vertices: %zu, largest distance %.2e (bound 1e-5); to the unmoved file %.3f\n",
              got.size(), error, control);
  EXPECT_LT(error, 1e-5f);
  EXPECT_NEAR(control, glm::length(shift), 1e-5f);

  ASSERT_EQ(exported.materials.size(), original->materials.size());
  for (size_t i = 0; i < exported.materials.size(); ++i) {
    EXPECT_EQ(exported.materials[i].base_color, original->materials[i].base_color) << i;
    EXPECT_EQ(exported.materials[i].emissive, original->materials[i].emissive) << i;
  }
  ASSERT_EQ(exported.lights.size(), 2u);
  EXPECT_EQ(exported.lights[0].type, LightType::kPoint);
  EXPECT_FLOAT_EQ(exported.lights[0].intensity, 5.0f);
  EXPECT_LT(glm::length(exported.lights[0].position - glm::vec3(0.2f, 1.7f, 0.1f)), 1e-6f);
  EXPECT_EQ(exported.lights[1].type, LightType::kSpot);
  EXPECT_LT(glm::length(exported.lights[1].direction - glm::vec3(0.0f, -1.0f, 0.0f)), 1e-6f);
  EXPECT_NEAR(exported.lights[1].outer_cone_angle, 30.0f * 3.14159265f / 180.0f, 1e-6f);
  // The ids clients know the lights by (0: the scene's, 1: the added one).
  EXPECT_NE(glb.find("\"ddgi_light_id\":1"), std::string::npos);
  EXPECT_NE(glb.find("\"ddgi_instance\":6"), std::string::npos);

  v1::ExportSceneRequest unknown;
  unknown.set_session_id("no-such-session");
  v1::SceneMetadata metadata;
  std::string bytes;
  const grpc::Status status = fetch_scene(
      *stub_, [this] { return context(); }, unknown, &metadata, &bytes);
  EXPECT_EQ(status.error_code(), grpc::StatusCode::NOT_FOUND) << status.error_message();
}

// A scene whose export takes a while: two 2048x2048 textures behind masked materials (PNG).
std::string slow_export_glb() {
  Scene scene;
  Mesh mesh;
  Primitive triangle;
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  triangle.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  triangle.texcoords0 = {{0, 0}, {1, 0}, {0, 1}};
  triangle.indices = {0, 1, 2};
  for (int t = 0; t < 2; ++t) {
    Texture texture{"big" + std::to_string(t), 2048, 2048, {}, true};
    texture.rgba8.resize(size_t(2048) * 2048 * 4);
    for (size_t i = 0; i < texture.rgba8.size(); ++i) texture.rgba8[i] = uint8_t((i * 7 + t) / 5);
    scene.textures.push_back(texture);
    Material material;
    material.base_color_texture = t;
    material.alpha_mode = AlphaMode::kMask;
    scene.materials.push_back(material);
    triangle.material = t;
    mesh.primitives.push_back(triangle);
  }
  scene.meshes.push_back(mesh);
  scene.instances.push_back(Instance{"tri", 0, 0, glm::mat4(1.0f)});
  scene.lights.push_back(Light{});
  auto glb = service::export_glb(scene, {});
  EXPECT_TRUE(glb.ok());
  return glb.ok() ? std::string(glb->glb.begin(), glb->glb.end()) : "";
}

class SceneExportLimitTest : public SceneExportTest {
 protected:
  void configure(service::ServerOptions& options) override {
    options.limits.max_upload_bytes = 64 << 20;
    options.limits.max_message_bytes = 64 << 20;
  }
};

// Eight clients ask for a slow export at once: two are written, the others are refused with
// RESOURCE_EXHAUSTED naming the limit, and a later call succeeds again.
TEST_F(SceneExportLimitTest, AtMostTwoExportsAreWrittenAtOnce) {
  v1::CreateSessionRequest request = small_session_request("cornell_box", 1);
  request.mutable_scene()->set_glb(slow_export_glb());
  const std::string session = create_session(request).session_id();
  ASSERT_FALSE(session.empty());
  std::vector<grpc::Status> statuses(8);
  std::vector<std::thread> clients;
  for (size_t i = 0; i < statuses.size(); ++i) {
    clients.emplace_back([&, i] {
      v1::ExportSceneRequest call;
      call.set_session_id(session);
      v1::SceneMetadata metadata;
      std::string bytes;
      statuses[i] = fetch_scene(
          *stub_, [this] { return context(kExportDeadlineSeconds); }, call, &metadata, &bytes);
    });
  }
  for (std::thread& client : clients) client.join();
  int written = 0, refused = 0;
  for (const grpc::Status& status : statuses) {
    if (status.ok()) ++written;
    if (status.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED) {
      ++refused;
      EXPECT_NE(status.error_message().find("2 scene exports are being written"), std::string::npos)
          << status.error_message();
    }
  }
  std::printf("8 concurrent exports: %d written, %d refused\n", written, refused);
  EXPECT_GE(written, 2);
  EXPECT_GE(refused, 1);
  EXPECT_EQ(written + refused, 8);
  std::string glb;
  EXPECT_EQ(export_session(session, &glb).textures.size(), 2u);  // the slots came back
}

// Images: a masked material's texture goes as PNG (alpha exact), an opaque one's as JPEG.
TEST(SceneExportImages, PngKeepsAlphaExactlyAndJpegStaysClose) {
  Scene scene;
  Mesh mesh;
  Primitive triangle;
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  triangle.texcoords0 = {{0, 0}, {1, 0}, {0, 1}};
  triangle.indices = {0, 1, 2};
  mesh.primitives = {triangle, triangle};
  mesh.primitives[0].material = 0;
  mesh.primitives[1].material = 1;
  scene.meshes.push_back(mesh);
  scene.instances.push_back(Instance{"tri", 0, 0, glm::mat4(1.0f)});
  for (int t = 0; t < 2; ++t) {
    Texture texture{"t" + std::to_string(t), 16, 16, {}, true};
    for (uint32_t i = 0; i < 16 * 16; ++i) {  // smooth ramps (JPEG-friendly), alpha in steps
      texture.rgba8.insert(texture.rgba8.end(),
                           {uint8_t(i % 16 * 16), uint8_t(i / 16 * 16), 128, uint8_t(i % 2 * 255)});
    }
    scene.textures.push_back(texture);
    Material material;
    material.base_color_texture = t;
    material.alpha_mode = t == 0 ? AlphaMode::kMask : AlphaMode::kOpaque;
    scene.materials.push_back(material);
  }
  auto exported = service::export_glb(scene, {});
  ASSERT_TRUE(exported.ok()) << exported.error().message;
  auto loaded = load_glb_from_memory(exported->glb, "images");
  ASSERT_TRUE(loaded.ok()) << loaded.error().message;
  ASSERT_EQ(loaded->textures.size(), 2u);
  EXPECT_EQ(loaded->textures[0].rgba8, scene.textures[0].rgba8);  // PNG: every byte
  int worst = 0;
  for (size_t i = 0; i < scene.textures[1].rgba8.size(); ++i) {
    if (i % 4 == 3) continue;  // JPEG has no alpha
    worst = std::max(worst,
                     std::abs(int(loaded->textures[1].rgba8[i]) - int(scene.textures[1].rgba8[i])));
  }
  std::printf("JPEG texture: largest channel error %d of 255 (bound 12)\n", worst);
  EXPECT_LE(worst, 12);
  EXPECT_GT(worst, 0);  // it did go through JPEG
}

}  // namespace
}  // namespace ddgi::test
