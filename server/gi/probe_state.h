// A probe's state as C++ sees it: ProbeState::flags keeps the state in bits 8..15 beside the
// condition bits (shaders/shared/field_data.h); probe_state() decodes it, so code outside the
// field (dumps, tests) never shifts or masks the flags itself.
#pragma once

#include <cstdint>
#include <vector>

#include "shared/field_data.h"

namespace ddgi {

// docs/probe-management.md. The values are the GLSL constants themselves.
enum class ProbeStateKind : uint32_t {
  kVigilant = gpu::kProbeVigilant,  // shades static geometry: traced every update
  kAwake = gpu::kProbeAwake,        // woken by a moving object nearby: traced while it is near
  kSleeping = gpu::kProbeSleeping,  // no surface within reach: not traced
  kOff = gpu::kProbeOff,            // inside geometry: never traced, never sampled
};
static_assert(gpu::kProbeStateCount == 4, "ProbeStateKind names every kProbe* state");

inline ProbeStateKind probe_state(const gpu::ProbeState& probe) {
  return static_cast<ProbeStateKind>((probe.flags & gpu::kProbeStateMask) >> gpu::kProbeStateShift);
}

// Per probe, 4 floats: relocation offset x, y, z and the state (ProbeStateKind), as the dumps
// and the probe stream send them.
inline std::vector<float> probe_state_values(const std::vector<gpu::ProbeState>& probes) {
  std::vector<float> values;
  values.reserve(probes.size() * 4);
  for (const gpu::ProbeState& probe : probes) {
    values.insert(values.end(), {probe.offset.x, probe.offset.y, probe.offset.z,
                                 float(static_cast<uint32_t>(probe_state(probe)))});
  }
  return values;
}

}  // namespace ddgi
