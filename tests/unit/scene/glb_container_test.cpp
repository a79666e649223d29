// The GLB container is checked before any parser sees it: every length field may lie.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "scene/gltf_loader.h"
#include "test_support.h"

namespace ddgi {
namespace {

using ::testing::AllOf;
using testing::error_of;
using ::testing::HasSubstr;
using testing::put_u32;
using testing::triangle_builder;

Result<Scene> load(const std::vector<uint8_t>& glb) {
  return load_glb_from_memory(glb, "upload.glb");
}

TEST(GlbContainer, ValidGlbLoads) {
  Result<Scene> scene = load(triangle_builder().glb());
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_EQ(scene->source, "upload.glb");
  EXPECT_EQ(testing::drawn_triangles(*scene), 1u);
}

TEST(GlbContainer, RefusesWrongMagic) {
  std::vector<uint8_t> glb = triangle_builder().glb();
  glb[0] = 'x';
  EXPECT_THAT(error_of(load(glb)), AllOf(HasSubstr("upload.glb"), HasSubstr("not a GLB")));
}

TEST(GlbContainer, RefusesVersion1) {
  std::vector<uint8_t> glb = triangle_builder().glb();
  put_u32(&glb, 4, 1);
  EXPECT_THAT(error_of(load(glb)), HasSubstr("GLB version 1"));
}

TEST(GlbContainer, RefusesLengthFieldThatDoesNotMatchTheSize) {
  std::vector<uint8_t> glb = triangle_builder().glb();
  put_u32(&glb, 8, static_cast<uint32_t>(glb.size() + 4));
  EXPECT_THAT(error_of(load(glb)), HasSubstr("does not match the file size"));
}

TEST(GlbContainer, RefusesTruncatedFile) {
  std::vector<uint8_t> glb = triangle_builder().glb();
  glb.resize(glb.size() - 8);
  EXPECT_THAT(error_of(load(glb)), HasSubstr("does not match the file size"));
  // A truncated file whose header was patched to match: the BIN chunk runs past the end.
  put_u32(&glb, 8, static_cast<uint32_t>(glb.size()));
  EXPECT_THAT(error_of(load(glb)), AllOf(HasSubstr("chunk 1"), HasSubstr("past the end")));
}

TEST(GlbContainer, RefusesTruncatedHeaders) {
  std::vector<uint8_t> glb = triangle_builder().glb();
  std::vector<uint8_t> header(glb.begin(), glb.begin() + 8);
  EXPECT_THAT(error_of(load(header)), HasSubstr("header truncated"));
  std::vector<uint8_t> half_chunk_header(glb.begin(), glb.begin() + 16);
  put_u32(&half_chunk_header, 8, 16);
  EXPECT_THAT(error_of(load(half_chunk_header)), HasSubstr("truncated chunk header"));
}

TEST(GlbContainer, RefusesJsonChunkLengthThatLies) {
  std::vector<uint8_t> glb = triangle_builder().glb();
  put_u32(&glb, 12, 0xFFFFFFF0u);
  EXPECT_THAT(error_of(load(glb)), AllOf(HasSubstr("chunk 0"), HasSubstr("past the end")));
  put_u32(&glb, 12, 6);
  EXPECT_THAT(error_of(load(glb)), HasSubstr("not a multiple of 4"));
}

TEST(GlbContainer, RefusesBinFirst) {
  std::vector<uint8_t> glb = triangle_builder().glb();
  put_u32(&glb, 16, 0x004E4942);
  EXPECT_THAT(error_of(load(glb)), HasSubstr("first chunk must be JSON"));
}

TEST(GlbContainer, RefusesUnknownSecondChunkAndEmptyBin) {
  testing::GltfBuilder builder = triangle_builder();
  std::vector<uint8_t> glb = builder.glb();
  const uint32_t json_length = glb[12] | glb[13] << 8 | glb[14] << 16 | glb[15] << 24;
  const size_t bin_header = 20 + json_length;
  put_u32(&glb, bin_header + 4, 0x12345678);
  EXPECT_THAT(error_of(load(glb)), HasSubstr("second chunk must be BIN"));

  std::vector<uint8_t> empty_bin = testing::make_glb(builder.gltf_text(), {});
  empty_bin.resize(empty_bin.size() + 8, 0);
  put_u32(&empty_bin, empty_bin.size() - 4, 0x004E4942);
  put_u32(&empty_bin, 8, static_cast<uint32_t>(empty_bin.size()));
  EXPECT_THAT(error_of(load(empty_bin)), HasSubstr("BIN chunk is empty"));
}

TEST(GlbContainer, IgnoresChunksAfterBin) {
  std::vector<uint8_t> glb = triangle_builder().glb();
  const std::vector<uint8_t> extra = {4, 0, 0, 0, 'X', 'T', 'R', 'A', 1, 2, 3, 4};
  glb.insert(glb.end(), extra.begin(), extra.end());
  put_u32(&glb, 8, static_cast<uint32_t>(glb.size()));
  EXPECT_TRUE(load(glb).ok()) << error_of(load(glb));
  // ... but their lengths are still checked.
  put_u32(&glb, glb.size() - 12, 400);
  EXPECT_THAT(error_of(load(glb)), AllOf(HasSubstr("chunk 2"), HasSubstr("past the end")));
}

TEST(GlbContainer, UploadMayNotReferenceFiles) {
  testing::GltfBuilder builder = triangle_builder();
  testing::json doc = testing::json::parse(builder.gltf_text("scene.bin"));
  std::vector<uint8_t> glb = testing::make_glb(doc.dump(), {});
  EXPECT_THAT(error_of(load(glb)),
              AllOf(HasSubstr("scene.bin"), HasSubstr("may not reference any")));
}

TEST(GlbContainer, MemoryEntryPointsCheckTheFormat) {
  EXPECT_THAT(error_of(load(testing::to_bytes(triangle_builder().gltf_text()))),
              HasSubstr("not a GLB"));
  EXPECT_THAT(error_of(load_gltf_from_memory(triangle_builder().glb(), "x.gltf")),
              HasSubstr("is a GLB"));
}

TEST(GlbContainer, OnlyBufferZeroMayUseTheBinChunk) {
  testing::GltfBuilder builder = triangle_builder();
  testing::json doc = testing::json::parse(builder.gltf_text());
  doc["buffers"] = {{{"byteLength", builder.bin().size()}}, {{"byteLength", 4}}};
  EXPECT_THAT(error_of(load(testing::make_glb(doc.dump(), builder.bin()))),
              HasSubstr("buffers[1] has no uri"));
}

}  // namespace
}  // namespace ddgi
