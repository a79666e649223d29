// Renders frames of one GPU scene: primary rays into a G-buffer, direct light, indirect light
// from the irradiance field, tone mapping, readback. Owns the kernels of these passes, built
// once per scene; frames are drawn into FrameTargets (two per view in the service). It never
// decides when fields update: the caller hands it the update passes (GiStack::frame_update) to
// record first, in the same submission. A frame is submitted without waiting (submit(), into
// the target's own command buffer) and finished later (PendingFrame::finish: wait, read back),
// so a caller can record the next frame while the GPU runs this one; render() does both.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/result.h"
#include "gi/irradiance_field.h"
#include "gi/shadow_field.h"
#include "gi/world_cache.h"
#include "gpu_scene/frame_types.h"
#include "gpu_scene/gpu_scene.h"
#include "render/frame_target.h"
#include "scene/scene.h"
#include "vk/context.h"
#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace ddgi {

// What one frame looks like. Every field: default, allowed range, reason.
struct FrameSettings {
  // Image size in pixels; 1..16384 each. Small defaults keep CPU (lavapipe) runs quick.
  uint32_t width = 640;
  uint32_t height = 480;
  Camera camera;
  // Shadow rays by default: the reference every cheaper mode is measured against.
  DirectMode direct_mode = DirectMode::kTracedShadows;
  View view = View::kFull;
  // ACES keeps highlights from clipping hard; clamp is for exact numeric comparisons.
  Tonemap tonemap = Tonemap::kAces;
  // Linear multiplier before tone mapping; (0, 1e9]. 1: radiance 1 maps to about mid-white.
  float exposure = 1.0f;
  // Copy the linear HDR image back (FrameResult::radiance). A stream that only encodes the
  // 8-bit image turns this off: at 1920x1080 the HDR copy is 33 MB per frame.
  bool read_radiance = true;
  // Hand on the 8-bit image as JPEG's YCbCr 4:2:0 planes (FrameResult::yuv420), converted on
  // the GPU, instead of RGBA8: 1.5 bytes per pixel to read back instead of 4, and the JPEG
  // encoder skips its colour conversion. Streams turn this on; images saved as PNG need RGBA8.
  bool read_yuv420 = false;
  // Shadow rays per spherical light (radius > 0) and pixel in the shadow-rays mode, [1, 64].
  // 1: the real-time default, noisy penumbrae; more give smooth soft shadows.
  uint32_t light_samples = 1;
  // AO rays per pixel in the ao-traced direct mode, [1, 4096]. 1: what a real-time frame can
  // afford (the cache's input); many: the converged AO the cache is measured against.
  uint32_t ao_samples = 1;
};
Status validate(const FrameSettings& settings);

struct FrameResult {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<float> radiance;        // linear HDR, RGBA float per pixel, row 0 = top (if read)
  std::vector<uint8_t> ldr;           // tone-mapped sRGB RGBA8 per pixel, row 0 = top (unless YUV)
  std::vector<uint8_t> yuv420;        // the same image as YUV 4:2:0 planes (if read_yuv420)
  gpu::Yuv420Layout yuv420_layout{};  // where the planes lie in `yuv420`
  std::vector<vk::PassTime> pass_times;
  uint64_t frame_index = 0;
};

// A frame submitted into its target and not yet read back (Renderer::submit). finish() waits
// for the GPU and reads the frame back; one dropped unfinished is still waited for, so its
// target is never re-recorded, reused or freed while the GPU draws into it. The target must
// outlive it.
class PendingFrame {
 public:
  PendingFrame() = default;
  PendingFrame(PendingFrame&& other) noexcept { *this = std::move(other); }
  PendingFrame& operator=(PendingFrame&& other) noexcept;
  PendingFrame(const PendingFrame&) = delete;
  PendingFrame& operator=(const PendingFrame&) = delete;
  ~PendingFrame() { release(); }

  // Waits for the GPU to finish the frame (no readback); idempotent.
  Status wait();
  // Waits, then reads back the 8-bit image, the HDR one when the settings asked for it, and
  // the pass times. Once: the frame is done afterwards (and the target free).
  Result<FrameResult> finish();
  // Submitted and not finished yet.
  bool active() const { return target_ != nullptr; }

 private:
  friend class Renderer;
  void release();  // waits if still active, then frees the target

  vk::Context* context_ = nullptr;
  FrameTarget* target_ = nullptr;
  uint32_t width_ = 0;
  uint32_t height_ = 0;
  bool read_radiance_ = false;
  bool read_yuv420_ = false;
  uint64_t frame_index_ = 0;
};

