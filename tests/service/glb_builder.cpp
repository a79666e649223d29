#include "tests/service/glb_builder.h"

#include <cstdint>
#include <cstring>
#include <vector>

namespace ddgi::test {
namespace {

void put_u32(std::string& out, uint32_t value) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((value >> (8 * i)) & 0xff));
}

}  // namespace

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
  while (json.size() % 4) json.push_back(' ');
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

}  // namespace ddgi::test
