// One-off frames: their limit, the frames waiting, their kept targets
// (service/one_off_frames.h).
#include "service/one_off_frames.h"

#include <algorithm>

namespace ddgi::service {

Status OneOffSlots::take(FrameWaiter& waiter) {
  uint32_t current = in_flight_->load();
  do {
    if (current >= max_) {
      return resource_exhausted(
          "session " + session_id_ + " already has " + std::to_string(current) +
          " one-off frames in flight, the most allowed (--max-one-off-frames " +
          std::to_string(max_) +
          "); wait for a reply, or render through a view (CreateView, then RenderFrame with its "
          "view_id)");
    }
  } while (!in_flight_->compare_exchange_weak(current, current + 1));
  waiter = [in_flight = in_flight_,
            inner = std::move(waiter)](Result<std::shared_ptr<const v1::Frame>> frame) {
    in_flight->fetch_sub(1);  // before the reply: a client that sends its next call at once
    inner(std::move(frame));  // finds the slot free
  };
  return ok_status();
}

void OneOffFrames::add(const ViewConfig& config, const Camera& camera, FrameWaiter waiter) {
  pending_.push_back({next_number_++, config, camera, std::move(waiter)});
}

std::vector<OneOffFrame> OneOffFrames::take() {
  std::vector<OneOffFrame> frames;
  frames.swap(pending_);
  return frames;
}

Result<FrameTarget*> OneOffFrames::target(vk::Context& context, uint32_t width, uint32_t height) {
  auto kept = std::find_if(targets_.begin(), targets_.end(), [&](const auto& target) {
    return target->width() == width && target->height() == height;
  });
  if (kept != targets_.end()) {
    std::rotate(targets_.begin(), kept, kept + 1);
    return targets_.front().get();
  }
  if (targets_.size() >= kKeptTargets) {
    targets_.pop_back();
    // Its frames were waited for: free its memory now, not at the end of the loop iteration,
    // so that an iteration of many sizes holds no more than kKeptTargets of them.
    context.collect_garbage();
  }
  DDGI_ASSIGN_OR_RETURN(std::unique_ptr<FrameTarget> made,
                        FrameTarget::create(context, width, height));
  targets_.insert(targets_.begin(), std::move(made));
  return targets_.front().get();
}

void OneOffFrames::close_all(const Error& error) {
  for (OneOffFrame& frame : take()) frame.waiter(error);
  targets_.clear();
}

}  // namespace ddgi::service