class Renderer {
 public:
  // `backend`: the tracing backend of every kernel (must be supported by the device).
  // `field`: the irradiance field that gives indirect light; nullptr renders direct light only.
  // `shadow_field`: what the shadow-field and AO direct modes sample; nullptr refuses them.
  static Result<std::unique_ptr<Renderer>> create(vk::Context& context, GpuScene& scene,
                                                  IrradianceField* field, vk::TraceBackend backend,
                                                  ShadowField* shadow_field = nullptr);

  // Records one frame into `target` (made for the settings' size, not busy with another frame)
  // after `before` (field updates), in one submission into the target's command buffer, and
  // returns without waiting. Frames submitted one after another run in that order on the GPU
  // (one queue, a full barrier after every pass), so a frame's field update follows the last.
  Result<PendingFrame> submit(const FrameSettings& settings, FrameTarget& target,
                              std::span<const vk::Pass> before = {});
  // submit() and PendingFrame::finish(): the frame, waited for.
  Result<FrameResult> render(const FrameSettings& settings, FrameTarget& target,
                             std::span<const vk::Pass> before = {});
  // The same into the renderer's own target, resized to the settings' size as needed.
  Result<FrameResult> render(const FrameSettings& settings, std::span<const vk::Pass> before = {});
  // The passes of one frame into `target`, in order, each with its declared inputs and outputs
  // (submit() first builds the kernels the field's parameters ask for).
  std::vector<vk::Pass> frame_passes(const FrameSettings& settings,
                                     const FrameTarget& target) const;
  // ddgi-bench's baseline for primary visibility: the frame's camera rays traced by a kernel
  // that only records hit distances (into the G-buffer, which the frame's primary pass writes).
  // Its kernel is built on the first call: only the benchmark asks.
  Result<std::vector<vk::Pass>> raw_primary_passes(const FrameSettings& settings,
                                                   const FrameTarget& target);
  vk::TraceBackend backend() const { return backend_; }

  // The world cache's parameters (the ao-cache direct mode). The cache is made on the first frame
  // that reads it; new parameters replace it, empty.
  Status set_world_cache_params(const WorldCacheParams& params);
  const WorldCacheParams& world_cache_params() const { return world_cache_params_; }
  // The cache, once a frame made it (nullptr before).
  const WorldCache* world_cache() const { return world_cache_.get(); }

 private:
  Renderer(vk::Context& context, GpuScene& scene, IrradianceField* field, ShadowField* shadow_field)
      : context_(context), scene_(scene), field_(field), shadow_field_(shadow_field) {}
  Status create_kernels();
  // Builds the kernels the field's current parameters need and create_kernels() leaves out.
  Status create_field_kernels();
  // Makes the world cache and its frame kernels when `settings` read it and they are missing.
  Status create_world_cache(const FrameSettings& settings);
  // The passes that feed the world cache at the frame's primary hits and fold the samples in.
  std::vector<vk::Pass> world_cache_passes(const FrameSettings& settings,
                                           const FrameTarget& target) const;
  // FAILED_PRECONDITION when the settings need a field this renderer was made without.
  Status check_inputs(const FrameSettings& settings) const;

  vk::Context& context_;
  GpuScene& scene_;
  IrradianceField* field_ = nullptr;
  ShadowField* shadow_field_ = nullptr;
  vk::TraceBackend backend_ = vk::TraceBackend::kRayQuery;
  vk::DescriptorLayout frame_layout_;
  vk::Kernel primary_;
  vk::Kernel primary_raw_trace_;
  vk::Kernel direct_;
  vk::Kernel direct_shadow_field_;  // the direct pass with the shadow field bound as set 2
  vk::Kernel indirect_;
  vk::Kernel pixel_paths_;  // the indirect pass tracing paths per pixel; built when first asked
  vk::Kernel field_views_;
  vk::Kernel tonemap_;
  vk::Kernel yuv420_;
  WorldCacheParams world_cache_params_;
  std::unique_ptr<WorldCache> world_cache_;
  vk::Kernel ao_cache_update_;               // the cache's AO samples; built with the cache
  vk::Kernel direct_ao_cache_;               // the direct pass with the cache bound as set 2
  std::unique_ptr<FrameTarget> own_target_;  // for render() without a target
};

// Turns a camera into the primary-ray basis of a width x height image.
struct CameraBasis {
  glm::vec3 position, forward, right, up;
};
CameraBasis camera_basis(const Camera& camera, uint32_t width, uint32_t height);

}  // namespace ddgi
