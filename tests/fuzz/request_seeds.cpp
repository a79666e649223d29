// Writes the request fuzzer's seed corpus: one input per request shape the service tests send
// (tests/service), in request_input.h's format, so fuzzing starts from requests that reach deep
// into validation and dispatch instead of from random bytes.
//   request_seeds OUT_DIR
#include <google/protobuf/text_format.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <string_view>

#include "ddgi/v1/render_service.pb.h"
#include "tests/fuzz/request_input.h"

namespace ddgi::fuzz {
namespace {

struct Seed {
  std::string_view method;
  uint8_t flags;
  std::string_view text;  // the request in protobuf text format
};

constexpr uint8_t kLive = kLiveSession;
constexpr uint8_t kLiveWithView = kLiveSession | kLiveView;

// clang-format off
constexpr Seed kSeeds[] = {
  {"GetServerInfo", 0, ""},
  {"GetServerInfo", kNoToken, ""},
  {"CreateSession", 0, R"(scene { name: "cornell_box" } warmup_updates: 1
      field_params { name: "counts" value: "2,2,2" } field_params { name: "rays_per_probe" value: "16" })"},
  {"CreateSession", 0, R"(scene { name: "two_rooms_open" } warmup_updates: 1 direct_mode: DIRECT_MODE_SHADOW_FIELD
      field_params { name: "counts" value: "2,2,2" })"},
  {"CreateSession", 0, R"(scene { name: "../etc/passwd" })"},
  {"CreateSession", 0, R"(scene { glb: "glTF\002\000\000\000" })"},
  {"LoadScene", kLive, R"(scene { name: "cornell_box" } warmup_updates: 1)"},
  {"CloseSession", 0, R"(session_id: "no-such-session")"},
  {"ListSessions", 0, ""},
  {"GetSession", kLive, ""},
  {"CreateView", kLive, R"(settings { width: 32 height: 24 view_mode: VIEW_MODE_INDIRECT }
      camera { position { x: 0 y: 1 z: 3 } target { x: 0 y: 1 z: 0 } vertical_fov_degrees: 60 })"},
  {"UpdateView", kLiveWithView, R"(settings { width: 40 exposure: 2 tonemap: TONEMAP_REINHARD jpeg_quality: 50 })"},
  {"DeleteView", kLiveWithView, ""},
  {"SetCamera", kLiveWithView, R"(camera { position { x: 0.3 y: 0.8 z: 1.2 } forward { x: 0 y: 0 z: -1 } up { y: 1 } })"},
  {"SetCamera", kLiveWithView, R"(camera { position { x: 0 y: 1 z: 3 } target { x: 0 y: 1 z: 3 } })"},
  {"SetCamera", kLiveWithView, R"(camera { position { x: inf y: 1 z: 3 } forward { z: -1 } vertical_fov_degrees: 179 })"},
  {"RenderFrame", kLive, R"(settings { width: 100000 height: 0 exposure: -1 jpeg_quality: 101 })"},
  {"AddLight", kLive, R"(light { type: LIGHT_TYPE_SPOT color { x: 1 y: 0.9 z: 0.8 } intensity: 20 range: 5
      inner_cone_degrees: 20 outer_cone_degrees: 30 position { y: 1.5 } direction { y: -1 } radius: 0.05 })"},
  {"AddLight", kLive, R"(light { type: LIGHT_TYPE_DIRECTIONAL direction { x: 1 y: -1 } intensity: 3 })"},
  {"UpdateLight", kLive, R"(light_id: 1 light { intensity: 5 position { x: 0.2 y: 1.2 } })"},
  {"RemoveLight", kLive, R"(light_id: 1)"},
  {"UpdateLight", kLive, R"(light_id: 99 light { intensity: nan })"},
  {"SetInstanceTransform", kLive, R"(instance_index: 0 transform { m: [1,0,0,0, 0,1,0,0, 0,0,1,0, 0.1,0,0,1] })"},
  {"SetInstanceTransform", kLive, R"(instance_index: 7 transform { m: [2,0,0,0, 0,2,0,0, 0,0,2,0, 0,0,0,1] })"},
  {"SetInstanceTransform", kLive, R"(instance_index: 0 transform { m: [0,0,0,0, 0,0,0,0, 0,0,0,0, 0,0,0,1] })"},
  {"GetFieldParams", kLive, R"(field: FIELD_KIND_IRRADIANCE)"},
  {"SetFieldParams", kLive, R"(params { name: "hysteresis" value: "0.9" } params { name: "rays_per_probe" value: "32" })"},
  {"SetFieldParams", kLive, R"(params { name: "counts" value: "3,2,3" })"},
  {"SetFieldParams", kLive, R"(field: FIELD_KIND_SHADOW params { name: "rays_per_probe" value: "8" })"},
  {"RenderFrame", kLive, R"(settings { width: 24 height: 16 view_mode: VIEW_MODE_NORMAL })"},
  {"RenderFrame", kLiveWithView, ""},
  {"StreamFrames", kLive, R"(settings { width: 16 height: 16 } max_fps: 30)"},
  {"StreamFrames", kLiveWithView, ""},
  {"DumpAtlas", kLive, R"(kind: ATLAS_KIND_IRRADIANCE format: ATLAS_FORMAT_EXR)"},
  {"DumpAtlas", kLive, R"(kind: ATLAS_KIND_PROBE_STATES)"},
  {"DumpAtlas", kLive, R"(kind: ATLAS_KIND_SH)"},
  {"StreamProbes", kLive, ""},
  {"StreamProbes", kLive, R"(change_threshold: 0.05 full_refresh_interval: 2)"},
  {"ExportScene", kLive, ""},
  {"ExportScene", 0, R"(session_id: "nope")"},
  {"QueryIrradiance", kLive, R"(points { position { y: 1 } normal { y: 1 } }
      points { position { x: 0.5 y: 0.2 } normal { x: -1 } to_viewer { z: 1 } })"},
};
// clang-format on

const google::protobuf::ServiceDescriptor& service() {
  return *v1::GetSessionRequest::descriptor()->file()->FindServiceByName("RenderService");
}

const google::protobuf::Descriptor* request_type(std::string_view method) {
  const google::protobuf::MethodDescriptor* found = service().FindMethodByName(std::string(method));
  return found ? found->input_type() : nullptr;
}

int method_index(std::string_view method) {
  for (size_t i = 0; i < kMethods.size(); ++i) {
    if (kMethods[i] == method) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace
}  // namespace ddgi::fuzz

int main(int argc, char** argv) {
  using namespace ddgi::fuzz;
  if (argc != 2) {
    std::fprintf(stderr, "usage: request_seeds OUT_DIR\n");
    return 2;
  }
  // Every method of the service has its place in the input format.
  if (service().method_count() != int(kMethods.size())) {
    std::fprintf(stderr, "request_input.h's kMethods does not list every RPC\n");
    return 1;
  }
  int written = 0;
  for (const Seed& seed : kSeeds) {
    const int index = method_index(seed.method);
    const google::protobuf::Descriptor* type = request_type(seed.method);
    if (index < 0 || !type) {
      std::fprintf(stderr, "seed for unknown method %s\n", std::string(seed.method).c_str());
      return 1;
    }
    std::unique_ptr<google::protobuf::Message> request(
        google::protobuf::MessageFactory::generated_factory()->GetPrototype(type)->New());
    if (!google::protobuf::TextFormat::ParseFromString(std::string(seed.text), request.get())) {
      std::fprintf(stderr, "seed %d (%s) does not parse\n", written,
                   std::string(seed.method).c_str());
      return 1;
    }
    std::string bytes(1, char(index));
    bytes += char(seed.flags);
    bytes += request->SerializeAsString();
    const std::string path =
        std::string(argv[1]) + "/" + std::to_string(written) + "-" + std::string(seed.method);
    std::ofstream(path, std::ios::binary) << bytes;
    ++written;
  }
  std::printf("request_seeds: %d seeds in %s\n", written, argv[1]);
  return 0;
}
