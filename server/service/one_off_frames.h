// One-off frames: RenderFrame calls without a view id, each a camera and settings of its own
// that are rendered once, at the session's next frame, and then forgotten. They are not views
// (no id, not listed, not counted against --max-views-per-session) and are bounded on their
// own: OneOffSlots lets at most --max-one-off-frames of a session's calls be in flight, and
// OneOffFrames draws them all into a few kept frame targets (one per image size, reused).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "render/frame_target.h"
#include "scene/scene.h"
#include "service/frame_encoder.h"
#include "service/session_view.h"
#include "vk/context.h"

namespace ddgi::service {

// Counts a session's one-off calls from RenderFrame to their reply. Any thread: RPC threads
// take slots, whoever answers a call (the loop, an encoder thread) frees its slot.
class OneOffSlots {
 public:
  OneOffSlots(std::string session_id, uint32_t max_in_flight)
      : session_id_(std::move(session_id)), max_(max_in_flight) {}
  // Takes a slot and wraps `waiter` so that answering it frees the slot first. When every slot
  // is taken: RESOURCE_EXHAUSTED naming the limit, and `waiter` untouched.
  Status take(FrameWaiter& waiter);

 private:
  const std::string session_id_;
  const uint32_t max_;
  // Shared with the wrapped waiters, which may outlive the session (queued encoder jobs).
  std::shared_ptr<std::atomic<uint32_t>> in_flight_ = std::make_shared<std::atomic<uint32_t>>(0);
};

struct OneOffFrame {
  uint64_t number = 0;  // tells their encoder jobs apart
  ViewConfig config;
  Camera camera;
  FrameWaiter waiter;
};

// The one-off frames waiting for the session's next frame, and their targets. Owned and used
// by the session's loop thread only.
class OneOffFrames {
 public:
  // Targets of this many image sizes are kept, the most recently used; a session's one-off
  // frames are drawn one after another, so one target per size is all they need.
  static constexpr size_t kKeptTargets = 2;

  void add(const ViewConfig& config, const Camera& camera, FrameWaiter waiter);
  bool empty() const { return pending_.empty(); }
  // The frames waiting for the next frame, in arrival order; none wait afterwards.
  std::vector<OneOffFrame> take();
  // A target of this size: a kept one, or a new one that replaces the least recently used
  // (freed first, budget and memory, so that neither sees more than kKeptTargets).
  Result<FrameTarget*> target(vk::Context& context, uint32_t width, uint32_t height);
  // Teardown: every waiting call gets `error`, the kept targets are freed.
  void close_all(const Error& error);

 private:
  std::vector<OneOffFrame> pending_;
  uint64_t next_number_ = 1;
  std::vector<std::unique_ptr<FrameTarget>> targets_;  // the most recently used first
};

}  // namespace ddgi::service
