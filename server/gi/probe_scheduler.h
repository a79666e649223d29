// Which probes an irradiance-field update traces. Pure CPU bookkeeping: the probes' states
// (shaders/shared/field_data.h kProbe*), the list of active (traced) probes, and the window of
// that list each update takes when a ray budget caps how many probes one update may trace.
//
// Fairness: windows advance round-robin through the active list, so with A active probes and
// at most K per update, every active probe is traced at least once every ceil(A / K) updates.
// Probes that become active (woken by a moving object, or switched on) go to the front of the
// queue: they have no history, so their first update comes before any other probe's turn; the
// others keep their round-robin order, delayed by at most ceil(woken / K) updates.
#pragma once

#include <cstdint>
#include <vector>

#include "shared/field_data.h"

namespace ddgi {

struct ProbeStateCounts {
  uint64_t vigilant = 0;
  uint64_t awake = 0;
  uint64_t sleeping = 0;
  uint64_t off = 0;
  uint64_t active() const { return vigilant + awake; }
  uint64_t total() const { return vigilant + awake + sleeping + off; }
};

const char* probe_state_name(uint32_t state);

class ProbeScheduler {
 public:
  // Every probe starts Vigilant: without classification every probe is traced.
  explicit ProbeScheduler(uint32_t probe_count = 0);

  uint32_t probe_count() const { return static_cast<uint32_t>(states_.size()); }
  const std::vector<uint8_t>& states() const { return states_; }
  uint32_t state(uint32_t probe) const { return states_[probe]; }
  void set_state(uint32_t probe, uint32_t state);
  // Replaces every state at once (after a classification); sizes must match.
  void set_states(const std::vector<uint8_t>& states);
  ProbeStateCounts counts() const;

  // Traced probes (Vigilant and Awake), in the order updates take them: ascending at first,
  // later with newly active probes first.
  const std::vector<uint32_t>& active() const { return active_; }
  // True once after the active list changed (so it can be uploaded again).
  bool take_active_changed();
  // Whether it changed since the last take_active_changed(), without taking it.
  bool active_changed() const { return active_changed_; }

  struct Window {
    uint32_t start = 0;  // index into active()
    uint32_t count = 0;  // probes; the window wraps around the end of active()
  };
  // The next update's probes: at most `max_probes` (0: all), continuing where the last
  // window ended.
  Window next_window(uint32_t max_probes);

 private:
  void rebuild_active();

  std::vector<uint8_t> states_;
  std::vector<uint32_t> active_;
  uint32_t cursor_ = 0;
  bool active_changed_ = true;
};

}  // namespace ddgi
