// The reference path tracer: the ground truth that DDGI images are measured against.
// Progressive: each accumulate() adds samples per pixel to a running mean in an fp32 buffer,
// and starts over when the image settings or the scene change. Seeded: a sample's random
// sequence depends only on (pixel, sample index, seed), so the same seed gives the same image
// on both tracing backends and however the samples are batched. docs/reference-path-tracer.md
// describes the estimator and what each view contains.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "gpu_scene/frame_types.h"
#include "gpu_scene/gpu_scene.h"
#include "render/frame_target.h"
#include "scene/scene.h"
#include "vk/context.h"
#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace ddgi {

// Values match the kPathTrace* constants of shaders/shared/path_trace_data.h.
enum class PathTraceView : uint32_t {
  kFull = 0,
  kDirect = 1,          // emission seen by the camera + light from any source at the first hit
  kIndirect = 2,        // full - direct: light that bounced before reaching the first hit
  kPunctualDirect = 3,  // emission seen + punctual lights only: the raster frame's direct pass
  kFieldIndirect = 4,   // full - punctual direct: what the DDGI frame's indirect view targets
};
// "full", "direct", "indirect", "punctual-direct", "field-indirect".
Result<PathTraceView> parse_path_trace_view(const std::string& text);

// What one accumulated image is. Every field: default, allowed range, reason.
struct PathTraceSettings {
  // Image size in pixels; 1..16384 each.
  uint32_t width = 640;
  uint32_t height = 480;
  Camera camera;
  PathTraceView view = PathTraceView::kFull;
  // Scattering events per path, [0, 1024]; 0 shows emission only, 1 direct light only. Paths
  // are cut by Russian roulette long before a high limit, so the default is nearly unbiased.
  uint32_t max_bounces = 64;
  // Russian roulette from this bounce on, [1, 1024]: early bounces carry most of the light.
  uint32_t roulette_start = 3;
  uint32_t seed = 0;
  // Random positions inside each pixel (antialiasing). Off: rays through pixel centres, as the
  // raster frame's primary rays, for exact comparisons.
  bool jitter = true;
};
Status validate(const PathTraceSettings& settings);

struct PathTraceImage {
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t samples = 0;         // per pixel
  std::vector<float> radiance;  // mean linear HDR radiance, RGBA float per pixel, row 0 = top
  std::vector<uint8_t> ldr;     // tone-mapped sRGB RGBA8 per pixel, row 0 = top
};

class PathTracer {
 public:
  // `backend`: the tracing backend of the kernel (must be supported by the device).
  static Result<std::unique_ptr<PathTracer>> create(vk::Context& context, GpuScene& scene,
                                                    vk::TraceBackend backend);

  // Adds `samples` (1..65536) samples per pixel to the running mean, in one GPU submission.
  // Starts over first when `settings` differ from the previous call's, the scene changed
  // (GpuScene::revision) or reset() was called.
  Status accumulate(const PathTraceSettings& settings, uint32_t samples);
  // Drops the accumulated samples; the next accumulate() starts over.
  void reset() { samples_ = 0; }
  uint32_t samples() const { return samples_; }
  // GPU milliseconds of the last accumulate() (0 when the device has no timestamps): what an
  // image of that many samples costs, for equal-time comparisons (ddgi-eval --pareto).
  double last_accumulate_ms() const { return last_accumulate_ms_; }

  // The mean so far, and its tone-mapped version.
  Result<PathTraceImage> read(Tonemap tonemap = Tonemap::kAces, float exposure = 1.0f);
  vk::TraceBackend backend() const { return backend_; }

 private:
  PathTracer(vk::Context& context, GpuScene& scene) : context_(context), scene_(scene) {}
  Status create_kernels();
  Status resize(uint32_t width, uint32_t height);
  bool same_image(const PathTraceSettings& settings) const;

  vk::Context& context_;
  GpuScene& scene_;
  vk::TraceBackend backend_ = vk::TraceBackend::kRayQuery;
  vk::DescriptorLayout layout_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  vk::Kernel path_trace_;
  vk::Kernel tonemap_;

  ImageBuffers images_;
  vk::GpuTimer timer_;
  double last_accumulate_ms_ = 0.0;

  PathTraceSettings settings_;  // of the accumulated samples
  uint64_t scene_revision_ = 0;
  uint32_t samples_ = 0;
};

}  // namespace ddgi
