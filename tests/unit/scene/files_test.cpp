// Scene files on disk: external buffers and images, URIs that try to leave the scene's
// folder, missing and truncated files, broken JSON, size limits.
#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_support.h"

namespace ddgi {
namespace {

using ::testing::AllOf;
using testing::error_of;
using testing::GltfBuilder;
using ::testing::HasSubstr;
using testing::json;
using testing::TempDir;

namespace fs = std::filesystem;

// triangle_builder written as scene/scene.gltf with its buffer at `buffer_uri`, and the
// buffer's bytes written to scene/scene.bin.
fs::path write_external(const TempDir& dir, const std::string& buffer_uri) {
  GltfBuilder b = testing::triangle_builder();
  dir.write("scene/scene.bin", b.bin());
  return dir.write("scene/scene.gltf", b.gltf_text(buffer_uri));
}

TEST(Files, ExternalBufferAndImageLoad) {
  TempDir dir;
  GltfBuilder b = testing::triangle_builder();
  b.doc()["meshes"][0]["primitives"][0]["material"] =
      b.add_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.doc()["images"] = {{{"uri", "textures/my%20image.png"}}};  // percent-encoded space
  b.doc()["textures"] = {{{"source", 0}}};
  dir.write("data/buffers/scene.bin", b.bin());
  dir.write("data/textures/my image.png", testing::encode_png(1, 1, {1, 2, 3, 4}));
  const fs::path gltf = dir.write("data/scene.gltf", b.gltf_text("buffers/scene.bin"));
  Result<Scene> scene = load_scene(gltf.string());
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_EQ(scene->source, gltf.string());
  EXPECT_EQ(testing::drawn_triangles(*scene), 1u);
  ASSERT_EQ(scene->textures.size(), 1u);
  EXPECT_EQ(scene->textures[0].rgba8, (std::vector<uint8_t>{1, 2, 3, 4}));
}

TEST(Files, GlbFileLoads) {
  TempDir dir;
  const fs::path glb = dir.write("scene.glb", testing::triangle_builder().glb());
  Result<Scene> scene = load_scene(glb.string());
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_EQ(testing::drawn_triangles(*scene), 1u);
}

TEST(Files, MissingBufferFileIsNamed) {
  TempDir dir;
  const fs::path gltf = write_external(dir, "missing.bin");
  Result<Scene> scene = load_scene(gltf.string());
  EXPECT_THAT(error_of(scene), AllOf(HasSubstr(gltf.string()), HasSubstr("'missing.bin'"),
                                     HasSubstr("file not found")));
  EXPECT_EQ(scene.error().code, ErrorCode::kNotFound);
}

TEST(Files, MissingImageFileIsAnError) {
  TempDir dir;
  GltfBuilder b = testing::triangle_builder();
  b.doc()["images"] = {{{"uri", "nowhere.png"}}};
  const fs::path gltf = dir.write("scene.gltf", b.gltf_text());
  EXPECT_THAT(error_of(load_scene(gltf.string())),
              AllOf(HasSubstr("scene.gltf"), HasSubstr("images[0]"), HasSubstr("'nowhere.png'"),
                    HasSubstr("not found")));
}

TEST(Files, BufferSizeMismatchIsRefused) {
  TempDir dir;
  GltfBuilder b = testing::triangle_builder();
  dir.write("scene/scene.bin", std::vector<uint8_t>(b.bin().begin(), b.bin().end() - 4));
  const fs::path gltf = dir.write("scene/scene.gltf", b.gltf_text("scene.bin"));
  EXPECT_THAT(error_of(load_scene(gltf.string())), HasSubstr("size mismatch"));
}

class EscapingUri : public ::testing::TestWithParam<const char*> {};

TEST_P(EscapingUri, IsRefused) {
  TempDir dir;
  // The file the URI aims at exists, so only the sandbox can stop it.
  dir.write("secret.bin", testing::triangle_builder().bin());
  const fs::path gltf = write_external(dir, GetParam());
  Result<Scene> scene = load_scene(gltf.string());
  ASSERT_FALSE(scene.ok());
  EXPECT_THAT(error_of(scene), HasSubstr(gltf.string()));
  const std::string message = error_of(scene);
  const bool explained = message.find("outside the scene folder") != std::string::npos ||
                         message.find("absolute path") != std::string::npos ||
                         message.find("has a scheme") != std::string::npos;
  EXPECT_TRUE(explained) << message;
}

INSTANTIATE_TEST_SUITE_P(Files, EscapingUri,
                         ::testing::Values("../secret.bin", "../../etc/passwd",
                                           "sub/../../secret.bin", "..%2Fsecret.bin",
                                           "%2E%2E/secret.bin", "/etc/passwd", "file:///etc/passwd",
                                           "http://example.com/scene.bin",
                                           "data:text/html;base64,AAAA"));

TEST(Files, SymbolicLinkLeavingTheFolderIsRefused) {
  TempDir dir;
  const fs::path secret = dir.write("secret.bin", testing::triangle_builder().bin());
  const fs::path gltf = write_external(dir, "link.bin");
  fs::create_symlink(secret, dir.path() / "scene" / "link.bin");
  EXPECT_THAT(error_of(load_scene(gltf.string())), HasSubstr("outside the scene folder"));
}

TEST(Files, InvalidAndTruncatedJsonAreRefused) {
  TempDir dir;
  const std::string text = testing::triangle_builder().gltf_text();
  const fs::path truncated = dir.write("truncated.gltf", text.substr(0, text.size() / 2));
  EXPECT_THAT(error_of(load_scene(truncated.string())),
              AllOf(HasSubstr("truncated.gltf"), HasSubstr("invalid JSON")));
  const fs::path garbage = dir.write("garbage.gltf", std::string("{\"asset\": nope}"));
  EXPECT_THAT(error_of(load_scene(garbage.string())), HasSubstr("invalid JSON"));
  const fs::path empty = dir.write("empty.gltf", std::string());
  EXPECT_THAT(error_of(load_scene(empty.string())), HasSubstr("too short"));
  const fs::path no_asset = dir.write("no_asset.gltf", std::string("{\"meshes\": []}"));
  EXPECT_THAT(error_of(load_scene(no_asset.string())), HasSubstr("asset"));
}

TEST(Files, DeeplyNestedJsonIsRefusedBeforeParsing) {
  json doc = json::parse(testing::triangle_builder().gltf_text());
  std::string text = doc.dump();
  text.pop_back();
  text += ",\"extras\":" + std::string(100000, '[') + std::string(100000, ']') + "}";
  Result<Scene> scene = load_gltf_from_memory(testing::to_bytes(text), "deep.gltf");
  EXPECT_THAT(error_of(scene), HasSubstr("deeper than 64 levels"));
  // Brackets inside strings do not count.
  doc["extras"] = std::string(1000, '[');
  EXPECT_TRUE(load_gltf_from_memory(testing::to_bytes(doc.dump()), "ok.gltf").ok());
}

TEST(Files, HugeIntegersAreRefusedOutsideExtras) {
  // tinygltf narrows indices to int: 4294967296 would silently become mesh 0.
  json doc = json::parse(testing::triangle_builder().gltf_text());
  doc["nodes"][0]["mesh"] = 4294967296ull;
  EXPECT_THAT(error_of(load_gltf_from_memory(testing::to_bytes(doc.dump()), "big.gltf")),
              HasSubstr("integer 4294967296 (under key 'mesh') is outside"));
  doc["nodes"][0]["mesh"] = 0;
  doc["nodes"][0]["extras"] = {{"hash", 18446744073709551615ull},
                               {"list", {-9223372036854775807ll}}};
  doc["extras"] = 18446744073709551615ull;
  Result<Scene> scene = load_gltf_from_memory(testing::to_bytes(doc.dump()), "extras.gltf");
  EXPECT_TRUE(scene.ok()) << error_of(scene);
  doc["nodes"][0]["extensions"] = {{"EXT_x", {{"n", -9223372036854775807ll}}}};
  EXPECT_THAT(error_of(load_gltf_from_memory(testing::to_bytes(doc.dump()), "ext.gltf")),
              HasSubstr("under key 'n'"));
}

TEST(Files, FileSizeLimit) {
  TempDir dir;
  const fs::path gltf = write_external(dir, "scene.bin");
  SceneLimits limits;
  limits.max_file_bytes = 1024;
  EXPECT_TRUE(load_scene(gltf.string(), limits).ok());
  dir.write("scene/scene.gltf",
            std::string(2000, ' ') + testing::triangle_builder().gltf_text("scene.bin"));
  Result<Scene> scene = load_scene(gltf.string(), limits);
  EXPECT_THAT(error_of(scene), HasSubstr("more than the limit of 1024"));
  EXPECT_EQ(scene.error().code, ErrorCode::kResourceExhausted);
}

TEST(Files, ReferencedFilesAddUpAgainstTheLimit) {
  // Many URIs naming one large file must not multiply what is read.
  TempDir dir;
  GltfBuilder b = testing::triangle_builder();
  std::vector<uint8_t> big = b.bin();
  big.resize(600, 0);
  dir.write("scene/scene.bin", big);
  json doc = json::parse(b.gltf_text("scene.bin"));
  doc["buffers"][0]["byteLength"] = 600;
  doc["buffers"].push_back({{"uri", "scene.bin"}, {"byteLength", 600}});
  const fs::path gltf = dir.write("scene/scene.gltf", doc.dump());
  SceneLimits limits;
  limits.max_file_bytes = 1024;
  Result<Scene> scene = load_scene(gltf.string(), limits);
  EXPECT_THAT(error_of(scene), HasSubstr("add up to more than the limit of 1024 bytes"));
  EXPECT_EQ(scene.error().code, ErrorCode::kResourceExhausted);
  limits.max_file_bytes = 2048;
  EXPECT_TRUE(load_scene(gltf.string(), limits).ok());
}

TEST(Files, PathErrors) {
  Result<Scene> missing = load_scene("/nonexistent/scene.gltf");
  EXPECT_THAT(error_of(missing), HasSubstr("/nonexistent/scene.gltf"));
  EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
  EXPECT_THAT(error_of(load_scene("/tmp/scene.obj")), HasSubstr("not a scene file"));
}

TEST(Files, LimitsAreValidated) {
  SceneLimits limits;
  EXPECT_TRUE(validate_limits(limits).ok());
  limits.max_texture_dimension = 0;
  EXPECT_THAT(error_of(validate_limits(limits)), HasSubstr("max_texture_dimension = 0"));
  EXPECT_THAT(error_of(load_scene("/x.gltf", limits)), HasSubstr("max_texture_dimension"));
  limits = SceneLimits();
  limits.max_file_bytes = 8ull << 30;
  EXPECT_THAT(error_of(validate_limits(limits)), HasSubstr("max_file_bytes"));
}

}  // namespace
}  // namespace ddgi
