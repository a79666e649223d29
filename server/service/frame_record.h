// What one rendered frame tells its client besides the image: the fields of the wire Frame,
// gathered by the session's frame loop and turned into a v1::Frame by convert.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "service/session_loop.h"
#include "vk/pass.h"

namespace ddgi::service {

struct FrameRecord {
  std::string session_id;
  std::string view_id;  // empty for a one-off frame
  uint64_t index = 0;   // the session's frame counter
  uint32_t width = 0;
  uint32_t height = 0;
  Camera camera;
  // The field updates of this loop iteration (recorded with its first view, reported by every
  // frame of it), then this view's own passes.
  std::vector<vk::PassTime> gi_passes;
  std::vector<vk::PassTime> view_passes;
  double gi_ms = 0.0;
  CommandStamp last_applied;
  int64_t rendered_unix_us = 0;
  uint64_t field_updates = 0;  // updates of the irradiance field (else the shadow field) so far
};

}  // namespace ddgi::service
