// Mesh data: every index and attribute component type the spec allows, strides, sparse
// accessors, strips and fans, and the ways accessor data can be broken.
#include <cmath>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_support.h"

namespace ddgi {
namespace {

using ::testing::AllOf;
using ::testing::Contains;
using ::testing::ElementsAre;
using testing::error_of;
using testing::GltfBuilder;
using ::testing::HasSubstr;
using testing::json;
using testing::load_text;

const std::vector<glm::vec3> kQuad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};

// One mesh from the builder's last mesh, on node 0 of scene 0.
GltfBuilder& place(GltfBuilder& b, int mesh) {
  b.set_scene({b.add_node({{"mesh", mesh}})});
  return b;
}

const Primitive& only_primitive(const Scene& scene) {
  EXPECT_EQ(scene.meshes.size(), 1u);
  EXPECT_EQ(scene.meshes.at(0).primitives.size(), 1u);
  return scene.meshes.at(0).primitives.at(0);
}

class IndexTypes : public ::testing::TestWithParam<int> {};

TEST_P(IndexTypes, ReadsEveryIndexComponentType) {
  GltfBuilder b;
  const int positions = b.add_positions(kQuad);
  const int indices = b.add_indices({0, 1, 2, 0, 2, 3}, GetParam());
  place(b, b.add_mesh({{"POSITION", positions}}, indices));
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_THAT(only_primitive(*scene).indices, ElementsAre(0, 1, 2, 0, 2, 3));
}

INSTANTIATE_TEST_SUITE_P(Geometry, IndexTypes,
                         ::testing::Values(testing::kUnsignedByte, testing::kUnsignedShort,
                                           testing::kUnsignedInt));

TEST(Geometry, NonIndexedPrimitivesGetGeneratedIndices) {
  GltfBuilder b;
  const int positions =
      b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 1}, {2, 1, 1}, {1, 2, 1}});
  place(b, b.add_mesh({{"POSITION", positions}}));
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  const Primitive& prim = only_primitive(*scene);
  EXPECT_THAT(prim.indices, ElementsAre(0, 1, 2, 3, 4, 5));
  EXPECT_TRUE(prim.normals.empty());  // absent: the GPU uses face normals
  EXPECT_TRUE(prim.texcoords0.empty());
}

TEST(Geometry, InterleavedAttributesWithByteStride) {
  // position (12 bytes) + normal (12 bytes) + 8 bytes of padding per vertex: stride 32.
  std::vector<float> interleaved;
  for (int v = 0; v < 3; ++v) {
    const float x = static_cast<float>(v);
    interleaved.insert(interleaved.end(), {x, 2 * x, 3 * x, 0, 0, 1, -7, -7});
  }
  GltfBuilder b;
  const int view = b.add_view(interleaved, 32);
  const int positions = b.add_accessor(view, testing::kFloat, 3, "VEC3");
  const int normals = b.add_accessor(view, testing::kFloat, 3, "VEC3", 12);
  place(b, b.add_mesh({{"POSITION", positions}, {"NORMAL", normals}}));
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  const Primitive& prim = only_primitive(*scene);
  ASSERT_EQ(prim.positions.size(), 3u);
  EXPECT_EQ(prim.positions[2], glm::vec3(2, 4, 6));
  EXPECT_EQ(prim.normals[1], glm::vec3(0, 0, 1));
}

