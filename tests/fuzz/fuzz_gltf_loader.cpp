// libFuzzer entry point: arbitrary bytes as an uploaded .glb, or as .gltf JSON text when they
// lack the GLB magic. The loader must return an error for bad input, never crash, hang or
// leak; the sanitizers turn any memory or UB fault into a crash report.
#include <cstddef>
#include <cstdint>
#include <span>

#include "scene/glb_container.h"
#include "scene/gltf_loader.h"

namespace {

// Small enough that one input cannot exhaust the fuzzer's memory or time budget, large
// enough to reach every code path.
ddgi::SceneLimits fuzz_limits() {
  ddgi::SceneLimits limits;
  limits.max_file_bytes = 16ull << 20;
  limits.max_texture_dimension = 512;
  limits.max_total_texture_bytes = 16ull << 20;
  limits.max_triangles = 1'000'000;
  limits.max_vertices = 1'000'000;
  limits.max_instances = 100'000;
  limits.max_node_depth = 256;
  return limits;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const ddgi::SceneLimits limits = fuzz_limits();
  const std::span<const uint8_t> bytes(data, size);
  if (ddgi::has_glb_magic(bytes)) {
    (void)ddgi::load_glb_from_memory(bytes, "fuzz.glb", limits);
  } else {
    (void)ddgi::load_gltf_from_memory(bytes, "fuzz.gltf", limits);
  }
  return 0;
}
