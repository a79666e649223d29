// Materials and textures: factors, emissive strength, transmission, alpha, texture references
// and image decoding with its limits.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_support.h"

namespace ddgi {
namespace {

using ::testing::AllOf;
using ::testing::ElementsAre;
using testing::error_of;
using testing::GltfBuilder;
using ::testing::HasSubstr;
using testing::json;
using testing::load_text;

// A 2x1 image: a red pixel and a half-transparent green one.
std::vector<uint8_t> two_pixel_png() {
  return testing::encode_png(2, 1, {255, 0, 0, 255, 0, 255, 0, 128});
}

std::string png_data_uri(const std::vector<uint8_t>& png) {
  return "data:image/png;base64," + testing::base64(png);
}

// triangle_builder with material 0 on its primitive.
GltfBuilder with_material(json material) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["meshes"][0]["primitives"][0]["material"] = b.add_material(material);
  return b;
}

GltfBuilder with_textured_material(json material) {
  GltfBuilder b = with_material(material);
  b.doc()["images"] = {{{"uri", png_data_uri(two_pixel_png())}, {"name", "checker"}}};
  b.doc()["samplers"] = json::array({json::object()});
  b.doc()["textures"] = {{{"source", 0}, {"sampler", 0}}};
  return b;
}

TEST(Materials, FactorsAndFlags) {
  GltfBuilder b =
      with_material({{"name", "m"},
                     {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1, 0.75}}}},
                     {"alphaMode", "MASK"},
                     {"alphaCutoff", 0.3},
                     {"doubleSided", true}});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_EQ(scene->materials.size(), 1u);
  const Material& m = scene->materials[0];
  EXPECT_EQ(m.name, "m");
  EXPECT_EQ(m.base_color, glm::vec4(0.5f, 0.25f, 1.0f, 0.75f));
  EXPECT_EQ(m.alpha_mode, AlphaMode::kMask);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
  EXPECT_TRUE(m.double_sided);
  EXPECT_EQ(m.base_color_texture, -1);
  EXPECT_EQ(scene->meshes[0].primitives[0].material, 0);
}

TEST(Materials, DefaultsFollowTheSpec) {
  Result<Scene> scene = load_text(with_material(json::object()));
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  const Material& m = scene->materials.at(0);
  EXPECT_EQ(m.base_color, glm::vec4(1.0f));
  EXPECT_EQ(m.emissive, glm::vec3(0.0f));
  EXPECT_EQ(m.alpha_mode, AlphaMode::kOpaque);
  EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.5f);
  EXPECT_FALSE(m.double_sided);
  EXPECT_FLOAT_EQ(m.transmission, 0.0f);
}

TEST(Materials, EmissiveStrengthMultipliesTheFactor) {
  GltfBuilder b = with_material(
      {{"emissiveFactor", {1, 0.5, 0}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 17}}}}}});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_EQ(scene->materials.at(0).emissive, glm::vec3(17.0f, 8.5f, 0.0f));
  EXPECT_TRUE(scene->has_any_light());  // an emitter in use is a light

  b.doc()["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] = -2;
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength "
                        "must be >= 0"));
  b.doc()["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] =
      "bright";
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("emissiveStrength: expected a number, got \"bright\""));
  b.doc()["materials"][0]["emissiveFactor"] = {1e30, 0, 0};
  b.doc()["materials"][0]["extensions"]["KHR_materials_emissive_strength"]["emissiveStrength"] =
      1e30;
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("materials[0]: emissive factor x strength overflows"));
}

TEST(Materials, EmitterNobodyUsesIsNotALight) {
  GltfBuilder b = testing::triangle_builder();
  b.add_material({{"emissiveFactor", {1, 1, 1}}});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_FALSE(scene->has_any_light());
}

