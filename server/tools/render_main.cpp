// ddgi-render: renders one frame of a scene without any server and writes it to a file.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "core/flags.h"
#include "core/log.h"
#include "encode/write_image.h"
#include "gi/field_params.h"
#include "gi/gi_stack.h"
#include "gi/shadow_params.h"
#include "gpu_scene/camera_fit.h"
#include "gpu_scene/gpu_scene.h"
#include "render/renderer.h"
#include "tools/reference_render.h"
#include "tools/tool_support.h"
#include "vk/context.h"

namespace ddgi {
namespace {

constexpr const char* kUsage = R"(usage: ddgi-render [SCENE] [flags]

Renders one frame of SCENE (.gltf, .glb or a .ddgi.json sidecar; default: the built-in
Cornell box) and writes it to --out. Prints the GPU time of every pass.

  --out FILE            output image: .png, .jpg or .exr (linear HDR)   [frame.png]
  --width N --height N  image size, 1..16384                            [640 x 480]
  --camera px,py,pz,tx,ty,tz[,yfov]  position, target, vertical FOV in degrees
                                                          [the scene's camera, or a fitted one]
  --backend B           auto | query | pipeline                         [auto]
  --view V              full | direct | indirect | albedo | normal | probes | atlas |
                        cache-points (ao-cache: the world-cache point each surface reads) [full]
  --direct M            shadow-rays | unshadowed | shadow-field | ao | ao-traced | ao-cache
                        [shadow-rays] (docs/shadow-field.md, docs/world-cache.md)
  --light-samples N     shadow rays per spherical light and pixel, 1..64 [1]
  --ao-samples N        ao-traced: AO rays per pixel, 1..4096            [1]
  --world-cache NAME=VALUE  set a world-cache parameter (repeatable); --world-cache help
                        lists them (ao-cache: --frames feed the cache, one sample per pixel each)
  --shadow-field NAME=VALUE  set a shadow-field parameter (repeatable); --shadow-field help
                        lists them [grid of about 512 probes fitted to the scene's bounds]
  --tonemap T           aces | reinhard | clamp                         [aces]
  --exposure X          linear multiplier before tone mapping           [1]
  --jpeg-quality Q      1..100                                          [90]
  --gi on|off           indirect light from a DDGI irradiance field      [on]
  --warmup N            field updates before the first frame, most at low     [128]
                        hysteresis so light converges fast (IrradianceField::warm_up)
  --field NAME=VALUE    set a field parameter (repeatable); --field help lists them
                        [grid from the scene's sidecar, else fitted to its bounds]
  --frames N            render N times (one field update each) and report median times [1]
  --reference SPP       render the path-traced reference instead, SPP samples per pixel;
                        --view full | direct | indirect | punctual-direct | field-indirect
                        (docs/reference-path-tracer.md)
  --max-bounces N       reference: scattering events per path, 0..1024    [64]
  --seed S              reference: random seed, 0..4294967295             [0]
  --device NAME         use the Vulkan device whose name contains NAME
  --validation          enable Vulkan validation layers
  --log-level L         debug | info | warning | error                  [info]
)";

std::string default_scene_path() {
#ifdef DDGI_DEFAULT_SCENE
  return DDGI_DEFAULT_SCENE;
#else
  return "scenes/cornell_box.gltf";
#endif
}

// Everything the flags ask for.
struct RenderJob {
  std::string scene_path;
  std::string out_path;
  encode::ImageFormat format = encode::ImageFormat::kPng;
  int64_t frames = 1;
  int64_t quality = 90;
  int64_t warmup = 128;
  int64_t reference_spp = 0;  // > 0: the path-traced reference instead of frames
  FrameSettings settings;
  ReferenceOptions reference;
  bool gi = true;
  std::vector<std::string> field_assignments;
  std::vector<std::string> shadow_assignments;
  WorldCacheParams world_cache;
  std::vector<double> camera_values;
};

Result<Flags> parse_flags(int argc, char** argv) {
  return Flags::parse(
      argc, argv,
      {"out",       "width",        "height",        "camera",       "backend",    "view",
       "direct",    "tonemap",      "exposure",      "jpeg-quality", "frames",     "device",
       "log-level", "gi",           "warmup",        "field",        "reference",  "max-bounces",
       "seed",      "shadow-field", "light-samples", "ao-samples",   "world-cache"},
      {"validation", "help"});
}

// --help, --field help and --shadow-field help print their text; true when one did.
bool printed_help(const Flags& flags) {
  if (flags.has("help")) {
    std::fputs(kUsage, stdout);
    return true;
  }
  const std::vector<std::string> shadow_assignments = flags.get_all("shadow-field");
  if (!shadow_assignments.empty() && shadow_assignments.front() == "help") {
    std::fputs(shadow_param_table().help().c_str(), stdout);
    return true;
  }
  const std::vector<std::string> cache_assignments = flags.get_all("world-cache");
  if (!cache_assignments.empty() && cache_assignments.front() == "help") {
    std::fputs(world_cache_param_table().help().c_str(), stdout);
    return true;
  }
  const std::vector<std::string> field_assignments = flags.get_all("field");
  if (!field_assignments.empty() && field_assignments.front() == "help") {
    std::fputs(field_param_table().help().c_str(), stdout);
    return true;
  }
  return false;
}

// The frame's own flags: size, view, direct light, tone mapping, camera, reference.
Status parse_frame_flags(const Flags& flags, RenderJob& job) {
  FrameSettings& settings = job.settings;
  DDGI_ASSIGN_OR_RETURN(const int64_t width, flags.get_int("width", 640, 1, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t height, flags.get_int("height", 480, 1, 16384));
  settings.width = static_cast<uint32_t>(width);
  settings.height = static_cast<uint32_t>(height);
  DDGI_ASSIGN_OR_RETURN(const double exposure, flags.get_double("exposure", 1.0, 1e-9, 1e9));
  settings.exposure = static_cast<float>(exposure);
  DDGI_ASSIGN_OR_RETURN(const std::string view, flags.get_string("view", "full"));
  DDGI_ASSIGN_OR_RETURN(job.reference_spp, flags.get_int("reference", 0, 0, 1 << 24));
  if (job.reference_spp > 0) {
    DDGI_ASSIGN_OR_RETURN(job.reference.settings.view, parse_path_trace_view(view));
    DDGI_ASSIGN_OR_RETURN(const int64_t bounces, flags.get_int("max-bounces", 64, 0, 1024));
    DDGI_ASSIGN_OR_RETURN(const int64_t seed, flags.get_int("seed", 0, 0, 4294967295));
    job.reference.settings.max_bounces = static_cast<uint32_t>(bounces);
    job.reference.settings.seed = static_cast<uint32_t>(seed);
  } else {
    DDGI_ASSIGN_OR_RETURN(settings.view, parse_view(view));
  }
  DDGI_ASSIGN_OR_RETURN(const std::string direct, flags.get_string("direct", "shadow-rays"));
  DDGI_ASSIGN_OR_RETURN(settings.direct_mode, parse_direct_mode(direct));
  DDGI_ASSIGN_OR_RETURN(const int64_t light_samples, flags.get_int("light-samples", 1, 1, 64));
  settings.light_samples = static_cast<uint32_t>(light_samples);
  DDGI_ASSIGN_OR_RETURN(const int64_t ao_samples, flags.get_int("ao-samples", 1, 1, 4096));
  settings.ao_samples = static_cast<uint32_t>(ao_samples);
  DDGI_TRY(world_cache_param_table().apply(job.world_cache, flags.get_all("world-cache")));
  DDGI_ASSIGN_OR_RETURN(const std::string tonemap, flags.get_string("tonemap", "aces"));
  DDGI_ASSIGN_OR_RETURN(settings.tonemap, parse_tonemap(tonemap));
  DDGI_ASSIGN_OR_RETURN(job.camera_values, flags.get_doubles("camera", 6, 7));
  return ok_status();
}

Result<RenderJob> parse_job(const Flags& flags) {
  if (flags.positional().size() > 1) {
    return invalid_argument("expected at most one scene argument (see --help)");
  }
  DDGI_ASSIGN_OR_RETURN(const std::string level_text, flags.get_string("log-level", "info"));
  LogLevel level;
  if (!parse_log_level(level_text, &level)) {
    return invalid_argument("--log-level must be debug, info, warning, error or off");
  }
  set_log_level(level);
  RenderJob job;
  job.scene_path = flags.positional().empty() ? default_scene_path() : flags.positional()[0];
  DDGI_ASSIGN_OR_RETURN(job.out_path, flags.get_string("out", "frame.png"));
  DDGI_ASSIGN_OR_RETURN(job.format, encode::format_from_path(job.out_path));
  DDGI_ASSIGN_OR_RETURN(const std::string backend, flags.get_string("backend", "auto"));
  DDGI_TRY(vk::parse_backend(backend));  // refused before the scene loads
  DDGI_ASSIGN_OR_RETURN(job.frames, flags.get_int("frames", 1, 1, 10000));
  DDGI_ASSIGN_OR_RETURN(job.quality, flags.get_int("jpeg-quality", 90, 1, 100));
  DDGI_TRY(parse_frame_flags(flags, job));
  DDGI_ASSIGN_OR_RETURN(const std::string gi, flags.get_string("gi", "on"));
  if (gi != "on" && gi != "off") return invalid_argument("--gi must be on or off");
  job.gi = gi == "on";
  DDGI_ASSIGN_OR_RETURN(job.warmup, flags.get_int("warmup", 128, 0, 100000));
  job.field_assignments = flags.get_all("field");
  job.shadow_assignments = flags.get_all("shadow-field");
  return job;
}

Status write_frame(const RenderJob& job, const FrameResult& frame) {
  if (job.format == encode::ImageFormat::kExr) {
    return encode::write_image(job.out_path,
                               encode::rgb_from_rgba(frame.width, frame.height, frame.radiance));
  }
  encode::WriteOptions write_options;
  write_options.jpeg_quality = static_cast<int>(job.quality);
  return encode::write_image(job.out_path, encode::ImageRgba8{frame.width, frame.height, frame.ldr},
                             write_options);
}

void log_stack(const RenderJob& job, const Scene& scene, const GiStack& gi) {
  LOG_INFO << "scene " << job.scene_path << ": " << gi.scene().triangle_count() << " triangles, "
           << scene.lights.size() << " lights, " << gi.scene().gpu_bytes() / (1 << 20)
           << " MiB on the GPU";
  if (const ShadowField* shadow = gi.shadow_field()) {
    const ShadowFieldParams& p = shadow->params();
    LOG_INFO << "shadow field: " << p.counts.x << "x" << p.counts.y << "x" << p.counts.z
             << " probes, " << p.rays_per_probe << " rays each, " << p.texels << "^2 texels, "
             << shadow->kept_lights() << " of " << scene.lights.size() << " lights kept, "
             << shadow->gpu_bytes() / 1024 << " KiB; " << job.warmup << " warm-up updates";
  }
  if (const IrradianceField* field = gi.field()) {
    const IrradianceFieldParams& p = field->params();
    LOG_INFO << "irradiance field: " << p.counts.x << "x" << p.counts.y << "x" << p.counts.z
             << " probes"
             << (p.cascades > 1 ? " x " + std::to_string(p.cascades) + " cascades" : "") << ", "
             << p.rays_per_probe << "+" << p.fixed_rays << " rays each, "
             << field->gpu_bytes() / 1024 << " KiB; " << job.warmup << " warm-up updates";
    const ProbeStateCounts counts = field->probe_counts();
    LOG_INFO << "probe states: " << counts.vigilant << " vigilant, " << counts.awake << " awake, "
             << counts.sleeping << " sleeping, " << counts.off << " off";
  }
}

// The pass table and the update rates, each field's from its own group's passes only.
void print_times(const RenderJob& job, const tools::PassTable& table, const GiStack& gi) {
  std::printf("%-18s %12s\n", "pass", job.frames > 1 ? "median ms" : "ms");
  double total = 0.0;
  for (const tools::PassTable::Row& row : table.rows()) {
    total += row.median_ms;
    std::printf("%-18s %12.3f\n", row.name.c_str(), row.median_ms);
  }
  std::printf("%-18s %12.3f\n", "total", total);
  const double field_ms = table.group_median(vk::PassGroup::kIrradianceField);
  if (gi.field() && field_ms > 0.0) {
    const uint64_t rays = gi.field()->rays_per_update();
    std::printf("field update: %.3f ms, %llu rays, %.1f Mrays/s\n", field_ms,
                static_cast<unsigned long long>(rays), double(rays) / (field_ms * 1e3));
  }
  const double shadow_ms = table.group_median(vk::PassGroup::kShadowField);
  if (gi.shadow_field() && shadow_ms > 0.0) {
    const uint64_t rays =
        gi.shadow_field()->rays_per_update(gi.shadow_update_mode(job.settings.direct_mode));
    std::printf("shadow field update: %.3f ms, %llu rays, %.1f Mrays/s\n", shadow_ms,
                static_cast<unsigned long long>(rays), double(rays) / (shadow_ms * 1e3));
  }
}

// Builds the GI stack, warms it up, renders the frames (one update each) and writes the last.
Status render_frames(const RenderJob& job, vk::Context& context, const Scene& scene) {
  DDGI_ASSIGN_OR_RETURN(
      const GiStackOptions options,
      fitted_gi_options(scene, job.gi, job.settings.direct_mode, job.field_assignments,
                        job.shadow_assignments, context.default_backend()));
  DDGI_ASSIGN_OR_RETURN(auto gi, GiStack::create(context, scene, options));
  DDGI_ASSIGN_OR_RETURN(
      auto renderer, Renderer::create(context, gi->scene(), gi->field(), context.default_backend(),
                                      gi->shadow_field()));
  DDGI_TRY(renderer->set_world_cache_params(job.world_cache));
  log_stack(job, scene, *gi);
  gi->track(job.settings.camera.position);
  DDGI_TRY(gi->warm_up(static_cast<uint32_t>(job.warmup)));
  FrameResult frame;
  tools::PassTable table;
  for (int64_t i = 0; i < job.frames; ++i) {
    DDGI_ASSIGN_OR_RETURN(const auto update, gi->frame_update(job.settings.direct_mode, {}));
    DDGI_ASSIGN_OR_RETURN(frame, renderer->render(job.settings, update));
    table.add(frame.pass_times);
  }
  DDGI_TRY(write_frame(job, frame));
  std::printf("%s: %ux%u, backend %s, device %s\n", job.out_path.c_str(), frame.width, frame.height,
              vk::backend_name(renderer->backend()), context.caps().device_name.c_str());
  print_times(job, table, *gi);
  if (const WorldCache* cache = renderer->world_cache()) {
    const WorldCacheCounters c = cache->counters();
    std::printf(
        "world cache: %u of %u entries live (%.1f%%); since it was made %u inserted, %u evicted, "
        "%u samples dropped, %u checksum rejects; %.1f MiB\n",
        c.live(), cache->capacity(), 100.0 * c.live() / cache->capacity(), c.inserted, c.evicted,
        c.dropped, c.checksum_rejects, double(cache->gpu_bytes()) / (1 << 20));
  }
  return ok_status();
}

Status run(int argc, char** argv) {
  DDGI_ASSIGN_OR_RETURN(const Flags flags, parse_flags(argc, argv));
  if (printed_help(flags)) return ok_status();
  DDGI_ASSIGN_OR_RETURN(RenderJob job, parse_job(flags));
  DDGI_ASSIGN_OR_RETURN(const Scene scene, tools::load_scene_logged(job.scene_path));
  job.settings.camera = default_camera(scene);
  if (!job.camera_values.empty()) {
    DDGI_ASSIGN_OR_RETURN(job.settings.camera,
                          camera_from_values(job.camera_values, job.settings.camera));
  }
  DDGI_ASSIGN_OR_RETURN(auto context, tools::context_from_flags(flags));
  if (job.reference_spp > 0) {
    ReferenceOptions& reference = job.reference;
    reference.settings.width = job.settings.width;
    reference.settings.height = job.settings.height;
    reference.settings.camera = job.settings.camera;
    reference.samples = static_cast<uint32_t>(job.reference_spp);
    reference.out_path = job.out_path;
    reference.jpeg_quality = static_cast<int>(job.quality);
    reference.tonemap = job.settings.tonemap;
    reference.exposure = job.settings.exposure;
    DDGI_ASSIGN_OR_RETURN(auto gpu_scene, GpuScene::create(*context, scene));
    DDGI_TRY(render_reference(*context, *gpu_scene, context->default_backend(), reference));
  } else {
    DDGI_TRY(render_frames(job, *context, scene));
  }
  return context->no_validation_messages();
}

}  // namespace
}  // namespace ddgi

int main(int argc, char** argv) {
  return ddgi::tools::tool_main("ddgi-render", ddgi::run, argc, argv);
}
