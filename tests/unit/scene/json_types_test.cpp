// Wrongly typed and out-of-range references in a glTF document: each is refused with a message
// naming its JSON path and showing the value, as .gltf text and as an uploaded .glb. tinygltf
// alone drops a member of the wrong type (the node or attribute silently disappears), so these
// are the cases an outside client found accepted (issue 18).
#include <functional>
#include <ostream>
#include <string>

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

struct BadValue {
  const char* name;  // test name suffix
  std::function<void(json&)> mutate;
  const char* message;  // a substring the error must contain: the path and what is wrong
};

// triangle_builder plus a second node on the same mesh, a material and a camera, so that
// every kind of reference has something valid to point at.
GltfBuilder base_scene() {
  GltfBuilder b = testing::triangle_builder();
  b.add_node({{"mesh", 0}});
  b.set_scene({0, 1});
  b.add_material({{"name", "grey"}});
  b.doc()["meshes"][0]["primitives"][0]["material"] = 0;
  b.doc()["cameras"] = {
      {{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}}}}};
  return b;
}

json& primitive(json& doc) {
  return doc["meshes"][0]["primitives"][0];
}

const BadValue kBadValues[] = {
    // The cases of the issue.
    {"MeshMinusOne", [](json& d) { d["nodes"][1]["mesh"] = -1; },
     "nodes[1].mesh: expected a non-negative integer index, got -1"},
    {"MeshString", [](json& d) { d["nodes"][1]["mesh"] = "abc"; },
     "nodes[1].mesh: expected a non-negative integer index, got \"abc\""},
    {"MeshFraction", [](json& d) { d["nodes"][1]["mesh"] = 1.5; },
     "nodes[1].mesh: expected a non-negative integer index, got 1.5"},
    {"IndicesString", [](json& d) { primitive(d)["indices"] = "x"; },
     "meshes[0].primitives[0].indices: expected a non-negative integer index, got \"x\""},
    {"MaterialString", [](json& d) { primitive(d)["material"] = "x"; },
     "meshes[0].primitives[0].material: expected a non-negative integer index, got \"x\""},
    {"MaterialMinusOne", [](json& d) { primitive(d)["material"] = -1; },
     "meshes[0].primitives[0].material: expected a non-negative integer index, got -1"},
    {"ChildString", [](json& d) { d["nodes"][0]["children"] = {"a"}; },
     "nodes[0].children[0]: expected a non-negative integer index, got \"a\""},
    {"SceneString", [](json& d) { d["scene"] = "x"; },
     "scene: expected a non-negative integer index, got \"x\""},
    {"CameraMinusOne", [](json& d) { d["nodes"][1]["camera"] = -1; },
     "nodes[1].camera: expected a non-negative integer index, got -1"},
    {"TranslationString", [](json& d) { d["nodes"][1]["translation"] = "x"; },
     "nodes[1].translation: expected an array of numbers, got \"x\""},
    // Refused before, still refused, with the path.
    {"MeshMinusTwo", [](json& d) { d["nodes"][1]["mesh"] = -2; },
     "nodes[1].mesh: expected a non-negative integer index, got -2"},
    {"Mesh99", [](json& d) { d["nodes"][1]["mesh"] = 99; },
     "nodes[1].mesh = 99 does not exist (the file has 1 meshes)"},
    // Neighbours of the same defects.
    {"MeshNarrowsToMinusOne", [](json& d) { d["nodes"][1]["mesh"] = 4294967295u; },
     "nodes[1].mesh = 4294967295 does not exist (the file has 1 meshes)"},
    {"MeshNull", [](json& d) { d["nodes"][1]["mesh"] = nullptr; },
     "nodes[1].mesh: expected a non-negative integer index, got null"},
    {"MeshBoolean", [](json& d) { d["nodes"][1]["mesh"] = true; },
     "nodes[1].mesh: expected a non-negative integer index, got true"},
    {"SecondChildString",
     [](json& d) {
       d["nodes"][0]["children"] = {1, "a"};
     },
     "nodes[0].children[1]: expected a non-negative integer index, got \"a\""},
    {"ChildrenNotArray", [](json& d) { d["nodes"][0]["children"] = 1; },
     "nodes[0].children: expected an array of indices, got 1"},
    {"SceneRootString",
     [](json& d) {
       d["scenes"][0]["nodes"] = {0, "1"};
     },
     "scenes[0].nodes[1]: expected a non-negative integer index, got \"1\""},
    {"TranslationElement",
     [](json& d) {
       d["nodes"][1]["translation"] = {1, "x", 3};
     },
     "nodes[1].translation[1]: expected a number, got \"x\""},
    {"MatrixString", [](json& d) { d["nodes"][1]["matrix"] = "identity"; },
     "nodes[1].matrix: expected an array of numbers, got \"identity\""},
    {"AttributeString", [](json& d) { primitive(d)["attributes"]["POSITION"] = "0"; },
     "meshes[0].primitives[0].attributes.POSITION: expected a non-negative integer index, got "
     "\"0\""},
    {"ModeString", [](json& d) { primitive(d)["mode"] = "TRIANGLES"; },
     "meshes[0].primitives[0].mode: expected an integer in [0, 6], got \"TRIANGLES\""},
    {"AccessorViewString", [](json& d) { d["accessors"][0]["bufferView"] = "0"; },
     "accessors[0].bufferView: expected a non-negative integer index, got \"0\""},
    {"ViewBufferMinusOne", [](json& d) { d["bufferViews"][0]["buffer"] = -1; },
     "bufferViews[0].buffer: expected a non-negative integer index, got -1"},
    {"BaseColorTextureString",
     [](json& d) {
       d["materials"][0]["pbrMetallicRoughness"] = {{"baseColorTexture", {{"index", "t"}}}};
     },
     "materials[0].pbrMetallicRoughness.baseColorTexture.index: expected a non-negative integer "
     "index, got \"t\""},
    {"BaseColorFactorString",
     [](json& d) {
       d["materials"][0]["pbrMetallicRoughness"] = {{"baseColorFactor", "red"}};
     },
     "materials[0].pbrMetallicRoughness.baseColorFactor: expected an array of numbers, got "
     "\"red\""},
    {"EmissiveStrengthString",
     [](json& d) {
       d["materials"][0]["extensions"] = {
           {"KHR_materials_emissive_strength", {{"emissiveStrength", "9"}}}};
     },
     "materials[0].extensions.KHR_materials_emissive_strength.emissiveStrength: expected a "
     "number, got \"9\""},
    {"MaterialNameNumber", [](json& d) { d["materials"][0]["name"] = 5; },
     "materials[0].name: expected a string, got 5"},
    {"LightIndexString",
     [](json& d) {
       d["nodes"][1]["extensions"] = {{"KHR_lights_punctual", {{"light", "0"}}}};
     },
     "nodes[1].extensions.KHR_lights_punctual.light: expected a non-negative integer index, got "
     "\"0\""},
    {"NodesNotArray",
     [](json& d) {
       d["cameras"] = {{"type", "perspective"}};
     },
     "cameras: expected an array of objects, got {\"type\":\"perspective\"}"},
    {"NodeNotObject", [](json& d) { d["nodes"].push_back(7); },
     "nodes[2]: expected an object, got 7"},
    {"LongValueIsCut", [](json& d) { d["nodes"][1]["mesh"] = std::string(200, 'z'); },
     "nodes[1].mesh: expected a non-negative integer index, got \"zzzzzzzzzzzzzzzzzzzzzzzzzzzzzz"
     "zzzzzz..."},
};

