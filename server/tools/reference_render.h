// ddgi-render --reference: the path-traced ground truth of a view, written like a frame.
#pragma once

#include <cstdint>
#include <string>

#include "core/result.h"
#include "gpu_scene/frame_types.h"
#include "gpu_scene/gpu_scene.h"
#include "render/path_tracer.h"
#include "vk/context.h"

namespace ddgi {

struct ReferenceOptions {
  PathTraceSettings settings;
  uint32_t samples = 256;  // per pixel
  std::string out_path;    // .png, .jpg or .exr (linear HDR)
  int jpeg_quality = 90;
  Tonemap tonemap = Tonemap::kAces;
  float exposure = 1.0f;
};

// Accumulates `samples` per pixel in batches of about a second, logging progress every few
// seconds, then writes the image and prints a summary line.
Status render_reference(vk::Context& context, GpuScene& scene, vk::TraceBackend backend,
                        const ReferenceOptions& options);

}  // namespace ddgi