TEST(Materials, Transmission) {
  GltfBuilder b = with_material(
      {{"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 0.8}}}}}});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_FLOAT_EQ(scene->materials.at(0).transmission, 0.8f);
}

TEST(Materials, BaseColorAndEmissiveTexturesAreDecoded) {
  GltfBuilder b = with_textured_material(
      {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 1}}}}},
       {"emissiveTexture", {{"index", 0}}},
       {"emissiveFactor", {1, 1, 1}},
       {"normalTexture", {{"index", 0}}}});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  // One image used twice is decoded once.
  ASSERT_EQ(scene->textures.size(), 1u);
  const Texture& t = scene->textures[0];
  EXPECT_EQ(t.name, "checker");
  EXPECT_EQ(t.width, 2u);
  EXPECT_EQ(t.height, 1u);
  EXPECT_TRUE(t.srgb);
  EXPECT_THAT(t.rgba8, ElementsAre(255, 0, 0, 255, 0, 255, 0, 128));
  const Material& m = scene->materials.at(0);
  EXPECT_EQ(m.base_color_texture, 0);
  EXPECT_EQ(m.base_color_texcoord, 1);
  EXPECT_EQ(m.emissive_texture, 0);
  EXPECT_EQ(m.emissive_texcoord, 0);
}

TEST(Materials, ImagesOnlyDataMapsUseAreNotDecoded) {
  GltfBuilder b = with_textured_material({{"normalTexture", {{"index", 0}}}});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_TRUE(scene->textures.empty());
}

TEST(Materials, ImageFromBufferViewInGlb) {
  GltfBuilder b = with_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  const int view = b.add_view(two_pixel_png());
  b.doc()["images"] = {{{"bufferView", view}, {"mimeType", "image/png"}}};
  b.doc()["textures"] = {{{"source", 0}}};
  Result<Scene> scene = load_glb_from_memory(b.glb(), "textured.glb");
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_EQ(scene->textures.size(), 1u);
  EXPECT_EQ(scene->textures[0].rgba8[4 + 1], 255);

  // Images sharing one buffer view each decode from it.
  b.doc()["images"].push_back({{"bufferView", view}, {"mimeType", "image/png"}});
  b.doc()["textures"].push_back({{"source", 1}});
  b.doc()["materials"][0]["emissiveTexture"] = {{"index", 1}};
  scene = load_glb_from_memory(b.glb(), "textured.glb");
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_EQ(scene->textures.size(), 2u);
  EXPECT_EQ(scene->textures[1].rgba8, scene->textures[0].rgba8);

  // A view that runs past the buffer must be caught before the image bytes are read.
  b.doc()["bufferViews"][view]["byteLength"] = 100000;
  EXPECT_THAT(error_of(load_glb_from_memory(b.glb(), "textured.glb")),
              AllOf(HasSubstr("textured.glb"), HasSubstr("images[0]"),
                    HasSubstr("runs past the end of buffers[0]")));
}

TEST(Materials, TextureReferencesOutOfRangeAreRefused) {
  GltfBuilder b =
      with_textured_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 3}}}}}});
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("materials[0].pbrMetallicRoughness.baseColorTexture.index = 3 does not "
                        "exist (the file has 1 textures)"));
  b = with_textured_material({{"occlusionTexture", {{"index", 1}}}});
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("materials[0].occlusionTexture.index = 1"));
  b = with_textured_material({{"emissiveTexture", {{"index", 0}, {"texCoord", -1}}}});
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("emissiveTexture.texCoord: expected a non-negative integer, got -1"));
  b = with_textured_material(json::object());
  b.doc()["textures"][0]["source"] = 1;
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("textures[0].source = 1 does not exist (the file has 1 images)"));
  b = with_textured_material(json::object());
  b.doc()["textures"][0]["sampler"] = 2;
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("textures[0].sampler = 2 does not exist"));
  b = with_material({{"alphaMode", "CUTOUT"}});
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("materials[0].alphaMode 'CUTOUT'"));
}

