// Renders frames of one GPU scene: primary rays into a G-buffer, direct light, tone mapping,
// readback. Owns the per-resolution frame buffers and the kernels of these passes.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "gi/irradiance_field.h"
#include "gi/shadow_field.h"
#include "gpu_scene/frame_types.h"
#include "gpu_scene/gpu_scene.h"
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
  // Irradiance-field updates recorded before this frame's passes, in [0, 64]. 1: one update
  // per frame, the real-time loop.
  uint32_t field_updates = 1;
  // Copy the linear HDR image back (FrameResult::radiance). A stream that only encodes the
  // 8-bit image turns this off: at 1920x1080 the HDR copy is 33 MB per frame.
  bool read_radiance = true;
  // Shadow-field updates recorded before this frame's passes when the direct mode uses the
  // shadow field, in [0, 64]. 1: the real-time loop.
  uint32_t shadow_field_updates = 1;
  // Shadow rays per spherical light (radius > 0) and pixel in the shadow-rays mode, [1, 64].
  // 1: the real-time default, noisy penumbrae; more give smooth soft shadows.
  uint32_t light_samples = 1;
};
Status validate(const FrameSettings& settings);

struct FrameResult {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<float> radiance;  // linear HDR, RGBA float per pixel, row 0 = top (if read)
  std::vector<uint8_t> ldr;     // tone-mapped sRGB RGBA8 per pixel, row 0 = top
  std::vector<vk::PassTime> pass_times;
  uint64_t frame_index = 0;
};

class Renderer {
 public:
  // `backend`: the tracing backend of every kernel (must be supported by the device).
  // `field`: the irradiance field that gives indirect light; nullptr renders direct light only.
  // `shadow_field`: what the shadow-field and AO direct modes sample; nullptr refuses them.
  static Result<std::unique_ptr<Renderer>> create(vk::Context& context, GpuScene& scene,
                                                  IrradianceField* field, vk::TraceBackend backend,
                                                  ShadowField* shadow_field = nullptr);

  Result<FrameResult> render(const FrameSettings& settings);
  vk::TraceBackend backend() const { return backend_; }

 private:
  Renderer(vk::Context& context, GpuScene& scene, IrradianceField* field, ShadowField* shadow_field)
      : context_(context), scene_(scene), field_(field), shadow_field_(shadow_field) {}
  Status create_kernels();
  Status resize(uint32_t width, uint32_t height);

  vk::Context& context_;
  GpuScene& scene_;
  IrradianceField* field_ = nullptr;
  ShadowField* shadow_field_ = nullptr;
  vk::TraceBackend backend_ = vk::TraceBackend::kRayQuery;
  vk::DescriptorLayout frame_layout_;
  VkDescriptorSet frame_set_ = VK_NULL_HANDLE;
  vk::Kernel primary_;
  vk::Kernel direct_;
  vk::Kernel direct_shadow_field_;  // the direct pass with the shadow field bound as set 2
  vk::Kernel indirect_;
  vk::Kernel field_views_;
  vk::Kernel tonemap_;
  vk::GpuTimer timer_;

  uint32_t width_ = 0;
  uint32_t height_ = 0;
  vk::Buffer gbuffer_;
  vk::Buffer radiance_;
  vk::Buffer ldr_;
  vk::Buffer radiance_readback_;
  vk::Buffer ldr_readback_;
  uint64_t frame_index_ = 0;
};

// Turns a camera into the primary-ray basis of a width x height image.
struct CameraBasis {
  glm::vec3 position, forward, right, up;
};
CameraBasis camera_basis(const Camera& camera, uint32_t width, uint32_t height);

}  // namespace ddgi
