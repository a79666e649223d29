#include "render/path_tracer.h"

#include <cstring>
#include <limits>

#include "render/renderer.h"
#include "shared/frame_data.h"
#include "shared/path_trace_data.h"

namespace ddgi {
namespace {

constexpr uint32_t kMaxBounces = 1024;
constexpr uint32_t kMaxSamplesPerCall = 65536;

static_assert(sizeof(gpu::PathTraceConstants) <= 128, "push constants guaranteed by Vulkan");
// The tone-mapping kernel reads the frame set's bindings; ours must line up with them.
static_assert(gpu::kPathTraceSet == gpu::kFrameSet);
static_assert(gpu::kPathTraceBindingRadiance == gpu::kFrameBindingRadiance);
static_assert(gpu::kPathTraceBindingLdr == gpu::kFrameBindingLdr);
static_assert(uint32_t(PathTraceView::kFull) == gpu::kPathTraceFull);
static_assert(uint32_t(PathTraceView::kDirect) == gpu::kPathTraceDirect);
static_assert(uint32_t(PathTraceView::kIndirect) == gpu::kPathTraceIndirect);
static_assert(uint32_t(PathTraceView::kPunctualDirect) == gpu::kPathTracePunctualDirect);
static_assert(uint32_t(PathTraceView::kFieldIndirect) == gpu::kPathTraceFieldIndirect);

bool same_camera(const Camera& a, const Camera& b) {
  return a.position == b.position && a.forward == b.forward && a.up == b.up && a.yfov == b.yfov &&
         a.znear == b.znear;
}

}  // namespace

Result<PathTraceView> parse_path_trace_view(const std::string& text) {
  if (text == "full") return PathTraceView::kFull;
  if (text == "direct") return PathTraceView::kDirect;
  if (text == "indirect") return PathTraceView::kIndirect;
  if (text == "punctual-direct") return PathTraceView::kPunctualDirect;
  if (text == "field-indirect") return PathTraceView::kFieldIndirect;
  return invalid_argument(
      "path-traced view must be one of full, direct, indirect, punctual-direct, field-indirect "
      "(got '" +
      text + "')");
}

Status validate(const PathTraceSettings& s) {
  // Image size and camera: the same rules as a raster frame.
  FrameSettings frame;
  frame.width = s.width;
  frame.height = s.height;
  frame.camera = s.camera;
  DDGI_TRY(validate(frame));
  if (static_cast<uint32_t>(s.view) > static_cast<uint32_t>(PathTraceView::kFieldIndirect)) {
    return invalid_argument("unknown path-traced view " +
                            std::to_string(static_cast<uint32_t>(s.view)));
  }
  if (s.max_bounces > kMaxBounces) {
    return invalid_argument("max bounces must be in [0, " + std::to_string(kMaxBounces) +
                            "] (got " + std::to_string(s.max_bounces) + ")");
  }
  if (s.roulette_start < 1 || s.roulette_start > kMaxBounces) {
    return invalid_argument("Russian roulette start must be in [1, " + std::to_string(kMaxBounces) +
                            "] (got " + std::to_string(s.roulette_start) + ")");
  }
  return ok_status();
}

Result<std::unique_ptr<PathTracer>> PathTracer::create(vk::Context& context, GpuScene& scene,
                                                       vk::TraceBackend backend) {
  DDGI_TRY(context.check_backend(backend));
  std::unique_ptr<PathTracer> tracer(new PathTracer(context, scene));
  tracer->backend_ = backend;
  DDGI_TRY(tracer->create_kernels());
  DDGI_ASSIGN_OR_RETURN(tracer->timer_, vk::GpuTimer::create(context, 1));
  return tracer;
}

Status PathTracer::create_kernels() {
  DDGI_ASSIGN_OR_RETURN(
      layout_, vk::DescriptorLayout::create(
                   context_, {{gpu::kPathTraceBindingRadiance}, {gpu::kPathTraceBindingLdr}}, 1,
                   "path tracer set"));
  DDGI_ASSIGN_OR_RETURN(set_, layout_.allocate());
  const std::vector<VkDescriptorSetLayout> layouts = {scene_.layout(), layout_.handle()};
  DDGI_ASSIGN_OR_RETURN(
      path_trace_,
      vk::Kernel::create(context_, {"path_trace", true, layouts, sizeof(gpu::PathTraceConstants)},
                         backend_));
  DDGI_ASSIGN_OR_RETURN(
      tonemap_,
      vk::Kernel::create(context_, {"tonemap", false, layouts, sizeof(gpu::TonemapConstants)},
                         backend_));
  return ok_status();
}

Status PathTracer::resize(uint32_t width, uint32_t height) {
  if (width == images_.width && height == images_.height) return ok_status();
  images_ = {};  // first, so that the budget sees only the new buffers
  samples_ = 0;
  DDGI_ASSIGN_OR_RETURN(images_, ImageBuffers::create(context_, width, height, "path-traced"));
  vk::DescriptorWriter(set_)
      .buffer(gpu::kPathTraceBindingRadiance, images_.radiance)
      .buffer(gpu::kPathTraceBindingLdr, images_.ldr)
      .apply(context_.device());
  return ok_status();
}

bool PathTracer::same_image(const PathTraceSettings& s) const {
  const PathTraceSettings& a = settings_;
  return a.width == s.width && a.height == s.height && same_camera(a.camera, s.camera) &&
         a.view == s.view && a.max_bounces == s.max_bounces &&
         a.roulette_start == s.roulette_start && a.seed == s.seed && a.jitter == s.jitter &&
         scene_revision_ == scene_.revision();
}

Status PathTracer::accumulate(const PathTraceSettings& settings, uint32_t samples) {
  DDGI_TRY(validate(settings));
  if (samples < 1 || samples > kMaxSamplesPerCall) {
    return invalid_argument("samples per call must be in [1, " +
                            std::to_string(kMaxSamplesPerCall) + "] (got " +
                            std::to_string(samples) + ")");
  }
  if (!same_image(settings)) samples_ = 0;
  if (samples > std::numeric_limits<uint32_t>::max() - samples_) {
    return invalid_argument("too many samples accumulated; reset first");
  }
  DDGI_TRY(resize(settings.width, settings.height));
  const CameraBasis basis = camera_basis(settings.camera, settings.width, settings.height);

  gpu::PathTraceConstants pc{};
  pc.camera_position = basis.position;
  pc.camera_forward = basis.forward;
  pc.camera_right = basis.right;
  pc.camera_up = basis.up;
  pc.width = settings.width;
  pc.height = settings.height;
  pc.tmin = settings.camera.znear;
  pc.view = static_cast<uint32_t>(settings.view);
  pc.seed = settings.seed;
  pc.first_sample = samples_;
  pc.sample_count = samples;
  pc.max_bounces = settings.max_bounces;
  pc.roulette_start = settings.roulette_start;
  pc.jitter = settings.jitter ? 1u : 0u;
  vk::Pass pass;
  pass.name = "path trace";
  pass.kernel = &path_trace_;
  pass.sets = {scene_.descriptor_set(), set_};
  pass.push_constants = vk::Pass::push(pc);
  pass.size = {settings.width, settings.height, 1};
  pass.reads = {&images_.radiance};
  pass.writes = {&images_.radiance};
  DDGI_TRY(context_.submit_and_wait([&](VkCommandBuffer cmd) {
    timer_.begin_frame(cmd);
    vk::record_passes(cmd, &timer_, std::span(&pass, 1));
  }));
  DDGI_ASSIGN_OR_RETURN(const std::vector<vk::PassTime> times, timer_.read());
  last_accumulate_ms_ = times.empty() ? 0.0 : times.front().milliseconds;
  settings_ = settings;
  scene_revision_ = scene_.revision();
  samples_ += samples;
  context_.collect_garbage();
  return ok_status();
}

Result<PathTraceImage> PathTracer::read(Tonemap tonemap, float exposure) {
  if (samples_ == 0) return failed_precondition("the path tracer has no samples yet");
  if (!(exposure > 0.0f) || !(exposure <= 1e9f)) {
    return invalid_argument("exposure must be in (0, 1e9] (got " + std::to_string(exposure) + ")");
  }
  const gpu::TonemapConstants constants{images_.width, images_.height,
                                        static_cast<uint32_t>(tonemap), exposure};
  vk::Pass tonemap_pass;
  tonemap_pass.name = "tonemap";
  tonemap_pass.kernel = &tonemap_;
  tonemap_pass.sets = {scene_.descriptor_set(), set_};
  tonemap_pass.push_constants = vk::Pass::push(constants);
  tonemap_pass.size = {images_.width, images_.height, 1};
  tonemap_pass.reads = {&images_.radiance};
  tonemap_pass.writes = {&images_.ldr};
  const vk::Pass passes[] = {tonemap_pass, images_.readback_pass(true)};
  DDGI_TRY(context_.submit_and_wait(
      [&](VkCommandBuffer cmd) { vk::record_passes(cmd, nullptr, passes); }));
  PathTraceImage image;
  image.width = images_.width;
  image.height = images_.height;
  image.samples = samples_;
  image.radiance = images_.read_radiance();
  image.ldr = images_.read_ldr();
  return image;
}

}  // namespace ddgi
