// The StreamProbes encoding (docs/probe-stream.md), shared by the server that writes it and the
// clients that read it: fp16 conversion, each probe's value layout, and the client side, which
// applies messages to a ProbeField (probe_field.h) that the evaluator then shades from.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "rpc/probe_field.h"

namespace ddgi {

// IEEE binary16, round to nearest even; beyond 65504 clamps to 65504 (NaN becomes 0).
uint16_t float_to_half(float value);
float half_to_float(uint16_t half);

// Floats per probe in ProbeUpdate.values (27 for SH; both tiles for octahedral probes).
uint32_t probe_value_count(const v1::ProbeGrid& grid);
inline constexpr uint32_t kProbeStateValues = 4;  // offset x, y, z and state

// A client's copy of the streamed field.
struct StreamedField {
  ProbeField field;  // empty until the first full message
  uint64_t field_updates = 0;
  uint64_t messages = 0;
  uint64_t bytes = 0;   // serialized message bytes received
  uint32_t stride = 0;  // floats per probe (probe_value_count of the grid)
};

// Applies one message; INVALID_ARGUMENT naming what does not fit (a delta before any full
// message, sizes that disagree with the grid).
Status apply_probe_update(const v1::ProbeUpdate& update, StreamedField* streamed);

}  // namespace ddgi
