// Camera paths: parsing with the sidecar's strict field checks, and the pose at a time.
#include "scene/camera_path.h"

#include <algorithm>
#include <cmath>

#include "scene/json_fields.h"
#include "scene/json_precheck.h"
#include "scene/scene_files.h"

namespace ddgi {
namespace {

using namespace json_fields;

// A path file is a list of keyframes, a few MiB at the most keyframes allowed.
constexpr uint64_t kMaxPathFileBytes = 32ull << 20;
constexpr uint32_t kMaxPathJsonDepth = 8;

// The smallest length of (1 - s) a + s b over s in [0, 1]: the distance from the origin to the
// segment from a to b (between two keyframes the view vector moves along such a segment).
float min_length_between(glm::vec3 a, glm::vec3 b) {
  const glm::vec3 d = b - a;
  const float dd = glm::dot(d, d);
  const float s = dd > 0.0f ? std::clamp(-glm::dot(a, d) / dd, 0.0f, 1.0f) : 0.0f;
  return glm::length(a + s * d);
}

// Between keyframes k and k+1 the view (target - position) moves linearly: it must neither
// vanish (the camera would look at itself) nor turn vertical (no up direction).
Status check_segment(const CameraKeyframe& a, const CameraKeyframe& b, size_t k) {
  const glm::vec3 va = a.target - a.position, vb = b.target - b.position;
  const float longest = std::max(glm::length(va), glm::length(vb));
  const float horizontal =
      min_length_between(glm::vec3(va.x, 0.0f, va.z), glm::vec3(vb.x, 0.0f, vb.z));
  if (!(horizontal > 1e-3f * longest)) {
    return invalid_argument("keyframes[" + std::to_string(k) + "] to [" + std::to_string(k + 1) +
                            "]: the camera would look straight up or down, or at its own "
                            "position (target - position must keep a horizontal part)");
  }
  return ok_status();
}

Result<CameraKeyframe> read_keyframe(const json& value, const std::string& path) {
  DDGI_TRY(check_object(value, path, {"time", "position", "target"}));
  for (const char* key : {"time", "position", "target"}) {
    if (!value.contains(key)) return invalid_argument(join(path, key) + ": missing");
  }
  CameraKeyframe keyframe;
  DDGI_ASSIGN_OR_RETURN(keyframe.time, read_number(value["time"], join(path, "time"),
                                                   Range{0.0, kMaxCameraPathSeconds}));
  DDGI_ASSIGN_OR_RETURN(keyframe.position,
                        read_vector<3>(value["position"], join(path, "position"), kAny));
  DDGI_ASSIGN_OR_RETURN(keyframe.target,
                        read_vector<3>(value["target"], join(path, "target"), kAny));
  return keyframe;
}

Result<std::vector<CameraKeyframe>> read_keyframes(const json& list) {
  if (!list.is_array() || list.size() < 2 || list.size() > kMaxCameraKeyframes) {
    return expected("keyframes",
                    "an array of 2 to " + std::to_string(kMaxCameraKeyframes) + " keyframes", list);
  }
  std::vector<CameraKeyframe> keyframes;
  for (size_t k = 0; k < list.size(); ++k) {
    const std::string path = "keyframes[" + std::to_string(k) + "]";
    DDGI_ASSIGN_OR_RETURN(const CameraKeyframe keyframe, read_keyframe(list[k], path));
    if (k == 0 && keyframe.time != 0.0) {
      return invalid_argument(path + ".time: the first keyframe must be at time 0");
    }
    if (k > 0 && !(keyframe.time > keyframes.back().time)) {
      return invalid_argument(path + ".time: must be later than the keyframe before it (" +
                              std::to_string(keyframes.back().time) + " s)");
    }
    keyframes.push_back(keyframe);
    if (k > 0) DDGI_TRY(check_segment(keyframes[k - 1], keyframes[k], k - 1));
  }
  return keyframes;
}

Result<CameraPath> parse_document(const json& root) {
  DDGI_TRY(check_object(root, "", {"scene", "description", "keyframes"}));
  if (!root.contains("keyframes")) return invalid_argument("keyframes: missing");
  CameraPath path;
  if (root.contains("scene")) {
    DDGI_ASSIGN_OR_RETURN(path.scene, read_string(root["scene"], "scene"));
  }
  if (root.contains("description")) {
    DDGI_ASSIGN_OR_RETURN(path.description, read_string(root["description"], "description"));
  }
  DDGI_ASSIGN_OR_RETURN(path.keyframes, read_keyframes(root["keyframes"]));
  return path;
}

}  // namespace

CameraPose CameraPath::pose_at(double time) const {
  const double t = std::clamp(time, 0.0, duration());
  // The first keyframe later than t; t lies between the one before it and it.
  const auto later =
      std::upper_bound(keyframes.begin(), keyframes.end(), t,
                       [](double value, const CameraKeyframe& k) { return value < k.time; });
  if (later == keyframes.end()) return {keyframes.back().position, keyframes.back().target};
  const CameraKeyframe& b = *later;
  const CameraKeyframe& a = *(later - 1);
  const float s = static_cast<float>((t - a.time) / (b.time - a.time));
  return {glm::mix(a.position, b.position, s), glm::mix(a.target, b.target, s)};
}

Camera CameraPath::camera_at(double time, float yfov) const {
  const CameraPose pose = pose_at(time);
  // Parsing refused views that vanish or turn vertical, so this cannot fail.
  return look_at_camera(pose.position, pose.target, glm::vec3(0.0f, 1.0f, 0.0f), yfov).value();
}

Result<CameraPath> parse_camera_path(std::span<const uint8_t> text,
                                     const std::filesystem::path& file) {
  const std::string context = file.string();
  Status nesting = precheck_json(text, kMaxPathJsonDepth);
  if (!nesting.ok()) return nesting.error().with_context(context);
  Result<json> root = parse_json_strict(text);
  if (!root.ok()) return root.error().with_context(context);
  Result<CameraPath> path = parse_document(*root);
  if (!path.ok()) return path.error().with_context(context);
  return path;
}

Result<CameraPath> read_camera_path(const std::filesystem::path& file) {
  DDGI_ASSIGN_OR_RETURN(const std::vector<uint8_t> text, read_file(file, kMaxPathFileBytes));
  return parse_camera_path(text, file);
}

}  // namespace ddgi
