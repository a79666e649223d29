// When a session submits its next frames (service/submit_pacer.h).
#include "service/submit_pacer.h"

#include <algorithm>
#include <sstream>

namespace ddgi::service {

Status check_submit_ahead_ms(double ahead_ms) {
  if (ahead_ms >= 0.0 && ahead_ms <= kMaxSubmitAheadMs) return ok_status();
  std::ostringstream text;
  text << "--submit-ahead-ms must be in [0, " << kMaxSubmitAheadMs << "] (got " << ahead_ms << ")";
  return invalid_argument(text.str());
}

void SubmitPacer::submitted(uint64_t index, Millis recording) {
  submitted_ = index;
  recording_ = recording;
}

void SubmitPacer::finished(uint64_t index, Clock::time_point done_at, Millis gpu) {
  if (index != finished_) {
    if (finished_ != 0) previous_gpu_ = finished_gpu_;
    finished_ = index;
    finished_gpu_ = Millis(0.0);
  }
  finished_at_ = done_at;
  finished_gpu_ += gpu;
}

SubmitPacer::Clock::time_point SubmitPacer::next_submit() const {
  if (finished_ == 0 || submitted_ <= finished_) return {};
  // The batches after the finished one run back to back from when it was seen done, each about
  // as long as the shorter of the last two: one slow batch (a field rebuilt, a resize) must not
  // leave the GPU idle for as long after the next.
  const Millis each = previous_gpu_ ? std::min(*previous_gpu_, finished_gpu_) : finished_gpu_;
  const Millis queued = each * double(submitted_ - finished_);
  return finished_at_ + std::chrono::duration_cast<Clock::duration>(queued - ahead_ - recording_);
}

}  // namespace ddgi::service
