// A thread's share of the GPU (vk/gpu_share.h).
#include "vk/gpu_share.h"

#include <algorithm>
#include <thread>

namespace ddgi::vk {
namespace {

using Clock = std::chrono::steady_clock;

thread_local double t_share = 1.0;
thread_local Clock::time_point t_submitted{};

}  // namespace

GpuShareScope::GpuShareScope(double share) : previous_(t_share) {
  t_share = std::clamp(share, 1e-3, 1.0);
}

GpuShareScope::~GpuShareScope() {
  t_share = previous_;
}

std::chrono::nanoseconds share_sleep(std::chrono::nanoseconds busy, double share) {
  if (share >= 1.0 || busy.count() <= 0) return std::chrono::nanoseconds(0);
  const double factor = 1.0 / std::max(share, 1e-3) - 1.0;
  const auto sleep = std::chrono::nanoseconds(static_cast<int64_t>(double(busy.count()) * factor));
  return std::min<std::chrono::nanoseconds>(sleep, kMaxShareSleep);
}

namespace gpu_share {

void submitted() {
  if (t_share < 1.0) t_submitted = Clock::now();
}

void waited() {
  if (t_share >= 1.0 || t_submitted == Clock::time_point{}) return;
  const auto busy = Clock::now() - t_submitted;
  t_submitted = Clock::time_point{};
  std::this_thread::sleep_for(share_sleep(busy, t_share));
}

}  // namespace gpu_share
}  // namespace ddgi::vk
