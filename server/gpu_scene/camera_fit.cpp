#include "gpu_scene/camera_fit.h"

#include <cmath>

namespace ddgi {

Camera fit_camera(const Bounds& bounds) {
  Camera camera;
  camera.yfov = glm::radians(45.0f);
  if (bounds.empty()) return camera;
  const glm::vec3 center = bounds.center();
  const float radius = std::max(0.5f * glm::length(bounds.extent()), 1e-6f);
  const float distance = radius / std::sin(camera.yfov * 0.5f);
  const glm::vec3 direction = glm::normalize(glm::vec3(0.0f, 0.3f, 1.0f));
  camera.position = center + direction * distance;
  camera.forward = -direction;
  camera.up =
      glm::normalize(glm::cross(glm::cross(camera.forward, glm::vec3(0, 1, 0)), camera.forward));
  camera.znear = radius * 1e-5f;
  return camera;
}

Camera default_camera(const Scene& scene) {
  return scene.cameras.empty() ? fit_camera(scene.world_bounds()) : scene.cameras.front();
}

Result<Camera> camera_from_values(const std::vector<double>& values, const Camera& base) {
  if (values.size() != 6 && values.size() != 7) {
    return invalid_argument("camera needs px,py,pz,tx,ty,tz[,yfov_degrees]");
  }
  Camera camera = base;
  camera.position = glm::vec3(values[0], values[1], values[2]);
  const glm::vec3 target(values[3], values[4], values[5]);
  const glm::vec3 forward = target - camera.position;
  if (glm::length(forward) <= 0.0f) return invalid_argument("camera position equals its target");
  camera.forward = glm::normalize(forward);
  const glm::vec3 right = glm::cross(camera.forward, glm::vec3(0, 1, 0));
  if (glm::length(right) < 1e-6f) {
    return invalid_argument("camera looks straight up or down; +Y cannot be its up vector");
  }
  camera.up = glm::normalize(glm::cross(right, camera.forward));
  if (values.size() == 7) {
    if (!(values[6] > 0.0 && values[6] <= kMaxCameraYfovDegrees)) {
      return invalid_argument("camera yfov must be in (0, " +
                              std::to_string(int(kMaxCameraYfovDegrees)) + "] degrees");
    }
    camera.yfov = camera_yfov_radians(static_cast<float>(values[6]));
  }
  return camera;
}

}  // namespace ddgi
