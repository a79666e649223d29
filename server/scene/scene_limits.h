// Bounds on what a scene file may make the loader do. Every input is untrusted (scenes come
// from RPC uploads), so each quantity that costs memory or time has a cap, checked before the
// cost is paid.
#pragma once

#include <cstdint>

#include "core/result.h"

namespace ddgi {

struct SceneLimits {
  // Default 2 GiB, range [1 KiB, 4 GiB - 1]: bounds every file read (.gltf, .glb, .bin,
  // images, .exr); the GLB container stores lengths in 32 bits.
  uint64_t max_file_bytes = 2ull << 30;
  // Default 16384, range [1, 32768]: the largest 2D image Vulkan devices commonly support;
  // checked from the image header before any pixel is decoded.
  uint32_t max_texture_dimension = 16384;
  // Default 4 GiB, range [0, 64 GiB]: decoded RGBA8 texel bytes summed over all textures.
  uint64_t max_total_texture_bytes = 4ull << 30;
  // Default 50 M, range [1, 1 G]: unique triangles over all meshes (CPU and GPU memory, BVH
  // build time).
  uint64_t max_triangles = 50'000'000;
  // Default 100 M, range [1, 1 G]: unique vertices over all meshes, checked per accessor
  // before it is read (an accessor without a buffer view costs no file bytes).
  uint64_t max_vertices = 100'000'000;
  // Default 1 M, range [1, 16 M]: placed meshes (TLAS instances; Vulkan guarantees 2^24).
  uint32_t max_instances = 1'000'000;
  // Default 1 M, range [1, 16 M]: triangle primitives over all meshes (BLAS geometries).
  uint32_t max_primitives = 1'000'000;
  // Default 4096, range [0, 1 M]: punctual lights, the glTF's and the sidecar's together;
  // direct lighting visits every light at every shading point.
  uint32_t max_lights = 4096;
  // Default 1024, range [1, 65536]: depth of the node hierarchy.
  uint32_t max_node_depth = 1024;
  // Default 64, range [8, 1024]: nesting of JSON arrays and objects; the glTF parser recurses
  // into `extras`, so a deeply nested file would overflow the stack.
  uint32_t max_json_depth = 64;
  // Default 16384 x 8192, range [1, 65536] each: the sidecar's equirectangular environment.
  uint32_t max_environment_width = 16384;
  uint32_t max_environment_height = 8192;
};

// Fails when a field is outside its documented range.
Status validate_limits(const SceneLimits& limits);

}  // namespace ddgi
