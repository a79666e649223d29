#include "tests/gpu/two_rooms.h"

namespace ddgi::test {

IrradianceFieldParams two_room_grid() {
  IrradianceFieldParams p;
  p.origin = {-3.85f, 0.25f, -1.75f};
  p.spacing = {0.5f, 0.5f, 0.5f};
  p.counts = {16, 6, 8};
  p.rays_per_probe = 128;
  p.hysteresis = 0.8f;
  p.fixed_rays = 0;
  p.relocation_iterations = 0;
  p.classification = false;
  return p;
}

std::vector<IrradianceQuery> room_points(float side) {
  std::vector<IrradianceQuery> q;
  const glm::vec3 wall_normal(side, 0.0f, 0.0f);
  for (float y : {0.3f, 1.0f, 2.5f}) {
    for (float z : {-1.5f, -0.9f, 0.9f, 1.5f}) {  // beside the (closed) door, not on it
      q.push_back({{side * 0.0101f, y, z}, wall_normal, wall_normal});
    }
  }
  for (float x : {0.2f, 0.6f, 1.5f, 3.0f}) {
    for (float z : {-1.2f, 0.0f, 1.2f}) {
      q.push_back({{side * x, 0.0001f, z}, {0, 1, 0}, {0, 1, 0}});
      q.push_back({{side * x, 2.9999f, z}, {0, -1, 0}, {0, -1, 0}});
    }
  }
  return q;
}

float mean_luminance(const std::vector<glm::vec3>& values) {
  double sum = 0.0;
  for (const glm::vec3& v : values) sum += 0.2126 * v.x + 0.7152 * v.y + 0.0722 * v.z;
  return values.empty() ? 0.0f : static_cast<float>(sum / values.size());
}

}  // namespace ddgi::test
