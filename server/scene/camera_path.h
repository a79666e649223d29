// Camera paths (`*.path.json`, docs/sidecar-format.md): a walk through a scene as keyframes of
// time, position and look-at target, linear between keyframes. The evaluation tool scores a
// field along one (ddgi-eval --path) and the client streams one through the service
// (ddgi-client stream --camera-path); both read it here, with the sidecar's strict checks.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "scene/scene.h"

namespace ddgi {

struct CameraKeyframe {
  double time = 0.0;  // seconds from the path's start
  glm::vec3 position{0.0f};
  glm::vec3 target{0.0f, 0.0f, -1.0f};
};

// Where the camera is at a time: position and target (target - position never zero, never
// vertical: parsing refuses paths where it would be).
struct CameraPose {
  glm::vec3 position{0.0f};
  glm::vec3 target{0.0f, 0.0f, -1.0f};
};

struct CameraPath {
  std::string scene;  // the scene file it was made for, as written (not checked)
  std::string description;
  std::vector<CameraKeyframe> keyframes;  // at least 2; the first at time 0, times increasing

  double duration() const { return keyframes.back().time; }
  // Position and target at `time` seconds, linear between the keyframes around it; clamped to
  // the first and last keyframe outside [0, duration()].
  CameraPose pose_at(double time) const;
  // The same as a camera (up +Y) with vertical field of view `yfov` (radians).
  Camera camera_at(double time, float yfov) const;
};

// Limits of a path file: far more than any walk needs, small enough to refuse a mistake.
inline constexpr size_t kMaxCameraKeyframes = 100000;
inline constexpr double kMaxCameraPathSeconds = 1e6;

// `file` prefixes error messages; nothing is read from it.
Result<CameraPath> parse_camera_path(std::span<const uint8_t> text,
                                     const std::filesystem::path& file);
Result<CameraPath> read_camera_path(const std::filesystem::path& file);

}  // namespace ddgi
