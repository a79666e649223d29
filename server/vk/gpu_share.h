// A thread's share of the GPU: work that runs beside sessions' streams (the background
// calibration, service/calibrator.h) caps the GPU time it takes by sleeping after each of its
// submissions, in proportion to how long the submission took from vkQueueSubmit to its fence.
// One queue serves every thread, so a submission's frames and another thread's interleave at
// submission boundaries; with a share s, the thread's submissions keep the queue at most about
// s of the wall time, and other threads' work waiting behind one of them waits at most that one
// submission. The wait time counts other threads' work queued ahead of it too, so the thread
// yields more, never less, when the GPU is busy. Context::submit and Context::wait apply it.
#pragma once

#include <chrono>

namespace ddgi::vk {

// The longest sleep after one submission: a submission of seconds (a large reference batch)
// still lets the thread go on within this.
inline constexpr std::chrono::milliseconds kMaxShareSleep{1000};

// Sets the calling thread's share for its lifetime; (0, 1], 1: no throttling (the default).
class GpuShareScope {
 public:
  explicit GpuShareScope(double share);
  ~GpuShareScope();
  GpuShareScope(const GpuShareScope&) = delete;
  GpuShareScope& operator=(const GpuShareScope&) = delete;

 private:
  double previous_;
};

// The sleep after a submission that took `busy` under `share`: busy x (1 / share - 1), at most
// kMaxShareSleep.
std::chrono::nanoseconds share_sleep(std::chrono::nanoseconds busy, double share);

namespace gpu_share {
// Called by Context: after a submission, and after its fence (sleeps as the share says).
void submitted();
void waited();
}  // namespace gpu_share

}  // namespace ddgi::vk