TEST(Geometry, TexcoordComponentTypes) {
  GltfBuilder b;
  const int positions = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int uv_float = b.add_accessor(b.add_view(std::vector<float>{0, 0, 0.5f, 0.25f, 1, 1}),
                                      testing::kFloat, 3, "VEC2");
  // Normalized u8 and u16: each pair padded to 4 bytes, as the spec's alignment asks.
  const int uv_u8 =
      b.add_accessor(b.add_view(std::vector<uint8_t>{0, 255, 0, 0, 51, 102, 0, 0, 255, 0, 0, 0}, 4),
                     testing::kUnsignedByte, 3, "VEC2", 0, true);
  const int uv_u16 =
      b.add_accessor(b.add_view(std::vector<uint16_t>{0, 65535, 13107, 0, 65535, 65535}),
                     testing::kUnsignedShort, 3, "VEC2", 0, true);
  place(b, b.add_mesh({{"POSITION", positions}, {"TEXCOORD_0", uv_u8}, {"TEXCOORD_1", uv_u16}}));
  b.doc()["meshes"].push_back(
      {{"primitives", {{{"attributes", {{"POSITION", positions}, {"TEXCOORD_0", uv_float}}}}}}});
  b.doc()["nodes"].push_back({{"mesh", 1}});
  b.doc()["scenes"][0]["nodes"].push_back(1);
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  ASSERT_EQ(scene->meshes.size(), 2u);
  const Primitive& quantized = scene->meshes[0].primitives[0];
  EXPECT_EQ(quantized.texcoords0[0], glm::vec2(0.0f, 1.0f));
  EXPECT_NEAR(quantized.texcoords0[1].x, 0.2f, 1e-6f);
  EXPECT_NEAR(quantized.texcoords0[1].y, 0.4f, 1e-6f);
  EXPECT_NEAR(quantized.texcoords1[1].x, 0.2f, 1e-6f);
  EXPECT_EQ(quantized.texcoords1[2], glm::vec2(1.0f, 1.0f));
  EXPECT_EQ(scene->meshes[1].primitives[0].texcoords0[1], glm::vec2(0.5f, 0.25f));
}

TEST(Geometry, MeshQuantizationPositionsAndNormals) {
  GltfBuilder b;
  b.use_extension("KHR_mesh_quantization");
  // Unnormalized shorts for positions (4-byte aligned: 3 shorts + 1 pad each).
  const int positions =
      b.add_accessor(b.add_view(std::vector<int16_t>{0, 0, 0, 0, 100, 0, 0, 0, 0, -100, 0, 0}, 8),
                     testing::kShort, 3, "VEC3");
  // Normalized bytes for normals: -127 maps to -1 (and -128 as well).
  const int normals =
      b.add_accessor(b.add_view(std::vector<int8_t>{0, 0, 127, 0, 0, 0, -127, 0, 0, -128, 0, 0}, 4),
                     testing::kByte, 3, "VEC3", 0, true);
  place(b, b.add_mesh({{"POSITION", positions}, {"NORMAL", normals}}));
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  const Primitive& prim = only_primitive(*scene);
  EXPECT_EQ(prim.positions[1], glm::vec3(100, 0, 0));
  EXPECT_EQ(prim.positions[2], glm::vec3(0, -100, 0));
  EXPECT_EQ(prim.normals[0], glm::vec3(0, 0, 1));
  EXPECT_EQ(prim.normals[1], glm::vec3(0, 0, -1));
  EXPECT_EQ(prim.normals[2], glm::vec3(0, -1, 0));
}

TEST(Geometry, UnnormalizedIntegerNormalsAreRefused) {
  GltfBuilder b;
  const int positions = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int normals =
      b.add_accessor(b.add_view(std::vector<int8_t>(12, 0), 4), testing::kByte, 3, "VEC3");
  place(b, b.add_mesh({{"POSITION", positions}, {"NORMAL", normals}}));
  EXPECT_THAT(error_of(load_text(b)),
              AllOf(HasSubstr("attributes.NORMAL"), HasSubstr("must be normalized")));
}

