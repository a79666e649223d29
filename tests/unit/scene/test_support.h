// Builders for tiny glTF inputs written by the tests themselves: a JSON document plus one
// binary buffer, emitted as .gltf (data URI or external .bin) or .glb, in a fresh temporary
// folder per test.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/result.h"
#include "scene/gltf_loader.h"

namespace ddgi::testing {

using nlohmann::json;

// glTF enums, spelled out for readability.
enum : int {
  kByte = 5120,
  kUnsignedByte = 5121,
  kShort = 5122,
  kUnsignedShort = 5123,
  kUnsignedInt = 5125,
  kFloat = 5126,
};

class GltfBuilder {
 public:
  GltfBuilder();

  json& doc() { return doc_; }
  const std::vector<uint8_t>& bin() const { return bin_; }

  // Appends bytes to the buffer (4-byte aligned) and adds a bufferView over them.
  int add_view(const void* data, size_t bytes, int stride = 0);
  template <typename T>
  int add_view(const std::vector<T>& values, int stride = 0) {
    return add_view(values.data(), values.size() * sizeof(T), stride);
  }
  int add_accessor(int view, int component_type, size_t count, const std::string& type,
                   size_t byte_offset = 0, bool normalized = false);
  int add_positions(const std::vector<glm::vec3>& positions);
  int add_indices(const std::vector<uint32_t>& indices, int component_type = kUnsignedInt);
  // One primitive; returns the mesh index.
  int add_mesh(json attributes, int indices = -1, int material = -1, int mode = -1);
  int add_node(json node);
  int add_material(json material);
  // Scene 0 with these roots (replaces any previous scenes).
  void set_scene(std::vector<int> roots);
  void use_extension(const std::string& name);

  // The document with buffer 0 embedded as a base64 data URI (or the given uri).
  std::string gltf_text(const std::string& buffer_uri = "") const;
  // The document and buffer as a binary glTF.
  std::vector<uint8_t> glb() const;

 private:
  json doc_;
  std::vector<uint8_t> bin_;
};

// A single triangle (0,0,0) (1,0,0) (0,1,0) on node 0 in scene 0, indexed with u16.
GltfBuilder triangle_builder();

std::string base64(const std::vector<uint8_t>& bytes);
std::vector<uint8_t> to_bytes(const std::string& text);
// A GLB container around these chunks, with exact lengths (tests corrupt them afterwards).
std::vector<uint8_t> make_glb(const std::string& json_text, const std::vector<uint8_t>& bin);
void put_u32(std::vector<uint8_t>* bytes, size_t offset, uint32_t value);
// RGBA8 pixels as a PNG file's bytes.
std::vector<uint8_t> encode_png(int width, int height, const std::vector<uint8_t>& rgba);

// A temporary folder removed when the object goes away.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path write(const std::string& name, const std::string& text) const;
  std::filesystem::path write(const std::string& name, const std::vector<uint8_t>& bytes) const;

 private:
  std::filesystem::path path_;
};

// The message of a failed result ("" when it succeeded, so EXPECT_THAT fails visibly).
template <typename T>
std::string error_of(const Result<T>& result) {
  return result.ok() ? std::string() : result.error().message;
}

// Loads the builder's document from memory as .gltf text.
Result<Scene> load_text(const GltfBuilder& builder, const SceneLimits& limits = {});
// Total triangles over every instance.
uint64_t drawn_triangles(const Scene& scene);

}  // namespace ddgi::testing