void PrintTo(const BadValue& value, std::ostream* out) {
  *out << value.name;
}

class JsonTypes : public ::testing::TestWithParam<BadValue> {};

TEST_P(JsonTypes, RefusedAsGltfTextNamingThePath) {
  GltfBuilder b = base_scene();
  ASSERT_TRUE(testing::load_text(b).ok()) << error_of(testing::load_text(b));
  GetParam().mutate(b.doc());
  const Result<Scene> scene = testing::load_text(b);
  EXPECT_THAT(error_of(scene), AllOf(HasSubstr("test.gltf: "), HasSubstr(GetParam().message)));
  if (!scene.ok()) {
    EXPECT_EQ(scene.error().code, ErrorCode::kInvalidArgument);
  }
}

TEST_P(JsonTypes, RefusedAsUploadedGlb) {
  GltfBuilder b = base_scene();
  GetParam().mutate(b.doc());
  EXPECT_THAT(error_of(load_glb_from_memory(b.glb(), "upload:1", {})),
              AllOf(HasSubstr("upload:1: "), HasSubstr(GetParam().message)));
}

INSTANTIATE_TEST_SUITE_P(Scene, JsonTypes, ::testing::ValuesIn(kBadValues),
                         [](const auto& test) { return std::string(test.param.name); });

}  // namespace
}  // namespace ddgi
