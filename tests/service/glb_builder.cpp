#include "tests/service/glb_builder.h"

#include <cstdint>
#include <cstring>
#include <vector>

namespace ddgi::test {
namespace {

void put_u32(std::string& out, uint32_t value) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((value >> (8 * i)) & 0xff));
}

std::string glb_of(std::string json, std::string bin) {
  while (json.size() % 4) json.push_back(' ');
  while (bin.size() % 4) bin.push_back('\0');
  std::string glb;
  put_u32(glb, 0x46546C67);  // "glTF"
  put_u32(glb, 2);
  put_u32(glb, static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin.size()));
  put_u32(glb, static_cast<uint32_t>(json.size()));
  put_u32(glb, 0x4E4F534A);  // "JSON"
  glb += json;
  put_u32(glb, static_cast<uint32_t>(bin.size()));
  put_u32(glb, 0x004E4942);  // "BIN"
  glb += bin;
  return glb;
}

}  // namespace

std::string make_grid_glb(uint32_t cells) {
  const uint32_t side = cells + 1;
  std::vector<float> positions;
  positions.reserve(size_t(side) * side * 3);
  for (uint32_t z = 0; z < side; ++z) {
    for (uint32_t x = 0; x < side; ++x) {
      positions.push_back(float(x) / float(cells) - 0.5f);
      positions.push_back(0.0f);
      positions.push_back(float(z) / float(cells) - 0.5f);
    }
  }
  std::vector<uint32_t> indices;
  indices.reserve(size_t(cells) * cells * 6);
  for (uint32_t z = 0; z < cells; ++z) {
    for (uint32_t x = 0; x < cells; ++x) {
      const uint32_t a = z * side + x, b = a + 1, c = a + side, d = c + 1;
      for (uint32_t i : {a, c, b, b, c, d}) indices.push_back(i);
    }
  }
  const size_t position_bytes = positions.size() * sizeof(float);
  const size_t index_bytes = indices.size() * sizeof(uint32_t);
  std::string bin(position_bytes + index_bytes, '\0');
  std::memcpy(bin.data(), positions.data(), position_bytes);
  std::memcpy(bin.data() + position_bytes, indices.data(), index_bytes);
  const std::string json =
      R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],)"
      R"("nodes":[{"name":"floor","mesh":0},{"name":"lamp","translation":[0,1,0],)"
      R"("extensions":{"KHR_lights_punctual":{"light":0}}}],)"
      R"("extensionsUsed":["KHR_lights_punctual"],)"
      R"("extensions":{"KHR_lights_punctual":{"lights":[{"name":"lamp","type":"point",)"
      R"("intensity":2.0}]}},)"
      R"("meshes":[{"name":"floor","primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":)" +
      std::to_string(positions.size() / 3) +
      R"(,"type":"VEC3","min":[-0.5,0,-0.5],"max":[0.5,0,0.5]},)"
      R"({"bufferView":1,"componentType":5125,"count":)" +
      std::to_string(indices.size()) +
      R"(,"type":"SCALAR"}],)"
      R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":)" +
      std::to_string(position_bytes) + R"(},{"buffer":0,"byteOffset":)" +
      std::to_string(position_bytes) + R"(,"byteLength":)" + std::to_string(index_bytes) +
      R"(}],"buffers":[{"byteLength":)" + std::to_string(bin.size()) + "}]}";
  return glb_of(json, bin);
}

std::string make_floor_glb() {
  const float positions[] = {-0.5f, 0, -0.5f, 0.5f, 0, -0.5f, 0.5f, 0, 0.5f, -0.5f, 0, 0.5f};
  const uint16_t indices[] = {0, 2, 1, 0, 3, 2};
  std::string bin(sizeof(positions) + sizeof(indices), '\0');
  std::memcpy(bin.data(), positions, sizeof(positions));
  std::memcpy(bin.data() + sizeof(positions), indices, sizeof(indices));
  while (bin.size() % 4) bin.push_back('\0');
  std::string json =
      R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],)"
      R"("nodes":[{"name":"floor","mesh":0},{"name":"lamp","translation":[0,1,0],)"
      R"("extensions":{"KHR_lights_punctual":{"light":0}}}],)"
      R"("extensionsUsed":["KHR_lights_punctual"],)"
      R"("extensions":{"KHR_lights_punctual":{"lights":[{"name":"lamp","type":"point",)"
      R"("intensity":2.0}]}},)"
      R"("meshes":[{"name":"floor","primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3",)"
      R"("min":[-0.5,0,-0.5],"max":[0.5,0,0.5]},)"
      R"({"bufferView":1,"componentType":5123,"count":6,"type":"SCALAR"}],)"
      R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},)"
      R"({"buffer":0,"byteOffset":48,"byteLength":12}],)"
      R"("buffers":[{"byteLength":60}]})";
  return glb_of(json, bin);
}

}  // namespace ddgi::test
