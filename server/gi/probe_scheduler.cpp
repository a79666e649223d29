#include "gi/probe_scheduler.h"

#include <algorithm>

namespace ddgi {

const char* probe_state_name(uint32_t state) {
  switch (state) {
    case gpu::kProbeVigilant:
      return "vigilant";
    case gpu::kProbeAwake:
      return "awake";
    case gpu::kProbeSleeping:
      return "sleeping";
    case gpu::kProbeOff:
      return "off";
  }
  return "unknown";
}

ProbeScheduler::ProbeScheduler(uint32_t probe_count)
    : states_(probe_count, static_cast<uint8_t>(gpu::kProbeVigilant)) {
  rebuild_active();
}

void ProbeScheduler::set_state(uint32_t probe, uint32_t state) {
  if (probe >= states_.size() || states_[probe] == state) return;
  states_[probe] = static_cast<uint8_t>(state);
  rebuild_active();
}

void ProbeScheduler::set_states(const std::vector<uint8_t>& states) {
  if (states.size() != states_.size() || states == states_) return;
  states_ = states;
  rebuild_active();
}

ProbeStateCounts ProbeScheduler::counts() const {
  ProbeStateCounts c;
  for (uint8_t s : states_) {
    if (s == gpu::kProbeVigilant)
      ++c.vigilant;
    else if (s == gpu::kProbeAwake)
      ++c.awake;
    else if (s == gpu::kProbeSleeping)
      ++c.sleeping;
    else
      ++c.off;
  }
  return c;
}

bool ProbeScheduler::take_active_changed() {
  const bool changed = active_changed_;
  active_changed_ = false;
  return changed;
}

ProbeScheduler::Window ProbeScheduler::next_window(uint32_t max_probes) {
  const uint32_t size = static_cast<uint32_t>(active_.size());
  if (size == 0) return {};
  const uint32_t count = max_probes == 0 ? size : std::min(max_probes, size);
  const Window window{cursor_ % size, count};
  cursor_ = (cursor_ + count) % size;
  return window;
}

void ProbeScheduler::rebuild_active() {
  auto is_active = [&](uint32_t p) {
    return states_[p] == gpu::kProbeVigilant || states_[p] == gpu::kProbeAwake;
  };
  std::vector<bool> was_active(states_.size(), false);
  for (uint32_t p : active_) was_active[p] = true;
  std::vector<uint32_t> order;
  // Newly active probes first: the next window starts with them.
  for (uint32_t p = 0; p < states_.size(); ++p) {
    if (is_active(p) && !was_active[p]) order.push_back(p);
  }
  // Then the probes that stay active, from the one whose turn was next.
  const size_t before = active_.size();
  for (size_t i = 0; i < before; ++i) {
    const uint32_t p = active_[(cursor_ + i) % before];
    if (is_active(p)) order.push_back(p);
  }
  active_ = std::move(order);
  cursor_ = 0;
  active_changed_ = true;
}

}  // namespace ddgi
