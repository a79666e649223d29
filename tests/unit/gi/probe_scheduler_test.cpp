// The probe scheduler's budget windows: round-robin fairness and the active list.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "gi/probe_scheduler.h"

namespace ddgi {
namespace {

TEST(ProbeScheduler, EveryProbeStartsVigilantAndActive) {
  ProbeScheduler s(5);
  EXPECT_EQ(s.counts().vigilant, 5u);
  EXPECT_EQ(s.active().size(), 5u);
  const ProbeScheduler::Window w = s.next_window(0);
  EXPECT_EQ(w.start, 0u);
  EXPECT_EQ(w.count, 5u);
}

TEST(ProbeScheduler, OnlyVigilantAndAwakeProbesAreActive) {
  ProbeScheduler s(6);
  s.set_states({gpu::kProbeVigilant, gpu::kProbeOff, gpu::kProbeAwake, gpu::kProbeSleeping,
                gpu::kProbeSleeping, gpu::kProbeVigilant});
  EXPECT_EQ(s.active(), (std::vector<uint32_t>{0, 2, 5}));
  const ProbeStateCounts c = s.counts();
  EXPECT_EQ(c.vigilant, 2u);
  EXPECT_EQ(c.awake, 1u);
  EXPECT_EQ(c.sleeping, 2u);
  EXPECT_EQ(c.off, 1u);
  EXPECT_TRUE(s.take_active_changed());
  EXPECT_FALSE(s.take_active_changed());
}

// With A active probes and K per update, every probe appears in every run of ceil(A / K)
// consecutive windows, and no window exceeds K.
TEST(ProbeScheduler, WindowsAreFairUnderABudget) {
  for (uint32_t active : {1u, 7u, 10u, 64u}) {
    for (uint32_t k : {1u, 3u, 10u, 100u}) {
      ProbeScheduler s(active);
      const uint32_t bound = (active + k - 1) / k;
      for (int round = 0; round < 5; ++round) {
        std::map<uint32_t, int> seen;
        for (uint32_t u = 0; u < bound; ++u) {
          const ProbeScheduler::Window w = s.next_window(k);
          EXPECT_LE(w.count, k);
          for (uint32_t i = 0; i < w.count; ++i) ++seen[s.active()[(w.start + i) % active]];
        }
        EXPECT_EQ(seen.size(), active) << active << " probes, " << k << " per update";
      }
    }
  }
}

TEST(ProbeScheduler, NoActiveProbesGivesEmptyWindows) {
  ProbeScheduler s(3);
  s.set_states({gpu::kProbeSleeping, gpu::kProbeOff, gpu::kProbeSleeping});
  EXPECT_EQ(s.next_window(2).count, 0u);
}

// A probe that wakes goes first: the next window starts with it, and the probes that were
// already active keep their round-robin order from where it stopped.
TEST(ProbeScheduler, WokenProbesAreTracedFirstAndTheOthersKeepTheirTurn) {
  ProbeScheduler s(8);
  s.set_states({gpu::kProbeVigilant, gpu::kProbeVigilant, gpu::kProbeVigilant, gpu::kProbeVigilant,
                gpu::kProbeVigilant, gpu::kProbeVigilant, gpu::kProbeSleeping,
                gpu::kProbeSleeping});
  ASSERT_EQ(s.active(), (std::vector<uint32_t>{0, 1, 2, 3, 4, 5}));
  const ProbeScheduler::Window first = s.next_window(4);  // probes 0..3
  EXPECT_EQ(first.start, 0u);
  s.set_state(7, gpu::kProbeAwake);
  EXPECT_EQ(s.active(), (std::vector<uint32_t>{7, 4, 5, 0, 1, 2, 3}));
  const ProbeScheduler::Window next = s.next_window(4);
  EXPECT_EQ(next.start, 0u);
  EXPECT_EQ(next.count, 4u);  // 7, then 4 and 5 whose turn it was, then 0
  // Every probe still comes within ceil(7 / 4) windows.
  std::set<uint32_t> seen;
  for (uint32_t i = 0; i < next.count; ++i) seen.insert(s.active()[(next.start + i) % 7]);
  const ProbeScheduler::Window after = s.next_window(4);
  for (uint32_t i = 0; i < after.count; ++i) seen.insert(s.active()[(after.start + i) % 7]);
  EXPECT_EQ(seen.size(), 7u);
}

}  // namespace
}  // namespace ddgi
