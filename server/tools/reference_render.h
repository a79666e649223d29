// The path-traced ground truth as the tools take it: ddgi-render --reference (a view written
// like a frame, with progress), and the pair of references ddgi-eval and ddgi-shadow-eval score
// frames against.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"
#include "gpu_scene/frame_types.h"
#include "gpu_scene/gpu_scene.h"
#include "render/path_tracer.h"
#include "scene/scene.h"
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

// Two references of one view, tone-mapped with one exposure chosen from the full image's linear
// radiance: the full image and a second view (the field's part, or the punctual direct light).
struct ReferencePair {
  PathTraceSettings settings;  // of the full image; pixel centres (frames trace those too)
  float exposure = 1.0f;
  PathTraceImage full;
  PathTraceImage second;
  // With ReferencePairOptions::estimate_mean_noise: the full image's mean luminance's relative
  // noise, from its two halves of full_spp / 2 samples each (|mean A - mean B| / 2 over the
  // mean: one draw of about 0.9 standard deviations of the whole); else 0.
  double mean_noise = 0.0;
};
struct ReferencePairOptions {
  uint32_t width = 480, height = 270;
  Camera camera;
  uint32_t full_spp = 1024;
  PathTraceView second_view = PathTraceView::kFieldIndirect;
  uint32_t second_spp = 1024;  // 0: no second view (ReferencePair::second stays empty)
  float (*exposure)(const std::vector<float>& radiance) = nullptr;  // from the full image
  bool estimate_mean_noise = false;  // ReferencePair::mean_noise (one more readback)
};
Result<ReferencePair> reference_pair(vk::Context& context, const Scene& scene,
                                     const ReferencePairOptions& options);
// The same over a scene already on the GPU.
Result<ReferencePair> reference_pair(vk::Context& context, GpuScene& scene,
                                     const ReferencePairOptions& options);

}  // namespace ddgi
