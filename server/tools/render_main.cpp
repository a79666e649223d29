// ddgi-render: renders one frame of a scene without any server and writes it to a file.
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "core/flags.h"
#include "core/log.h"
#include "encode/write_image.h"
#include "gi/field_params.h"
#include "gi/irradiance_field.h"
#include "gi/shadow_params.h"
#include "gpu_scene/camera_fit.h"
#include "gpu_scene/gpu_scene.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "tools/reference_render.h"
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
  --view V              full | direct | indirect | albedo | normal | probes | atlas  [full]
  --direct M            shadow-rays | unshadowed | shadow-field | ao    [shadow-rays]
                        (docs/shadow-field.md)
  --light-samples N     shadow rays per spherical light and pixel, 1..64 [1]
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

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[values.size() / 2];
}

Status run(int argc, char** argv) {
  DDGI_ASSIGN_OR_RETURN(
      Flags flags,
      Flags::parse(
          argc, argv,
          {"out",       "width",        "height",       "camera",       "backend",   "view",
           "direct",    "tonemap",      "exposure",     "jpeg-quality", "frames",    "device",
           "log-level", "gi",           "warmup",       "field",        "reference", "max-bounces",
           "seed",      "shadow-field", "light-samples"},
          {"validation", "help"}));
  if (flags.has("help")) {
    std::fputs(kUsage, stdout);
    return ok_status();
  }
  if (flags.positional().size() > 1) {
    return invalid_argument("expected at most one scene argument (see --help)");
  }
  DDGI_ASSIGN_OR_RETURN(const std::string level_text, flags.get_string("log-level", "info"));
  LogLevel level;
  if (!parse_log_level(level_text, &level)) {
    return invalid_argument("--log-level must be debug, info, warning, error or off");
  }
  set_log_level(level);

  const std::string scene_path =
      flags.positional().empty() ? default_scene_path() : flags.positional()[0];
  DDGI_ASSIGN_OR_RETURN(const std::string out_path, flags.get_string("out", "frame.png"));
  DDGI_ASSIGN_OR_RETURN(const encode::ImageFormat format, encode::format_from_path(out_path));
  DDGI_ASSIGN_OR_RETURN(const std::string backend_text, flags.get_string("backend", "auto"));
  DDGI_ASSIGN_OR_RETURN(const auto forced_backend, vk::parse_backend(backend_text));
  DDGI_ASSIGN_OR_RETURN(const int64_t frames, flags.get_int("frames", 1, 1, 10000));
  DDGI_ASSIGN_OR_RETURN(const int64_t quality, flags.get_int("jpeg-quality", 90, 1, 100));

  FrameSettings settings;
  DDGI_ASSIGN_OR_RETURN(const int64_t width, flags.get_int("width", 640, 1, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t height, flags.get_int("height", 480, 1, 16384));
  settings.width = static_cast<uint32_t>(width);
  settings.height = static_cast<uint32_t>(height);
  DDGI_ASSIGN_OR_RETURN(const double exposure, flags.get_double("exposure", 1.0, 1e-9, 1e9));
  settings.exposure = static_cast<float>(exposure);
  DDGI_ASSIGN_OR_RETURN(const std::string view, flags.get_string("view", "full"));
  DDGI_ASSIGN_OR_RETURN(const int64_t reference_spp, flags.get_int("reference", 0, 0, 1 << 24));
  ReferenceOptions reference;
  if (reference_spp > 0) {
    DDGI_ASSIGN_OR_RETURN(reference.settings.view, parse_path_trace_view(view));
    DDGI_ASSIGN_OR_RETURN(const int64_t bounces, flags.get_int("max-bounces", 64, 0, 1024));
    DDGI_ASSIGN_OR_RETURN(const int64_t seed, flags.get_int("seed", 0, 0, 4294967295));
    reference.settings.max_bounces = static_cast<uint32_t>(bounces);
    reference.settings.seed = static_cast<uint32_t>(seed);
  } else {
    DDGI_ASSIGN_OR_RETURN(settings.view, parse_view(view));
  }
  DDGI_ASSIGN_OR_RETURN(const std::string direct, flags.get_string("direct", "shadow-rays"));
  DDGI_ASSIGN_OR_RETURN(settings.direct_mode, parse_direct_mode(direct));
  DDGI_ASSIGN_OR_RETURN(const int64_t light_samples, flags.get_int("light-samples", 1, 1, 64));
  settings.light_samples = static_cast<uint32_t>(light_samples);
  const std::vector<std::string> shadow_assignments = flags.get_all("shadow-field");
  if (!shadow_assignments.empty() && shadow_assignments.front() == "help") {
    std::fputs(shadow_param_table().help().c_str(), stdout);
    return ok_status();
  }
  DDGI_ASSIGN_OR_RETURN(const std::string tonemap, flags.get_string("tonemap", "aces"));
  DDGI_ASSIGN_OR_RETURN(settings.tonemap, parse_tonemap(tonemap));
  DDGI_ASSIGN_OR_RETURN(const std::vector<double> camera_values, flags.get_doubles("camera", 6, 7));

  DDGI_ASSIGN_OR_RETURN(const std::string gi, flags.get_string("gi", "on"));
  if (gi != "on" && gi != "off") return invalid_argument("--gi must be on or off");
  DDGI_ASSIGN_OR_RETURN(const int64_t warmup, flags.get_int("warmup", 128, 0, 100000));
  const std::vector<std::string> field_assignments = flags.get_all("field");
  if (!field_assignments.empty() && field_assignments.front() == "help") {
    std::fputs(field_param_table().help().c_str(), stdout);
    return ok_status();
  }

  DDGI_ASSIGN_OR_RETURN(const Scene scene, load_scene(scene_path));
  for (const std::string& warning : scene.warnings) LOG_WARNING << scene_path << ": " << warning;
  IrradianceFieldParams field_params = default_field_params(scene);
  DDGI_TRY(field_param_table().apply(field_params, field_assignments));
  ShadowFieldParams shadow_params = fit_shadow_grid(scene.world_bounds());
  DDGI_TRY(shadow_param_table().apply(shadow_params, shadow_assignments));
  settings.camera = default_camera(scene);
  if (!camera_values.empty()) {
    DDGI_ASSIGN_OR_RETURN(settings.camera, camera_from_values(camera_values, settings.camera));
  }

  vk::ContextOptions options;
  options.validation = flags.has("validation");
  DDGI_ASSIGN_OR_RETURN(options.device_filter, flags.get_string("device", ""));
  options.backend = forced_backend;
  DDGI_ASSIGN_OR_RETURN(auto context, vk::Context::create(options));
  DDGI_ASSIGN_OR_RETURN(auto gpu_scene, GpuScene::create(*context, scene));
  if (reference_spp > 0) {
    reference.settings.width = settings.width;
    reference.settings.height = settings.height;
    reference.settings.camera = settings.camera;
    reference.samples = static_cast<uint32_t>(reference_spp);
    reference.out_path = out_path;
    reference.jpeg_quality = static_cast<int>(quality);
    reference.tonemap = settings.tonemap;
    reference.exposure = settings.exposure;
    return render_reference(*context, *gpu_scene, context->default_backend(), reference);
  }
  // The shadow field first: the irradiance field's probe rays read it in its modes. It exists
  // when the frame reads it or the probe rays do (--field probe_direct=...).
  const DirectMode shadow_mode =
      shadow_field_mode(settings.direct_mode, gi == "on" ? &field_params : nullptr);
  std::unique_ptr<ShadowField> shadow_field;
  if (uses_shadow_field(shadow_mode)) {
    DDGI_ASSIGN_OR_RETURN(shadow_field, ShadowField::create(*context, *gpu_scene, shadow_params,
                                                            context->default_backend()));
    const ShadowFieldParams& p = shadow_field->params();
    LOG_INFO << "shadow field: " << p.counts.x << "x" << p.counts.y << "x" << p.counts.z
             << " probes, " << p.rays_per_probe << " rays each, " << p.texels << "^2 texels, "
             << shadow_field->kept_lights() << " of " << scene.lights.size() << " lights kept, "
             << shadow_field->gpu_bytes() / 1024 << " KiB; " << warmup << " warm-up updates";
    const auto warm = shadow_field->update(static_cast<uint32_t>(warmup), shadow_mode);
    if (!warm.ok()) return warm.error();
  }
  std::unique_ptr<IrradianceField> field;
  if (gi == "on") {
    DDGI_ASSIGN_OR_RETURN(field,
                          IrradianceField::create(*context, *gpu_scene, field_params,
                                                  context->default_backend(), shadow_field.get()));
  }
  DDGI_ASSIGN_OR_RETURN(
      auto renderer, Renderer::create(*context, *gpu_scene, field.get(), context->default_backend(),
                                      shadow_field.get()));
  LOG_INFO << "scene " << scene_path << ": " << gpu_scene->triangle_count() << " triangles, "
           << scene.lights.size() << " lights, " << gpu_scene->gpu_bytes() / (1 << 20)
           << " MiB on the GPU";
  if (field) {
    const IrradianceFieldParams& p = field->params();
    LOG_INFO << "irradiance field: " << p.counts.x << "x" << p.counts.y << "x" << p.counts.z
             << " probes, " << p.rays_per_probe << "+" << p.fixed_rays << " rays each, "
             << field->gpu_bytes() / 1024 << " KiB; " << warmup << " warm-up updates";
    const ProbeStateCounts counts = field->probe_counts();
    LOG_INFO << "probe states: " << counts.vigilant << " vigilant, " << counts.awake << " awake, "
             << counts.sleeping << " sleeping, " << counts.off << " off";
    DDGI_TRY(field->warm_up(static_cast<uint32_t>(warmup), settings.direct_mode));
  }

  FrameResult frame;
  std::vector<std::vector<double>> pass_ms;
  for (int64_t i = 0; i < frames; ++i) {
    DDGI_ASSIGN_OR_RETURN(frame, renderer->render(settings));
    pass_ms.resize(frame.pass_times.size());
    for (size_t p = 0; p < frame.pass_times.size(); ++p) {
      pass_ms[p].push_back(frame.pass_times[p].milliseconds);
    }
  }

  if (format == encode::ImageFormat::kExr) {
    encode::ImageRgbF hdr{frame.width, frame.height, {}};
    hdr.rgb.reserve(size_t(frame.width) * frame.height * 3);
    for (size_t i = 0; i < size_t(frame.width) * frame.height; ++i) {
      hdr.rgb.insert(hdr.rgb.end(), &frame.radiance[i * 4], &frame.radiance[i * 4 + 3]);
    }
    DDGI_TRY(encode::write_image(out_path, hdr));
  } else {
    encode::WriteOptions write_options;
    write_options.jpeg_quality = static_cast<int>(quality);
    DDGI_TRY(encode::write_image(out_path, encode::ImageRgba8{frame.width, frame.height, frame.ldr},
                                 write_options));
  }

  std::printf("%s: %ux%u, backend %s, device %s\n", out_path.c_str(), frame.width, frame.height,
              vk::backend_name(renderer->backend()), context->caps().device_name.c_str());
  std::printf("%-18s %12s\n", "pass", frames > 1 ? "median ms" : "ms");
  double total = 0.0, field_ms = 0.0, shadow_ms = 0.0;
  for (size_t p = 0; p < frame.pass_times.size(); ++p) {
    const double ms = median(pass_ms[p]);
    total += ms;
    if (p < 5 && field) field_ms += ms;
    if (frame.pass_times[p].name.rfind("shadow ", 0) == 0) shadow_ms += ms;
    std::printf("%-18s %12.3f\n", frame.pass_times[p].name.c_str(), ms);
  }
  std::printf("%-18s %12.3f\n", "total", total);
  if (field && field_ms > 0.0) {
    std::printf("field update: %.3f ms, %llu rays, %.1f Mrays/s\n", field_ms,
                static_cast<unsigned long long>(field->rays_per_update()),
                double(field->rays_per_update()) / (field_ms * 1e3));
  }
  if (shadow_field && shadow_ms > 0.0) {
    const uint64_t rays = shadow_field->rays_per_update(shadow_mode);
    std::printf("shadow field update: %.3f ms, %llu rays, %.1f Mrays/s\n", shadow_ms,
                static_cast<unsigned long long>(rays), double(rays) / (shadow_ms * 1e3));
  }
  if (context->validation_message_count() > 0) {
    return internal_error(std::to_string(context->validation_message_count()) +
                          " Vulkan validation messages (see above)");
  }
  return ok_status();
}

}  // namespace
}  // namespace ddgi

int main(int argc, char** argv) {
  const ddgi::Status status = ddgi::run(argc, argv);
  if (!status.ok()) {
    std::fprintf(stderr, "ddgi-render: %s\n", status.error().message.c_str());
    return status.error().code == ddgi::ErrorCode::kInvalidArgument ? 2 : 1;
  }
  return 0;
}
