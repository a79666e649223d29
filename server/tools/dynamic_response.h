// How fast a method recovers after the scene changes (issue 14, "dynamic response"): probe GI
// lags behind a moved light or object by its hysteresis. ddgi-eval --dynamic runs a field
// warmed up on the scene as loaded, applies one change (a light or an object moved), then
// renders frame after frame (one field update each) and measures each frame's error against
// the path-traced reference of the changed scene; the path tracer restarted at the change
// (one sample per pixel per frame, accumulating) is the baseline.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "scene/scene.h"

namespace ddgi::tools {

// "light:INDEX:dx,dy,dz" or "object:INDEX:dx,dy,dz": moves a light or an instance.
struct SceneChange {
  enum class Kind { kLight, kObject } kind = Kind::kLight;
  size_t index = 0;
  glm::vec3 offset{0.0f};
};

// Parses a change and checks it against `scene` (the index exists, the offset is finite).
Result<SceneChange> parse_scene_change(const std::string& text, const Scene& scene);

// "object 6 'box' moved by (0, 0, 0.5); the scene spans (2, 2, 2)", for the output.
std::string describe(const Scene& scene, const SceneChange& change);

// `scene` with the change applied.
Scene changed_scene(const Scene& scene, const SceneChange& change);

// Mean absolute difference of linear RGB over the reference's mean (RGBA inputs): 0 is exact.
double relative_l1(const std::vector<float>& test, const std::vector<float>& reference);

// One method's frames: `change_frame` frames of the scene as loaded (scored against its own
// reference), then the frames after the change.
struct ResponseCurve {
  std::string name;
  std::vector<double> error;  // per frame (relative L1)
  std::vector<double> ms;     // GPU ms per frame (field update + frame, or the path tracer's)
  std::vector<double> rays;   // probe rays the frame's field update traced (fields only)
  int64_t change_frame = 0;   // the first frame after the change
  // Where the method settles: for a field, the median error of the same configuration (on the
  // same grid) warmed up on the changed scene from the start; 0 for the path tracer.
  double steady = 0.0;
  // The first frame after the change (counted from it) from which the mean error of every
  // later window of `window` frames is within `factor` x `target` (windows smooth the field's
  // frame-to-frame noise); -1: never.
  int64_t frames_until_within(double target, double factor = 1.1, size_t window = 10) const;
  // GPU ms summed over the first `frames` frames after the change (the time to get there).
  double ms_until(int64_t frames) const;
};

// The curves as SVGs (error per frame; where fields counted them, probe rays per frame) and a
// CSV (frame counted from the change, then per curve its error and, where counted, its rays).
Status write_response_files(const std::string& dir, const std::string& stem,
                            const std::vector<ResponseCurve>& curves);

}  // namespace ddgi::tools