TEST(Materials, UnusableTexturesAreDroppedWithAWarning) {
  GltfBuilder b = with_textured_material(
      {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 2}}}}}});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_EQ(scene->materials.at(0).base_color_texture, -1);
  EXPECT_THAT(scene->warnings, ::testing::Contains(HasSubstr("texCoord 2 is not supported")));
}

TEST(Materials, ImageDimensionsAreCheckedBeforeDecoding) {
  GltfBuilder b = with_textured_material(json::object());
  b.doc()["images"][0]["uri"] = png_data_uri(testing::encode_png(8, 4, std::vector<uint8_t>(128)));
  SceneLimits limits;
  limits.max_texture_dimension = 4;
  Result<Scene> scene = load_text(b, limits);
  EXPECT_THAT(error_of(scene),
              AllOf(HasSubstr("images[0] 'checker'"), HasSubstr("8x4 pixels; the limit is 4")));
  EXPECT_EQ(scene.error().code, ErrorCode::kResourceExhausted);

  // A PNG header claiming 20000 x 3 pixels with 2 pixels of data: refused from the header.
  std::vector<uint8_t> lying = two_pixel_png();
  testing::put_u32(&lying, 16, 0x204E0000);  // big-endian 20000
  testing::put_u32(&lying, 20, 0x03000000);  // big-endian 3
  b.doc()["images"][0]["uri"] = png_data_uri(lying);
  EXPECT_THAT(error_of(load_text(b, limits)), HasSubstr("20000x3 pixels; the limit is 4"));
}

TEST(Materials, TotalTextureBytesAreBounded) {
  GltfBuilder b =
      with_textured_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  SceneLimits limits;
  limits.max_total_texture_bytes = 7;  // the image needs 2 x 1 x 4 = 8
  EXPECT_THAT(error_of(load_text(b, limits)), HasSubstr("need 8 bytes decoded"));
  limits.max_total_texture_bytes = 8;
  EXPECT_TRUE(load_text(b, limits).ok());
}

TEST(Materials, NonPngJpegAndCorruptImagesAreRefused) {
  GltfBuilder b =
      with_textured_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.doc()["images"][0]["uri"] = "data:image/bmp;base64," + testing::base64({'B', 'M', 0, 0});
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("not a PNG or JPEG"));

  std::vector<uint8_t> truncated = two_pixel_png();
  truncated.resize(40);  // the header survives, the pixels do not
  b.doc()["images"][0]["uri"] = png_data_uri(truncated);
  EXPECT_THAT(error_of(load_text(b)), AllOf(HasSubstr("images[0]"), HasSubstr("decode")));
}

// The PNG standard allows an IDAT chunk of zero bytes; stb_image copies nothing from a null
// buffer for it (the fuzzer's finding, tests/fuzz/regressions/stb-png-empty-idat.glb). The
// pixel must still come out of the IDAT that follows.
TEST(Materials, PngWithAnEmptyIdatChunkDecodes) {
  const std::vector<uint8_t> png = {
      0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a,                          // signature
      0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52, 0x00, 0x00, 0x00, 0x01,  // IHDR 1x1
      0x00, 0x00, 0x00, 0x01, 0x08, 0x06, 0x00, 0x00, 0x00, 0x1f, 0x15, 0xc4, 0x89,
      0x00, 0x00, 0x00, 0x00, 0x49, 0x44, 0x41, 0x54, 0x35, 0xaf, 0x06, 0x1e,  // empty IDAT
      0x00, 0x00, 0x00, 0x0d, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0x38,  // IDAT: one pixel
      0x91, 0x62, 0xd4, 0x00, 0x00, 0x05, 0x35, 0x01, 0xdf, 0x73, 0x62, 0xe3, 0xdb,
      0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};  // IEND
  GltfBuilder b =
      with_textured_material({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
  b.doc()["images"][0]["uri"] = png_data_uri(png);
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_EQ(scene->textures.size(), 1u);
  EXPECT_THAT(scene->textures[0].rgba8, ElementsAre(200, 100, 50, 128));
}

}  // namespace
}  // namespace ddgi
