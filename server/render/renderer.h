// Renders frames of one GPU scene: primary rays into a G-buffer, direct light, tone mapping,
// readback. Owns the per-resolution frame buffers and the kernels of these passes.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "render/gpu_scene.h"
#include "scene/scene.h"
#include "vk/context.h"
#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace ddgi {

enum class Tonemap : uint32_t { kClamp = 0, kReinhard = 1, kAces = 2 };
enum class DirectMode : uint32_t { kTracedShadows = 0, kUnshadowed = 1 };
enum class View : uint32_t { kFull = 0, kDirect = 1, kIndirect = 2, kAlbedo = 3, kNormal = 4 };

Result<Tonemap> parse_tonemap(const std::string& text);
Result<DirectMode> parse_direct_mode(const std::string& text);
Result<View> parse_view(const std::string& text);

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
};
Status validate(const FrameSettings& settings);

struct FrameResult {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<float> radiance;  // linear HDR, RGBA float per pixel, row 0 = top
  std::vector<uint8_t> ldr;     // tone-mapped sRGB RGBA8 per pixel, row 0 = top
  std::vector<vk::PassTime> pass_times;
  uint64_t frame_index = 0;
};

class Renderer {
 public:
  // `backend`: the tracing backend of every kernel (must be supported by the device).
  static Result<std::unique_ptr<Renderer>> create(vk::Context& context, GpuScene& scene,
                                                  vk::TraceBackend backend);

  Result<FrameResult> render(const FrameSettings& settings);
  vk::TraceBackend backend() const { return backend_; }

 private:
  Renderer(vk::Context& context, GpuScene& scene) : context_(context), scene_(scene) {}
  Status create_kernels();
  Status resize(uint32_t width, uint32_t height);

  vk::Context& context_;
  GpuScene& scene_;
  vk::TraceBackend backend_ = vk::TraceBackend::kRayQuery;
  vk::DescriptorLayout frame_layout_;
  VkDescriptorSet frame_set_ = VK_NULL_HANDLE;
  vk::Kernel primary_;
  vk::Kernel direct_;
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
