#include "gpu_scene/emitter_table.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_inverse.hpp>

namespace ddgi {
namespace {

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

float emission_luminance(const glm::vec3& emission) {
  const glm::vec3 e = glm::max(emission, glm::vec3(0.0f));
  return 0.2126f * e.r + 0.7152f * e.g + 0.0722f * e.b;
}

EmitterTable build_emitter_table(const Scene& scene, std::span<const uint32_t> first_geometry) {
  EmitterTable table;
  std::vector<double> weights;
  for (size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& inst = scene.instances[i];
    if (inst.mesh < 0 || size_t(inst.mesh) >= first_geometry.size()) continue;
    const glm::mat3 normal_matrix = glm::inverseTranspose(glm::mat3(inst.transform));
    const std::vector<Primitive>& primitives = scene.meshes[inst.mesh].primitives;
    for (size_t p = 0; p < primitives.size(); ++p) {
      const Primitive& prim = primitives[p];
      if (prim.material < 0) continue;  // the default material does not emit
      const Material& material = scene.materials[prim.material];
      const float luminance = emission_luminance(material.emissive);
      if (!(luminance > 0.0f) || !std::isfinite(luminance) || material.transmission > 0.0f) {
        continue;
      }
      for (size_t t = 0; t + 2 < prim.indices.size(); t += 3) {
        const uint32_t a = prim.indices[t], b = prim.indices[t + 1], c = prim.indices[t + 2];
        if (std::max({a, b, c}) >= prim.positions.size()) continue;
        const glm::vec3 object_normal = glm::cross(prim.positions[b] - prim.positions[a],
                                                   prim.positions[c] - prim.positions[a]);
        gpu::GpuEmitter e{};
        e.p0 = glm::vec3(inst.transform * glm::vec4(prim.positions[a], 1.0f));
        e.p1 = glm::vec3(inst.transform * glm::vec4(prim.positions[b], 1.0f));
        e.p2 = glm::vec3(inst.transform * glm::vec4(prim.positions[c], 1.0f));
        e.area = 0.5f * glm::length(glm::cross(e.p1 - e.p0, e.p2 - e.p0));
        const glm::vec3 normal = normal_matrix * object_normal;
        const float normal_length = glm::length(normal);
        if (!(e.area > 0.0f) || !std::isfinite(e.area) || !(normal_length > 0.0f) ||
            !finite(e.p0) || !finite(e.p1) || !finite(e.p2) || !finite(normal / normal_length)) {
          continue;  // degenerate: it can neither be hit nor sampled
        }
        e.normal = normal / normal_length;
        e.instance = static_cast<uint32_t>(i);
        e.geometry = first_geometry[inst.mesh] + static_cast<uint32_t>(p);
        e.primitive = static_cast<uint32_t>(t / 3);
        e.emission = material.emissive;
        table.emitters.push_back(e);
        weights.push_back(double(e.area) * luminance);
      }
    }
  }
  double total = 0.0;
  for (double w : weights) total += w;
  if (!(total > 0.0) || !std::isfinite(total)) return EmitterTable{};
  double running = 0.0;
  for (size_t i = 0; i < weights.size(); ++i) {
    running += weights[i];
    table.emitters[i].cdf = static_cast<float>(running / total);
  }
  table.emitters.back().cdf = 1.0f;
  table.total_weight = static_cast<float>(total);
  return table;
}

}  // namespace ddgi