TEST(Geometry, SparseAccessorReplacesElements) {
  GltfBuilder b;
  const int base = b.add_view(std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int sparse_indices = b.add_view(std::vector<uint16_t>{1, 2});
  const int sparse_values = b.add_view(std::vector<glm::vec3>{{5, 0, 0}, {0, 7, 0}});
  const int positions = b.add_accessor(base, testing::kFloat, 3, "VEC3");
  b.doc()["accessors"][positions]["sparse"] = {
      {"count", 2},
      {"indices", {{"bufferView", sparse_indices}, {"componentType", testing::kUnsignedShort}}},
      {"values", {{"bufferView", sparse_values}}}};
  place(b, b.add_mesh({{"POSITION", positions}}));
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_THAT(only_primitive(*scene).positions,
              ElementsAre(glm::vec3(0, 0, 0), glm::vec3(5, 0, 0), glm::vec3(0, 7, 0)));
}

TEST(Geometry, SparseAccessorWithoutBufferViewStartsFromZeros) {
  GltfBuilder b;
  const int sparse_indices = b.add_view(std::vector<uint8_t>{2, 0, 0, 0});
  const int sparse_values = b.add_view(std::vector<glm::vec3>{{0, 3, 0}});
  const int positions = b.add_accessor(-1, testing::kFloat, 3, "VEC3");
  b.doc()["accessors"][positions]["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", sparse_indices}, {"componentType", testing::kUnsignedByte}}},
      {"values", {{"bufferView", sparse_values}}}};
  place(b, b.add_mesh({{"POSITION", positions}}));
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_THAT(only_primitive(*scene).positions,
              ElementsAre(glm::vec3(0), glm::vec3(0), glm::vec3(0, 3, 0)));
}

TEST(Geometry, SparseIndexOutOfRangeIsRefused) {
  GltfBuilder b;
  const int sparse_indices = b.add_view(std::vector<uint8_t>{9, 0, 0, 0});
  const int sparse_values = b.add_view(std::vector<glm::vec3>{{0, 3, 0}});
  const int positions = b.add_accessor(-1, testing::kFloat, 3, "VEC3");
  b.doc()["accessors"][positions]["sparse"] = {
      {"count", 1},
      {"indices", {{"bufferView", sparse_indices}, {"componentType", testing::kUnsignedByte}}},
      {"values", {{"bufferView", sparse_values}}}};
  place(b, b.add_mesh({{"POSITION", positions}}));
  EXPECT_THAT(error_of(load_text(b)),
              AllOf(HasSubstr("accessors[0].sparse.indices[0] = 9"), HasSubstr("out of range")));
}

TEST(Geometry, SparseValuesBeyondTheirViewAreRefused) {
  GltfBuilder b;
  const int sparse_indices = b.add_view(std::vector<uint8_t>{0, 1, 0, 0});
  const int sparse_values = b.add_view(std::vector<glm::vec3>{{0, 3, 0}});  // one, not two
  const int positions = b.add_accessor(-1, testing::kFloat, 3, "VEC3");
  b.doc()["accessors"][positions]["sparse"] = {
      {"count", 2},
      {"indices", {{"bufferView", sparse_indices}, {"componentType", testing::kUnsignedByte}}},
      {"values", {{"bufferView", sparse_values}}}};
  place(b, b.add_mesh({{"POSITION", positions}}));
  EXPECT_THAT(error_of(load_text(b)), AllOf(HasSubstr("sparse.values"), HasSubstr("do not fit")));
}

TEST(Geometry, StripsAndFansBecomeLists) {
  GltfBuilder b;
  const int positions = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}});
  const int corners = b.add_indices({0, 1, 2, 3, 4});
  const int strip = b.add_mesh({{"POSITION", positions}}, corners, -1, 5);
  const int fan = b.add_mesh({{"POSITION", positions}}, corners, -1, 6);
  b.set_scene({b.add_node({{"mesh", strip}}), b.add_node({{"mesh", fan}})});
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  // Strip: (0 1 2) (2 1 3) (2 3 4), every other triangle swapped to keep the winding.
  EXPECT_THAT(scene->meshes[0].primitives[0].indices, ElementsAre(0, 1, 2, 1, 3, 2, 2, 3, 4));
  // Fan: (1 2 0) (2 3 0) (3 4 0).
  EXPECT_THAT(scene->meshes[1].primitives[0].indices, ElementsAre(1, 2, 0, 2, 3, 0, 3, 4, 0));
}

