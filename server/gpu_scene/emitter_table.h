// The emissive triangles of a scene in world space, with the distribution that light sampling
// draws them from (proportional to area x luminance of the emissive factor).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "scene/scene.h"
#include "shared/scene_data.h"

namespace ddgi {

struct EmitterTable {
  std::vector<gpu::GpuEmitter> emitters;
  float total_weight = 0.0f;  // sum of area x luminance
};

// Rec. 709 luminance; the shaders weigh emitters with the same function (emitters.glsl).
float emission_luminance(const glm::vec3& emission);

// `first_geometry[m]`: where mesh m's primitives start in the GPU geometry table (one entry per
// primitive). Thin glass is left out: closest-hit rays never see it, so neither may lights.
EmitterTable build_emitter_table(const Scene& scene, std::span<const uint32_t> first_geometry);

}  // namespace ddgi
