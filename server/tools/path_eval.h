// ddgi-eval --path: field configurations walked along a camera path (scene/camera_path.h), as
// a viewer would walk it: one field update and one frame per 1/--path-rate seconds of the
// path, a tracking field following the camera. Every --path-every seconds the frame is scored
// against a path-traced reference of that view; every frame's indirect view is compared with
// the one before, so scroll events can be told from ordinary frames (the 'no pop' check).
#pragma once

#include <string>

#include "core/result.h"
#include "tools/eval_job.h"
#include "vk/context.h"

namespace ddgi::tools {

// Prints the per-view and per-configuration tables; with --out-dir also writes
// DIR/STEM.path.svg (FLIP along the path per configuration) and DIR/STEM.path.csv.
Status run_path(vk::Context& context, const EvalJob& job, const std::string& scene_path);

}  // namespace ddgi::tools