TEST(Geometry, PointsAndLinesAreSkippedWithAWarning) {
  GltfBuilder b;
  const int positions = b.add_positions(kQuad);
  const int points = b.add_mesh({{"POSITION", positions}}, -1, -1, 0);
  b.doc()["meshes"][points]["primitives"].push_back({{"attributes", {{"POSITION", positions}}}});
  b.doc()["meshes"][points]["primitives"].push_back(
      {{"attributes", {{"POSITION", positions}}}, {"mode", 1}});
  place(b, points);
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_EQ(only_primitive(*scene).indices.size(), 3u);  // the triangle list, one dropped corner
  EXPECT_THAT(scene->warnings, Contains(HasSubstr("primitives[0]: mode 0")));
  EXPECT_THAT(scene->warnings, Contains(HasSubstr("primitives[2]: mode 1")));
  EXPECT_THAT(scene->warnings, Contains(HasSubstr("not a multiple of 3")));
}

TEST(Geometry, MeshWithoutTrianglesIsLeftOut) {
  GltfBuilder b;
  const int positions = b.add_positions(kQuad);
  place(b, b.add_mesh({{"POSITION", positions}}, -1, -1, 0));
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_TRUE(scene->meshes.empty());
  EXPECT_TRUE(scene->instances.empty());
  EXPECT_THAT(scene->warnings, Contains(HasSubstr("no triangles")));
}

TEST(Geometry, IndexOutOfRangeIsRefused) {
  GltfBuilder b;
  const int positions = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int indices = b.add_indices({0, 1, 3}, testing::kUnsignedShort);
  place(b, b.add_mesh({{"POSITION", positions}}, indices));
  EXPECT_THAT(error_of(load_text(b)),
              AllOf(HasSubstr("test.gltf"), HasSubstr("meshes[0].primitives[0].indices"),
                    HasSubstr("index 3 at position 2 is out of range"), HasSubstr("3 vertices")));
}

TEST(Geometry, AccessorLargerThanItsBufferViewIsRefused) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["accessors"][0]["count"] = 4;  // 4 x 12 bytes in a 36-byte view
  EXPECT_THAT(error_of(load_text(b)),
              AllOf(HasSubstr("accessors[0]"), HasSubstr("do not fit in bufferViews[0]")));
  // The last element ends at offset + stride * (count - 1) + element size.
  b.doc()["accessors"][0]["count"] = 3;
  b.doc()["accessors"][0]["byteOffset"] = 4;
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("do not fit"));
}

TEST(Geometry, StrideSmallerThanAnElementIsRefused) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["bufferViews"][0]["byteStride"] = 8;
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("byteStride 8 is smaller than one element"));
}

TEST(Geometry, BufferViewBeyondItsBufferIsRefused) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["bufferViews"][1]["byteLength"] = 400;
  EXPECT_THAT(error_of(load_text(b)),
              AllOf(HasSubstr("bufferViews[1]"), HasSubstr("runs past the end of buffers[0]")));
  b.doc()["bufferViews"][1]["byteLength"] = 6;
  b.doc()["bufferViews"][1]["buffer"] = 3;
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("bufferViews[1].buffer = 3 does not exist (the file has 1 buffers)"));
}

TEST(Geometry, AbsurdCountsAreRefused) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["accessors"][0]["count"] = 1ull << 31;
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("2147483648 elements"));
  // Without a bufferView the elements cost no file bytes; the vertex limit stops them.
  b.doc()["accessors"][0].erase("bufferView");
  Result<Scene> scene = load_text(b);
  EXPECT_THAT(error_of(scene), HasSubstr("exceeds the vertex limit"));
  EXPECT_EQ(scene.error().code, ErrorCode::kResourceExhausted);
}

TEST(Geometry, NanAndInfinitePositionsAreRefused) {
  for (float bad :
       {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    GltfBuilder b;
    const int positions = b.add_positions({{0, 0, 0}, {1, bad, 0}, {0, 1, 0}});
    place(b, b.add_mesh({{"POSITION", positions}}));
    EXPECT_THAT(error_of(load_text(b)),
                AllOf(HasSubstr("attributes.POSITION"), HasSubstr("element 1 component 1"),
                      HasSubstr(std::isnan(bad) ? "NaN" : "infinite")));
  }
}

TEST(Geometry, AttributeCountMismatchIsRefused) {
  GltfBuilder b;
  const int positions = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int normals = b.add_positions({{0, 0, 1}, {0, 0, 1}});
  place(b, b.add_mesh({{"POSITION", positions}, {"NORMAL", normals}}));
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("attributes.NORMAL has 2 elements but POSITION has 3"));
}

