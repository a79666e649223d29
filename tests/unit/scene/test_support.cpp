#include "test_support.h"

#include <cstring>
#include <fstream>
#include <random>

#include <stb_image_write.h>

namespace ddgi::testing {
namespace fs = std::filesystem;

GltfBuilder::GltfBuilder() {
  doc_ = {{"asset", {{"version", "2.0"}}}};
}

int GltfBuilder::add_view(const void* data, size_t bytes, int stride) {
  while (bin_.size() % 4 != 0) bin_.push_back(0);
  const size_t offset = bin_.size();
  bin_.resize(offset + bytes);
  if (bytes > 0) std::memcpy(bin_.data() + offset, data, bytes);
  json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
  if (stride > 0) view["byteStride"] = stride;
  doc_["bufferViews"].push_back(view);
  return static_cast<int>(doc_["bufferViews"].size()) - 1;
}

int GltfBuilder::add_accessor(int view, int component_type, size_t count, const std::string& type,
                              size_t byte_offset, bool normalized) {
  json accessor = {{"componentType", component_type}, {"count", count}, {"type", type}};
  if (view >= 0) accessor["bufferView"] = view;
  if (byte_offset > 0) accessor["byteOffset"] = byte_offset;
  if (normalized) accessor["normalized"] = true;
  doc_["accessors"].push_back(accessor);
  return static_cast<int>(doc_["accessors"].size()) - 1;
}

int GltfBuilder::add_positions(const std::vector<glm::vec3>& positions) {
  const int view = add_view(positions);
  return add_accessor(view, kFloat, positions.size(), "VEC3");
}

int GltfBuilder::add_indices(const std::vector<uint32_t>& indices, int component_type) {
  int view = -1;
  if (component_type == kUnsignedByte) {
    view = add_view(std::vector<uint8_t>(indices.begin(), indices.end()));
  } else if (component_type == kUnsignedShort) {
    view = add_view(std::vector<uint16_t>(indices.begin(), indices.end()));
  } else {
    view = add_view(indices);
  }
  return add_accessor(view, component_type, indices.size(), "SCALAR");
}

int GltfBuilder::add_mesh(json attributes, int indices, int material, int mode) {
  json primitive = {{"attributes", attributes}};
  if (indices >= 0) primitive["indices"] = indices;
  if (material >= 0) primitive["material"] = material;
  if (mode >= 0) primitive["mode"] = mode;
  doc_["meshes"].push_back({{"primitives", {primitive}}});
  return static_cast<int>(doc_["meshes"].size()) - 1;
}

int GltfBuilder::add_node(json node) {
  doc_["nodes"].push_back(node);
  return static_cast<int>(doc_["nodes"].size()) - 1;
}

int GltfBuilder::add_material(json material) {
  doc_["materials"].push_back(material);
  return static_cast<int>(doc_["materials"].size()) - 1;
}

void GltfBuilder::set_scene(std::vector<int> roots) {
  doc_["scenes"] = json::array({{{"nodes", roots}}});
  doc_["scene"] = 0;
}

void GltfBuilder::use_extension(const std::string& name) {
  doc_["extensionsUsed"].push_back(name);
}

std::string GltfBuilder::gltf_text(const std::string& buffer_uri) const {
  json doc = doc_;
  if (!bin_.empty()) {
    doc["buffers"] = json::array(
        {{{"byteLength", bin_.size()},
          {"uri", buffer_uri.empty() ? "data:application/octet-stream;base64," + base64(bin_)
                                     : buffer_uri}}});
  }
  return doc.dump();
}

std::vector<uint8_t> GltfBuilder::glb() const {
  json doc = doc_;
  if (!bin_.empty()) doc["buffers"] = json::array({{{"byteLength", bin_.size()}}});
  return make_glb(doc.dump(), bin_);
}

GltfBuilder triangle_builder() {
  GltfBuilder b;
  const int positions = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int indices = b.add_indices({0, 1, 2}, kUnsignedShort);
  const int mesh = b.add_mesh({{"POSITION", positions}}, indices);
  b.set_scene({b.add_node({{"mesh", mesh}})});
  return b;
}

std::string base64(const std::vector<uint8_t>& bytes) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t b0 = bytes[i];
    const uint32_t b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0;
    const uint32_t b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0;
    const uint32_t triple = b0 << 16 | b1 << 8 | b2;
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(triple >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[triple & 63] : '=';
  }
  return out;
}

std::vector<uint8_t> to_bytes(const std::string& text) {
  return std::vector<uint8_t>(text.begin(), text.end());
}

void put_u32(std::vector<uint8_t>* bytes, size_t offset, uint32_t value) {
  for (int i = 0; i < 4; ++i) (*bytes)[offset + static_cast<size_t>(i)] = (value >> (8 * i)) & 0xFF;
}

std::vector<uint8_t> make_glb(const std::string& json_text, const std::vector<uint8_t>& bin) {
  std::vector<uint8_t> json_chunk(json_text.begin(), json_text.end());
  while (json_chunk.size() % 4 != 0) json_chunk.push_back(' ');
  std::vector<uint8_t> bin_chunk = bin;
  while (bin_chunk.size() % 4 != 0) bin_chunk.push_back(0);
  std::vector<uint8_t> out(12, 0);
  auto append_chunk = [&](const std::vector<uint8_t>& data, uint32_t type) {
    const size_t at = out.size();
    out.resize(at + 8);
    put_u32(&out, at, static_cast<uint32_t>(data.size()));
    put_u32(&out, at + 4, type);
    out.insert(out.end(), data.begin(), data.end());
  };
  append_chunk(json_chunk, 0x4E4F534A);
  if (!bin_chunk.empty()) append_chunk(bin_chunk, 0x004E4942);
  put_u32(&out, 0, 0x46546C67);
  put_u32(&out, 4, 2);
  put_u32(&out, 8, static_cast<uint32_t>(out.size()));
  return out;
}

std::vector<uint8_t> encode_png(int width, int height, const std::vector<uint8_t>& rgba) {
  std::vector<uint8_t> png;
  stbi_write_png_to_func(
      [](void* context, void* data, int size) {
        auto* out = static_cast<std::vector<uint8_t>*>(context);
        const auto* bytes = static_cast<const uint8_t*>(data);
        out->insert(out->end(), bytes, bytes + size);
      },
      &png, width, height, 4, rgba.data(), width * 4);
  return png;
}

TempDir::TempDir() {
  std::random_device random;
  path_ = fs::temp_directory_path() /
          ("ddgi_scene_test_" + std::to_string(random()) + std::to_string(random()));
  fs::create_directories(path_);
}

TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

fs::path TempDir::write(const std::string& name, const std::string& text) const {
  return write(name, to_bytes(text));
}

fs::path TempDir::write(const std::string& name, const std::vector<uint8_t>& bytes) const {
  const fs::path file = path_ / name;
  fs::create_directories(file.parent_path());
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  return file;
}

Result<Scene> load_text(const GltfBuilder& builder, const SceneLimits& limits) {
  return load_gltf_from_memory(to_bytes(builder.gltf_text()), "test.gltf", limits);
}

uint64_t drawn_triangles(const Scene& scene) {
  uint64_t total = 0;
  for (const Instance& instance : scene.instances) {
    for (const Primitive& prim : scene.meshes[static_cast<size_t>(instance.mesh)].primitives) {
      total += prim.indices.size() / 3;
    }
  }
  return total;
}

}  // namespace ddgi::testing
