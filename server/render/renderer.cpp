// The frame passes (render/renderer.h).
#include "render/renderer.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "shared/frame_data.h"
#include "shared/world_cache_data.h"

namespace ddgi {
namespace {

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

Status validate(const FrameSettings& s) {
  DDGI_TRY(validate_image_size(s.width, s.height));
  if (s.light_samples < 1 || s.light_samples > 64) {
    return invalid_argument("light samples per pixel must be in [1, 64] (got " +
                            std::to_string(s.light_samples) + ")");
  }
  if (s.ao_samples < 1 || s.ao_samples > 4096) {
    return invalid_argument("AO samples per pixel must be in [1, 4096] (got " +
                            std::to_string(s.ao_samples) + ")");
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
  if (!camera_yfov_in_range(c.yfov)) {
    return invalid_argument("camera vertical field of view must be in (0, " +
                            std::to_string(int(kMaxCameraYfovDegrees)) + "] degrees (got " +
                            std::to_string(c.yfov * 180.0f / 3.14159265f) + ")");
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
  return renderer;
}

Status Renderer::create_kernels() {
  DDGI_ASSIGN_OR_RETURN(
      frame_layout_, vk::DescriptorLayout::create(context_, frame_set_bindings(), 1, "frame set"));
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
  DDGI_ASSIGN_OR_RETURN(
      yuv420_, vk::Kernel::create(context_, {"yuv420", false, layouts, sizeof(gpu::Yuv420Layout)},
                                  backend_));
  return ok_status();
}

Status Renderer::create_field_kernels() {
  // A path traversal inlined per pixel compiles for a while on lavapipe: only when asked.
  if (!field_ || field_->params().pixel_paths == 0 || pixel_paths_.valid()) return ok_status();
  DDGI_ASSIGN_OR_RETURN(
      pixel_paths_,
      vk::Kernel::create(context_,
                         {"pixel_paths",
                          true,
                          {scene_.layout(), frame_layout_.handle(), field_->sampling_layout()},
                          sizeof(gpu::IndirectConstants)},
                         backend_));
  return ok_status();
}

Status Renderer::create_world_cache(const FrameSettings& settings) {
  if (!uses_world_cache(settings.direct_mode) || world_cache_) return ok_status();
  DDGI_ASSIGN_OR_RETURN(world_cache_, WorldCache::create(context_, world_cache_params_));
  const std::vector<VkDescriptorSetLayout> layouts = {scene_.layout(), frame_layout_.handle(),
                                                      world_cache_->layout()};
  DDGI_ASSIGN_OR_RETURN(
      ao_cache_update_,
      vk::Kernel::create(
          context_, {"ao_cache_update", true, layouts, sizeof(gpu::WorldCacheDispatch)}, backend_));
  DDGI_ASSIGN_OR_RETURN(
      direct_ao_cache_,
      vk::Kernel::create(context_, {"direct_ao_cache", true, layouts, sizeof(gpu::DirectConstants)},
                         backend_));
  return ok_status();
}

Status Renderer::set_world_cache_params(const WorldCacheParams& params) {
  DDGI_TRY(validate(params));
  world_cache_params_ = params;
  world_cache_.reset();  // made again, empty, by the next frame that reads it
  return ok_status();
}

Status Renderer::check_inputs(const FrameSettings& settings) const {
  DDGI_TRY(validate(settings));
  const bool field_view = settings.view == View::kProbes || settings.view == View::kAtlas;
  if (field_view && !field_) {
    return failed_precondition("the probes and atlas views need an irradiance field (GI is off)");
  }
  if (settings.view == View::kCachePoints && !uses_world_cache(settings.direct_mode)) {
    return failed_precondition("the cache-points view needs the ao-cache direct mode (got " +
                               std::string(direct_mode_name(settings.direct_mode)) + ")");
  }
  if (uses_shadow_field(settings.direct_mode) && !shadow_field_) {
    return failed_precondition(std::string("the ") + direct_mode_name(settings.direct_mode) +
                               " direct mode needs a shadow field (none was created)");
  }
  return ok_status();
}

namespace {

// The push constants of one frame's passes.
struct FrameConstants {
  gpu::PrimaryConstants primary{};
  gpu::DirectConstants direct{};
  gpu::IndirectConstants indirect{};
  gpu::FieldViewConstants views{};
  gpu::TonemapConstants tonemap{};
};

FrameConstants frame_constants(const FrameSettings& settings, const IrradianceField* field,
                               const WorldCacheParams& cache) {
  const CameraBasis basis = camera_basis(settings.camera, settings.width, settings.height);
  FrameConstants c;
  gpu::PrimaryConstants& primary = c.primary;
  primary.camera_position = basis.position;
  primary.camera_forward = basis.forward;
  primary.camera_right = basis.right;
  primary.camera_up = basis.up;
  primary.width = settings.width;
  primary.height = settings.height;
  primary.tmin = settings.camera.znear;
  primary.tmax = 1e30f;
  gpu::DirectConstants& direct = c.direct;
  direct.width = settings.width;
  direct.height = settings.height;
  direct.mode = static_cast<uint32_t>(settings.direct_mode);
  direct.view = static_cast<uint32_t>(settings.view);
  direct.camera_position = basis.position;
  direct.light_samples = settings.light_samples;
  direct.ao_samples = settings.ao_samples;
  direct.ao_distance = cache.ao_distance;
  // Without an irradiance field nothing else brings the sky: the AO mode adds it.
  direct.flags = field ? 0u : gpu::kDirectAddSky;
  // The field decides where emitter light comes from; the frame must agree or count it twice.
  if (field && field->params().emitter_samples > 0) {
    direct.flags |= gpu::kDirectSampleEmitters;
    direct.emitter_samples = field->params().emitter_samples;
  }
  c.tonemap = {settings.width, settings.height, static_cast<uint32_t>(settings.tonemap),
               settings.exposure};
  c.indirect.camera_position = basis.position;
  c.indirect.view = static_cast<uint32_t>(settings.view);
  c.indirect.width = settings.width;
  c.indirect.height = settings.height;
  if (field) {
    c.indirect.paths = field->params().pixel_paths;
    c.indirect.path_vertices = field->params().pixel_path_vertices;
  }
  gpu::FieldViewConstants& views = c.views;
  views.camera_position = basis.position;
  views.view = static_cast<uint32_t>(settings.view);
  views.camera_forward = basis.forward;
  views.width = settings.width;
  views.camera_right = basis.right;
  views.height = settings.height;
  views.camera_up = basis.up;
  if (field) {
    const glm::vec3 spacing = field->params().spacing;
    views.probe_radius = 0.1f * std::min({spacing.x, spacing.y, spacing.z});
  }
  return c;
}

}  // namespace

std::vector<vk::Pass> Renderer::frame_passes(const FrameSettings& settings,
                                             const FrameTarget& target) const {
  const FrameConstants c = frame_constants(settings, field_, world_cache_params_);
  const std::vector<VkDescriptorSet> frame_sets = {scene_.descriptor_set(), target.frame_set()};
  const glm::uvec3 size{settings.width, settings.height, 1};
  const vk::Buffer& gbuffer = target.gbuffer();
  const vk::Buffer& radiance = target.images().radiance;
  auto pass = [&](const char* name, const vk::Kernel& kernel, std::vector<VkDescriptorSet> sets,
                  std::vector<uint8_t> push, std::vector<vk::ResourceRef> reads,
                  std::vector<vk::ResourceRef> writes) {
    vk::Pass p;
    p.name = name;
    p.group = vk::PassGroup::kFrame;
    p.kernel = &kernel;
    p.sets = std::move(sets);
    p.push_constants = std::move(push);
    p.size = size;
    p.reads = std::move(reads);
    p.writes = std::move(writes);
    return p;
  };
  std::vector<vk::Pass> passes;
  passes.push_back(
      pass("primary", primary_, frame_sets, vk::Pass::push(c.primary), {}, {&gbuffer}));
  if (uses_world_cache(settings.direct_mode)) {
    for (vk::Pass& p : world_cache_passes(settings, target)) passes.push_back(std::move(p));
    passes.push_back(
        pass("direct", direct_ao_cache_,
             {scene_.descriptor_set(), target.frame_set(), world_cache_->descriptor_set()},
             vk::Pass::push(c.direct), {&gbuffer}, {&radiance}));
  } else if (uses_shadow_field(settings.direct_mode)) {
    passes.push_back(
        pass("direct", direct_shadow_field_,
             {scene_.descriptor_set(), target.frame_set(), shadow_field_->sampling_set()},
             vk::Pass::push(c.direct), {&gbuffer}, {&radiance}));
  } else {
    passes.push_back(
        pass("direct", direct_, frame_sets, vk::Pass::push(c.direct), {&gbuffer}, {&radiance}));
  }
  if (field_) {
    const std::vector<VkDescriptorSet> with_field = {scene_.descriptor_set(), target.frame_set(),
                                                     field_->sampling_set()};
    const vk::Kernel& indirect = c.indirect.paths > 0 ? pixel_paths_ : indirect_;
    passes.push_back(pass("indirect", indirect, with_field, vk::Pass::push(c.indirect),
                          {&gbuffer, &radiance}, {&radiance}));
    if (settings.view == View::kProbes || settings.view == View::kAtlas) {
      passes.push_back(pass("field view", field_views_, with_field, vk::Pass::push(c.views),
                            {&gbuffer, &radiance}, {&radiance}));
    }
  }
  passes.push_back(pass("tonemap", tonemap_, frame_sets, vk::Pass::push(c.tonemap), {&radiance},
                        {&target.images().ldr}));
  if (settings.read_yuv420) {
    // One invocation per 8x2 pixels (yuv420.comp).
    const gpu::Yuv420Layout& layout = target.yuv420_layout();
    vk::Pass yuv = pass("yuv420", yuv420_, frame_sets, vk::Pass::push(layout),
                        {&target.images().ldr}, {&target.yuv420()});
    yuv.size = {layout.y_stride / 8, layout.y_rows / 2, 1};
    passes.push_back(std::move(yuv));
  }
  passes.push_back(target.readback_pass(settings.read_radiance, settings.read_yuv420));
  return passes;
}

std::vector<vk::Pass> Renderer::world_cache_passes(const FrameSettings& settings,
                                                   const FrameTarget& target) const {
  // A pixel's footprint per unit distance: the image's height spans 2 tan(yfov/2) there.
  const float footprint = 2.0f * std::tan(settings.camera.yfov * 0.5f) / float(settings.height);
  std::vector<vk::Pass> passes = {
      world_cache_->begin_frame_pass(settings.camera.position, footprint, scene_.move_count())};
  vk::Pass samples;
  samples.name = "ao cache samples";
  samples.group = vk::PassGroup::kFrame;
  samples.kernel = &ao_cache_update_;
  samples.sets = {scene_.descriptor_set(), target.frame_set(), world_cache_->descriptor_set()};
  samples.push_constants =
      vk::Pass::push(gpu::WorldCacheDispatch{settings.width, settings.height, 0, 0});
  samples.size = {settings.width, settings.height, 1};
  samples.reads = {&target.gbuffer()};
  passes.push_back(std::move(samples));
  passes.push_back(world_cache_->resolve_pass());
  return passes;
}

Result<std::vector<vk::Pass>> Renderer::raw_primary_passes(const FrameSettings& settings,
                                                           const FrameTarget& target) {
  if (!primary_raw_trace_.valid()) {
    const std::vector<VkDescriptorSetLayout> layouts = {scene_.layout(), frame_layout_.handle()};
    DDGI_ASSIGN_OR_RETURN(
        primary_raw_trace_,
        vk::Kernel::create(context_,
                           {"primary_raw_trace", true, layouts, sizeof(gpu::PrimaryConstants)},
                           backend_));
  }
  vk::Pass pass;
  pass.name = "primary raw trace";
  pass.group = vk::PassGroup::kBaseline;
  pass.kernel = &primary_raw_trace_;
  pass.sets = {scene_.descriptor_set(), target.frame_set()};
  pass.push_constants =
      vk::Pass::push(frame_constants(settings, field_, world_cache_params_).primary);
  pass.size = {settings.width, settings.height, 1};
  pass.writes = {&target.gbuffer()};
  return std::vector<vk::Pass>{pass};
}

Result<FrameResult> Renderer::render(const FrameSettings& settings,
                                     std::span<const vk::Pass> before) {
  DDGI_TRY(validate(settings));
  if (!own_target_ || own_target_->width() != settings.width ||
      own_target_->height() != settings.height) {
    own_target_.reset();  // first, so that the budget sees only the new target
    DDGI_ASSIGN_OR_RETURN(own_target_,
                          FrameTarget::create(context_, settings.width, settings.height));
  }
  return render(settings, *own_target_, before);
}

Result<PendingFrame> Renderer::submit(const FrameSettings& settings, FrameTarget& target,
                                      std::span<const vk::Pass> before) {
  DDGI_TRY(check_inputs(settings));
  DDGI_TRY(create_field_kernels());
  DDGI_TRY(create_world_cache(settings));
  if (target.width() != settings.width || target.height() != settings.height) {
    return invalid_argument("the frame target is " + std::to_string(target.width()) + "x" +
                            std::to_string(target.height()) + ", the frame " +
                            std::to_string(settings.width) + "x" + std::to_string(settings.height));
  }
  if (target.busy()) {
    return failed_precondition("the frame target still holds a frame in flight: finish it first");
  }
  const std::vector<vk::Pass> passes = frame_passes(settings, target);
  DDGI_ASSIGN_OR_RETURN(VkCommandBuffer cmd, target.commands().begin());
  target.timer().begin_frame(cmd);
  vk::record_passes(cmd, &target.timer(), before);
  vk::record_passes(cmd, &target.timer(), passes);
  DDGI_TRY(target.commands().submit());
  target.set_busy(true);
  PendingFrame frame;
  frame.context_ = &context_;
  frame.target_ = &target;
  frame.width_ = settings.width;
  frame.height_ = settings.height;
  frame.read_radiance_ = settings.read_radiance;
  frame.read_yuv420_ = settings.read_yuv420;
  frame.frame_index_ = target.next_frame_index();
  return frame;
}

Result<FrameResult> Renderer::render(const FrameSettings& settings, FrameTarget& target,
                                     std::span<const vk::Pass> before) {
  DDGI_ASSIGN_OR_RETURN(PendingFrame frame, submit(settings, target, before));
  return frame.finish();
}

PendingFrame& PendingFrame::operator=(PendingFrame&& other) noexcept {
  if (this != &other) {
    release();
    context_ = std::exchange(other.context_, nullptr);
    target_ = std::exchange(other.target_, nullptr);
    width_ = other.width_;
    height_ = other.height_;
    read_radiance_ = other.read_radiance_;
    read_yuv420_ = other.read_yuv420_;
    frame_index_ = other.frame_index_;
  }
  return *this;
}

void PendingFrame::release() {
  if (!target_) return;
  (void)target_->commands().wait();  // an error here leaves nothing to do but let go
  target_->set_busy(false);
  target_ = nullptr;
}

Status PendingFrame::wait() {
  if (!target_) return failed_precondition("the frame was finished already");
  return target_->commands().wait();
}

Result<FrameResult> PendingFrame::finish() {
  if (!target_) return failed_precondition("the frame was finished already");
  const Status waited = wait();
  if (!waited.ok()) {
    release();
    return waited.error();
  }
  FrameTarget& target = *target_;
  FrameResult result;
  result.width = width_;
  result.height = height_;
  if (read_radiance_) result.radiance = target.images().read_radiance();
  if (read_yuv420_) {
    result.yuv420 = target.read_yuv420();
    result.yuv420_layout = target.yuv420_layout();
  } else {
    result.ldr = target.images().read_ldr();
  }
  Result<std::vector<vk::PassTime>> times = target.timer().read();
  release();
  if (!times.ok()) return times.error();
  result.pass_times = std::move(times).value();
  result.frame_index = frame_index_;
  context_->collect_garbage();
  return result;
}

}  // namespace ddgi