TEST(Geometry, WrongAccessorTypesAreRefused) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["accessors"][0]["type"] = "VEC2";
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("attributes.POSITION (accessors[0]) must be VEC3"));
  b = GltfBuilder();
  const int positions = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int indices = b.add_indices({0, 1, 2}, testing::kUnsignedInt);
  b.doc()["accessors"][indices]["componentType"] = testing::kFloat;
  place(b, b.add_mesh({{"POSITION", positions}}, indices));
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("indices (accessors[1]): componentType 5126"));
  b = testing::triangle_builder();
  b.doc()["accessors"][1]["componentType"] = 5124;  // INT: not a glTF 2.0 component type
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("not a glTF 2.0 accessor component type"));
}

TEST(Geometry, ReferencesOutOfRangeAreRefused) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 7;
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("meshes[0].primitives[0].attributes.POSITION = 7 does not exist"));
  b = testing::triangle_builder();
  b.doc()["meshes"][0]["primitives"][0]["indices"] = 5;
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("test.gltf: meshes[0].primitives[0].indices = 5 does not exist (the file "
                        "has 2 accessors)"));
  b = testing::triangle_builder();
  b.doc()["meshes"][0]["primitives"][0]["material"] = 2;
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("meshes[0].primitives[0].material = 2 does not exist"));
  b = testing::triangle_builder();
  b.doc()["accessors"][0]["bufferView"] = 9;
  EXPECT_THAT(error_of(load_text(b)), HasSubstr("accessors[0].bufferView = 9 does not exist"));
  b = testing::triangle_builder();
  b.doc()["meshes"][0]["primitives"][0]["mode"] = 9;
  EXPECT_THAT(error_of(load_text(b)),
              HasSubstr("meshes[0].primitives[0].mode: expected an integer in [0, 6], got 9"));
}

TEST(Geometry, TriangleLimitIsEnforced) {
  GltfBuilder b;
  const int positions = b.add_positions(kQuad);
  const int indices = b.add_indices({0, 1, 2, 0, 2, 3});
  place(b, b.add_mesh({{"POSITION", positions}}, indices));
  SceneLimits limits;
  limits.max_triangles = 1;
  Result<Scene> scene = load_text(b, limits);
  EXPECT_THAT(error_of(scene), HasSubstr("limit"));
  EXPECT_EQ(scene.error().code, ErrorCode::kResourceExhausted);
  limits.max_triangles = 2;
  EXPECT_TRUE(load_text(b, limits).ok());
}

TEST(Geometry, PrimitiveLimitIsEnforced) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["meshes"][0]["primitives"].push_back(b.doc()["meshes"][0]["primitives"][0]);
  SceneLimits limits;
  limits.max_primitives = 1;
  EXPECT_THAT(error_of(load_text(b, limits)),
              HasSubstr("primitives[1]: the scene has more than the limit of 1 primitives"));
  limits.max_primitives = 2;
  EXPECT_TRUE(load_text(b, limits).ok());
}

TEST(Geometry, SharedMeshIsConvertedOnce) {
  GltfBuilder b = testing::triangle_builder();
  b.doc()["nodes"].push_back({{"mesh", 0}, {"translation", {5, 0, 0}}});
  b.doc()["scenes"][0]["nodes"].push_back(1);
  Result<Scene> scene = load_text(b);
  ASSERT_TRUE(scene.ok()) << error_of(scene);
  EXPECT_EQ(scene->meshes.size(), 1u);
  ASSERT_EQ(scene->instances.size(), 2u);
  EXPECT_EQ(scene->instances[1].mesh, 0);
  EXPECT_EQ(scene->instances[1].node, 1);
  EXPECT_EQ(testing::drawn_triangles(*scene), 2u);
}

}  // namespace
}  // namespace ddgi
