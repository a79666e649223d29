// One-off frames: RenderFrame calls without a view id, each a camera and settings of its own
// that are rendered once, at the session's next frame, and then forgotten. They are not views
// (no id, not listed, not counted against --max-views-per-session). Owned and used by the
// session's loop thread only.
#pragma once

#include <cstdint>
#include <vector>

#include "core/result.h"
#include "scene/scene.h"
#include "service/frame_encoder.h"
#include "service/session_view.h"

namespace ddgi::service {

struct OneOffFrame {
  uint64_t number = 0;  // tells their encoder jobs apart
  ViewConfig config;
  Camera camera;
  FrameWaiter waiter;
};

class OneOffFrames {
 public:
  void add(const ViewConfig& config, const Camera& camera, FrameWaiter waiter);
  bool empty() const { return pending_.empty(); }
  // The frames waiting for the next frame, in arrival order; none wait afterwards.
  std::vector<OneOffFrame> take();
  // Teardown: every waiting call gets `error`.
  void close_all(const Error& error);

 private:
  std::vector<OneOffFrame> pending_;
  uint64_t next_number_ = 1;
};

}  // namespace ddgi::service
