// One-off frames waiting for the session's next frame (service/one_off_frames.h).
#include "service/one_off_frames.h"

namespace ddgi::service {

void OneOffFrames::add(const ViewConfig& config, const Camera& camera, FrameWaiter waiter) {
  pending_.push_back({next_number_++, config, camera, std::move(waiter)});
}

std::vector<OneOffFrame> OneOffFrames::take() {
  std::vector<OneOffFrame> frames;
  frames.swap(pending_);
  return frames;
}

void OneOffFrames::close_all(const Error& error) {
  for (OneOffFrame& frame : take()) frame.waiter(error);
}

}  // namespace ddgi::service
