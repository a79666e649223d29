#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "shared/frame_data.h"

namespace ddgi {
namespace {

constexpr uint32_t kMaxImageDimension = 16384;
// Field updates + shadow-field updates + frame passes.
constexpr uint32_t kMaxTimedPasses = 5 * 64 + 4 * 64 + 8;

static_assert(sizeof(gpu::GBufferTexel) == 40);
static_assert(sizeof(gpu::PrimaryConstants) == 64);
static_assert(sizeof(gpu::DirectConstants) == 48);
static_assert(sizeof(gpu::TonemapConstants) == 16);
static_assert(sizeof(gpu::IndirectConstants) == 32);
static_assert(sizeof(gpu::FieldViewConstants) == 64);

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

Status validate(const FrameSettings& s) {
  if (s.width < 1 || s.width > kMaxImageDimension || s.height < 1 ||
      s.height > kMaxImageDimension) {
    return invalid_argument(
        "image size " + std::to_string(s.width) + "x" + std::to_string(s.height) +
        " is out of range: each side must be in [1, " + std::to_string(kMaxImageDimension) + "]");
  }
  if (s.field_updates > 64) {
    return invalid_argument("field updates per frame must be in [0, 64] (got " +
                            std::to_string(s.field_updates) + ")");
  }
  if (s.shadow_field_updates > 64) {
    return invalid_argument("shadow field updates per frame must be in [0, 64] (got " +
                            std::to_string(s.shadow_field_updates) + ")");
  }
  if (s.light_samples < 1 || s.light_samples > 64) {
    return invalid_argument("light samples per pixel must be in [1, 64] (got " +
                            std::to_string(s.light_samples) + ")");
  }
  if (!(s.exposure > 0.0f) || !(s.exposure <= 1e9f)) {
    return invalid_argument("exposure must be in (0, 1e9] (got " + std::to_string(s.exposure) +
                            ")");
  }
  const Camera& c = s.camera;
  if (!finite(c.position) || !finite(c.forward) || !finite(c.up)) {
    return invalid_argument("camera position, forward and up must be finite");
  }
  if (glm::length(c.forward) < 1e-6f || glm::length(glm::cross(c.forward, c.up)) < 1e-6f) {
    return invalid_argument("camera forward must be non-zero and not parallel to up");
  }
  if (!(c.yfov > 0.0f) || !(c.yfov < 3.1241f)) {
    return invalid_argument("camera vertical field of view must be in (0, 179] degrees");
  }
  if (!(c.znear >= 0.0f) || !std::isfinite(c.znear)) {
    return invalid_argument("camera near distance must be finite and >= 0");
  }
  return ok_status();
}

CameraBasis camera_basis(const Camera& camera, uint32_t width, uint32_t height) {
  CameraBasis b;
  b.position = camera.position;
  b.forward = glm::normalize(camera.forward);
  const glm::vec3 right = glm::normalize(glm::cross(b.forward, camera.up));
  const glm::vec3 up = glm::cross(right, b.forward);
  const float tan_half = std::tan(camera.yfov * 0.5f);
  const float aspect = float(width) / float(height);
  b.right = right * tan_half * aspect;
  b.up = up * tan_half;
  return b;
}

Result<std::unique_ptr<Renderer>> Renderer::create(vk::Context& context, GpuScene& scene,
                                                   IrradianceField* field, vk::TraceBackend backend,
                                                   ShadowField* shadow_field) {
  DDGI_TRY(context.check_backend(backend));
  std::unique_ptr<Renderer> renderer(new Renderer(context, scene, field, shadow_field));
  renderer->backend_ = backend;
  DDGI_TRY(renderer->create_kernels());
  DDGI_ASSIGN_OR_RETURN(renderer->timer_, vk::GpuTimer::create(context, kMaxTimedPasses));
  return renderer;
}

Status Renderer::create_kernels() {
  DDGI_ASSIGN_OR_RETURN(frame_layout_, vk::DescriptorLayout::create(context_,
                                                                    {{gpu::kFrameBindingGBuffer},
                                                                     {gpu::kFrameBindingRadiance},
                                                                     {gpu::kFrameBindingLdr}},
                                                                    1, "frame set"));
  DDGI_ASSIGN_OR_RETURN(frame_set_, frame_layout_.allocate());
  const std::vector<VkDescriptorSetLayout> layouts = {scene_.layout(), frame_layout_.handle()};
  DDGI_ASSIGN_OR_RETURN(
      primary_, vk::Kernel::create(
                    context_, {"primary", true, layouts, sizeof(gpu::PrimaryConstants)}, backend_));
  DDGI_ASSIGN_OR_RETURN(
      direct_, vk::Kernel::create(context_, {"direct", true, layouts, sizeof(gpu::DirectConstants)},
                                  backend_));
  if (shadow_field_) {
    DDGI_ASSIGN_OR_RETURN(direct_shadow_field_,
                          vk::Kernel::create(context_,
                                             {"direct_shadow_field",
                                              true,
                                              {scene_.layout(), frame_layout_.handle(),
                                               shadow_field_->sampling_layout()},
                                              sizeof(gpu::DirectConstants)},
                                             backend_));
  }
  if (field_) {
    const std::vector<VkDescriptorSetLayout> with_field = {scene_.layout(), frame_layout_.handle(),
                                                           field_->sampling_layout()};
    DDGI_ASSIGN_OR_RETURN(
        indirect_,
        vk::Kernel::create(
            context_, {"indirect", false, with_field, sizeof(gpu::IndirectConstants)}, backend_));
    DDGI_ASSIGN_OR_RETURN(field_views_, vk::Kernel::create(context_,
                                                           {"field_views", false, with_field,
                                                            sizeof(gpu::FieldViewConstants)},
                                                           backend_));
  }
  DDGI_ASSIGN_OR_RETURN(
      tonemap_,
      vk::Kernel::create(context_, {"tonemap", false, layouts, sizeof(gpu::TonemapConstants)},
                         backend_));
  return ok_status();
}

Status Renderer::resize(uint32_t width, uint32_t height) {
  if (width == width_ && height == height_) return ok_status();
  const VkDeviceSize pixels = VkDeviceSize(width) * height;
  const VkBufferUsageFlags usage =
      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  // Drop the old buffers first so the budget sees only the new ones.
  gbuffer_.reset();
  radiance_.reset();
  ldr_.reset();
  radiance_readback_.reset();
  ldr_readback_.reset();
  width_ = height_ = 0;
  DDGI_ASSIGN_OR_RETURN(gbuffer_,
                        vk::Buffer::create(context_, pixels * sizeof(gpu::GBufferTexel), usage,
                                           vk::MemoryUsage::kDeviceLocal, "gbuffer"));
  DDGI_ASSIGN_OR_RETURN(radiance_, vk::Buffer::create(context_, pixels * 16, usage,
                                                      vk::MemoryUsage::kDeviceLocal, "radiance"));
  DDGI_ASSIGN_OR_RETURN(
      ldr_, vk::Buffer::create(context_, pixels * 4, usage, vk::MemoryUsage::kDeviceLocal, "ldr"));
  DDGI_ASSIGN_OR_RETURN(radiance_readback_,
                        vk::Buffer::create(context_, pixels * 16, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           vk::MemoryUsage::kReadback, "radiance readback"));
  DDGI_ASSIGN_OR_RETURN(ldr_readback_,
                        vk::Buffer::create(context_, pixels * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           vk::MemoryUsage::kReadback, "ldr readback"));
  vk::DescriptorWriter(frame_set_)
      .buffer(gpu::kFrameBindingGBuffer, gbuffer_)
      .buffer(gpu::kFrameBindingRadiance, radiance_)
      .buffer(gpu::kFrameBindingLdr, ldr_)
      .apply(context_.device());
  width_ = width;
  height_ = height;
  return ok_status();
}

Result<FrameResult> Renderer::render(const FrameSettings& settings) {
  DDGI_TRY(validate(settings));
  const bool field_view = settings.view == View::kProbes || settings.view == View::kAtlas;
  if (field_view && !field_) {
    return failed_precondition("the probes and atlas views need an irradiance field (GI is off)");
  }
  const bool shadow_mode = uses_shadow_field(settings.direct_mode);
  if (shadow_mode && !shadow_field_) {
    return failed_precondition(std::string("the ") + direct_mode_name(settings.direct_mode) +
                               " direct mode needs a shadow field (none was created)");
  }
  DDGI_TRY(resize(settings.width, settings.height));
  const CameraBasis basis = camera_basis(settings.camera, settings.width, settings.height);

  gpu::PrimaryConstants primary{};
  primary.camera_position = basis.position;
  primary.camera_forward = basis.forward;
  primary.camera_right = basis.right;
  primary.camera_up = basis.up;
  primary.width = settings.width;
  primary.height = settings.height;
  primary.tmin = settings.camera.znear;
  primary.tmax = 1e30f;
  gpu::DirectConstants direct{};
  direct.width = settings.width;
  direct.height = settings.height;
  direct.mode = static_cast<uint32_t>(settings.direct_mode);
  direct.view = static_cast<uint32_t>(settings.view);
  direct.camera_position = basis.position;
  direct.light_samples = settings.light_samples;
  // Without an irradiance field nothing else brings the sky: the AO mode adds it.
  direct.flags = field_ ? 0u : gpu::kDirectAddSky;
  // The field decides where emitter light comes from; the frame must agree or count it twice.
  if (field_ && field_->params().emitter_samples > 0) {
    direct.flags |= gpu::kDirectSampleEmitters;
    direct.emitter_samples = field_->params().emitter_samples;
  }
  const gpu::TonemapConstants tonemap{settings.width, settings.height,
                                      static_cast<uint32_t>(settings.tonemap), settings.exposure};
  gpu::IndirectConstants indirect{};
  indirect.camera_position = basis.position;
  indirect.view = static_cast<uint32_t>(settings.view);
  indirect.width = settings.width;
  indirect.height = settings.height;
  gpu::FieldViewConstants views{};
  views.camera_position = basis.position;
  views.view = static_cast<uint32_t>(settings.view);
  views.camera_forward = basis.forward;
  views.width = settings.width;
  views.camera_right = basis.right;
  views.height = settings.height;
  views.camera_up = basis.up;
  if (field_) {
    const glm::vec3 spacing = field_->params().spacing;
    views.probe_radius = 0.1f * std::min({spacing.x, spacing.y, spacing.z});
  }
  const VkDescriptorSet sets[] = {scene_.descriptor_set(), frame_set_,
                                  field_ ? field_->sampling_set() : VK_NULL_HANDLE};
  const std::span<const VkDescriptorSet> frame_sets(sets, 2);
  const glm::uvec3 size{settings.width, settings.height, 1};

  // The shadow field is updated when the frame reads it, or when the irradiance field's probe
  // rays do (their own mode, field parameter probe_direct).
  const DirectMode shadow_update_mode = shadow_field_mode(
      settings.direct_mode, field_ && settings.field_updates > 0 ? &field_->params() : nullptr);
  const bool update_shadow_field = shadow_field_ && uses_shadow_field(shadow_update_mode);
  if (field_ && settings.field_updates > 0) DDGI_TRY(field_->prepare());
  DDGI_TRY(context_.submit_and_wait([&](VkCommandBuffer cmd) {
    timer_.begin_frame(cmd);
    // The shadow field first: the irradiance field's probe rays read it in these modes.
    if (update_shadow_field) {
      for (uint32_t i = 0; i < settings.shadow_field_updates; ++i) {
        shadow_field_->record_update(cmd, timer_, shadow_update_mode);
      }
    }
    if (field_) {
      for (uint32_t i = 0; i < settings.field_updates; ++i) {
        field_->record_update(cmd, timer_, settings.direct_mode);
      }
    }
    timer_.begin_pass(cmd, "primary");
    primary_.dispatch(cmd, frame_sets, &primary, size);
    timer_.end_pass(cmd);
    vk::barrier_all(cmd);
    timer_.begin_pass(cmd, "direct");
    if (shadow_mode) {
      const VkDescriptorSet shadow_sets[] = {scene_.descriptor_set(), frame_set_,
                                             shadow_field_->sampling_set()};
      direct_shadow_field_.dispatch(cmd, shadow_sets, &direct, size);
    } else {
      direct_.dispatch(cmd, frame_sets, &direct, size);
    }
    timer_.end_pass(cmd);
    vk::barrier_all(cmd);
    if (field_) {
      timer_.begin_pass(cmd, "indirect");
      indirect_.dispatch(cmd, sets, &indirect, size);
      timer_.end_pass(cmd);
      vk::barrier_all(cmd);
    }
    if (field_view) {
      timer_.begin_pass(cmd, "field view");
      field_views_.dispatch(cmd, sets, &views, size);
      timer_.end_pass(cmd);
      vk::barrier_all(cmd);
    }
    timer_.begin_pass(cmd, "tonemap");
    tonemap_.dispatch(cmd, frame_sets, &tonemap, size);
    timer_.end_pass(cmd);
    vk::barrier_all(cmd);
    timer_.begin_pass(cmd, "readback");
    if (settings.read_radiance) {
      VkBufferCopy radiance_copy{0, 0, radiance_.size()};
      vkCmdCopyBuffer(cmd, radiance_.handle(), radiance_readback_.handle(), 1, &radiance_copy);
    }
    VkBufferCopy ldr_copy{0, 0, ldr_.size()};
    vkCmdCopyBuffer(cmd, ldr_.handle(), ldr_readback_.handle(), 1, &ldr_copy);
    timer_.end_pass(cmd);
  }));

  FrameResult result;
  result.width = settings.width;
  result.height = settings.height;
  const size_t pixels = size_t(settings.width) * settings.height;
  if (settings.read_radiance) {
    result.radiance.resize(pixels * 4);
    std::memcpy(result.radiance.data(), radiance_readback_.mapped(), pixels * 16);
  }
  result.ldr.resize(pixels * 4);
  std::memcpy(result.ldr.data(), ldr_readback_.mapped(), pixels * 4);
  DDGI_ASSIGN_OR_RETURN(result.pass_times, timer_.read());
  result.frame_index = frame_index_++;
  context_.collect_garbage();
  return result;
}

}  // namespace ddgi
