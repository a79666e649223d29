// Decoding a probe's state from ProbeState::flags (gi/probe_state.h): the state bits alone,
// whatever condition bits sit beside them.
#include <gtest/gtest.h>

#include "gi/probe_state.h"

namespace ddgi {
namespace {

gpu::ProbeState with_flags(uint32_t flags) {
  gpu::ProbeState probe{};
  probe.flags = flags;
  return probe;
}

TEST(ProbeState, DecodesTheStateBits) {
  for (uint32_t state = 0; state < gpu::kProbeStateCount; ++state) {
    const gpu::ProbeState probe = with_flags(state << gpu::kProbeStateShift);
    EXPECT_EQ(static_cast<uint32_t>(probe_state(probe)), state);
  }
  EXPECT_EQ(probe_state(with_flags(gpu::kProbeOff << gpu::kProbeStateShift)), ProbeStateKind::kOff);
}

TEST(ProbeState, IgnoresTheConditionBits) {
  const uint32_t sleeping = gpu::kProbeSleeping << gpu::kProbeStateShift;
  EXPECT_EQ(probe_state(with_flags(sleeping | gpu::kProbeResetHistory)), ProbeStateKind::kSleeping);
  EXPECT_EQ(probe_state(with_flags(gpu::kProbeResetHistory)), ProbeStateKind::kVigilant);
}

}  // namespace
}  // namespace ddgi
