// The light each kind of source puts into a scene (gi/light_power.h).
#include "gi/light_power.h"

#include <cmath>
#include <vector>

#include "gpu_scene/emitter_table.h"

namespace ddgi {
namespace {

constexpr double kPi = 3.14159265358979323846;

// The area of `bounds` seen along `direction` (unit): each face pair's area times how squarely
// the light meets it.
double facing_area(const Bounds& bounds, glm::vec3 direction) {
  const glm::dvec3 e = glm::dvec3(bounds.extent());
  return std::abs(direction.x) * e.y * e.z + std::abs(direction.y) * e.x * e.z +
         std::abs(direction.z) * e.x * e.y;
}

}  // namespace

LightPower light_power(const Scene& scene) {
  LightPower power;
  // The emitter table weighs each emissive triangle by area x luminance, as sampling draws them;
  // its geometry indices are not needed here.
  const std::vector<uint32_t> first_geometry(scene.meshes.size(), 0u);
  power.emitters = kPi * double(build_emitter_table(scene, first_geometry).total_weight);
  const Bounds bounds = scene.world_bounds();
  for (const Light& light : scene.lights) {
    const double intensity = double(light.intensity) * emission_luminance(light.color);
    if (!(intensity > 0.0) || !std::isfinite(intensity)) continue;
    switch (light.type) {
      case LightType::kPoint:
        power.punctual += 4.0 * kPi * intensity;
        break;
      case LightType::kSpot:
        power.punctual += 2.0 * kPi * (1.0 - std::cos(double(light.outer_cone_angle))) * intensity;
        break;
      case LightType::kDirectional: {
        const float length = glm::length(light.direction);
        if (length > 0.0f && !bounds.empty()) {
          power.directional += intensity * facing_area(bounds, light.direction / length);
        }
        break;
      }
    }
  }
  return power;
}

bool emitters_worth_sampling(const Scene& scene) {
  const LightPower power = light_power(scene);
  return power.emitters > 0.0 && power.emitters >= kEmitterShareToSample * power.total();
}

}  // namespace ddgi
