// ddgi-eval: image quality of DDGI frames against the path-traced reference, with GPU time.
// For every scene: a reference (full image, and the part the irradiance field must supply:
// everything but punctual direct light), then for every field configuration a warmed-up DDGI
// frame, compared with PSNR, SSIM and FLIP on the tone-mapped images. One markdown table.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "core/flags.h"
#include "core/log.h"
#include "encode/write_image.h"
#include "gi/field_params.h"
#include "gi/irradiance_field.h"
#include "gpu_scene/camera_fit.h"
#include "gpu_scene/gpu_scene.h"
#include "metrics/flip.h"
#include "metrics/pixel_error.h"
#include "metrics/ssim.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "vk/context.h"

namespace ddgi {
namespace {

constexpr const char* kUsage = R"(usage: ddgi-eval SCENE... [flags]

Measures DDGI frames against the path-traced reference. For each SCENE: path-trace the full
image and its field part (everything but punctual direct light) with --spp samples; then for
each configuration, warm a field up, render the full and the indirect view, and print PSNR,
SSIM and mean FLIP (on the tone-mapped images, one exposure per scene chosen from the
reference so its log-average luminance maps to 0.18) and the median GPU ms of a frame.

  --width N --height N  image size                                     [480 x 270]
  --spp N               reference samples per pixel                    [1024]
  --warmup N            field updates before measuring                 [64]
  --frames N            timed frames per configuration                 [10]
  --configs LIST        NAME:ASSIGNMENTS entries separated by ';', ASSIGNMENTS being
                        comma-separated field parameters, e.g.
                        "default:;no management:classification=false,relocation_iterations=0"
                                                                        [default:]
  --field NAME=VALUE    applied to every configuration first (repeatable)
  --out-dir DIR         also write every reference and frame as EXR there
  --backend B           auto | query | pipeline                         [auto]
)";

struct Config {
  std::string name;
  std::vector<std::string> assignments;
};

Result<std::vector<Config>> parse_configs(const std::string& text) {
  std::vector<Config> configs;
  std::stringstream entries(text);
  std::string entry;
  while (std::getline(entries, entry, ';')) {
    if (entry.empty()) continue;
    const size_t colon = entry.find(':');
    if (colon == std::string::npos || colon == 0) {
      return invalid_argument("--configs entry '" + entry + "' is not NAME:ASSIGNMENTS");
    }
    Config c{entry.substr(0, colon), {}};
    std::stringstream items(entry.substr(colon + 1));
    std::string item;
    while (std::getline(items, item, ',')) {
      if (!item.empty()) c.assignments.push_back(item);
    }
    configs.push_back(c);
  }
  if (configs.empty()) return invalid_argument("--configs names no configuration");
  return configs;
}

// sRGB-encoded [0,1] floats from RGBA8, the form the metrics take.
std::vector<float> to_unit_rgb(const std::vector<uint8_t>& rgba) {
  std::vector<float> rgb;
  rgb.reserve(rgba.size() / 4 * 3);
  for (size_t i = 0; i < rgba.size(); i += 4) {
    for (int c = 0; c < 3; ++c) rgb.push_back(rgba[i + c] / 255.0f);
  }
  return rgb;
}

// Exposure that maps the log-average luminance of `radiance` (RGBA) to 0.18.
float auto_exposure(const std::vector<float>& radiance) {
  double log_sum = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < radiance.size(); i += 4) {
    const double y = 0.2126 * radiance[i] + 0.7152 * radiance[i + 1] + 0.0722 * radiance[i + 2];
    log_sum += std::log(1e-6 + y);
    ++n;
  }
  const double average = n ? std::exp(log_sum / n) : 1.0;
  return static_cast<float>(std::clamp(0.18 / average, 1e-6, 1e6));
}

struct Scores {
  double psnr = 0.0, ssim = 0.0, flip = 0.0;
};

Result<Scores> score(const std::vector<uint8_t>& reference, const std::vector<uint8_t>& test,
                     uint32_t width, uint32_t height) {
  const std::vector<float> a = to_unit_rgb(reference), b = to_unit_rgb(test);
  const metrics::RgbImageView va{width, height, a}, vb{width, height, b};
  Scores s;
  DDGI_ASSIGN_OR_RETURN(s.psnr, metrics::psnr(va, vb));
  DDGI_ASSIGN_OR_RETURN(s.ssim, metrics::ssim(va, vb));
  DDGI_ASSIGN_OR_RETURN(const metrics::FlipResult f, metrics::flip(va, vb));
  s.flip = f.mean;
  return s;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

Status write_exr(const std::string& dir, const std::string& name, uint32_t width, uint32_t height,
                 const std::vector<float>& rgba) {
  if (dir.empty()) return ok_status();
  encode::ImageRgbF image{width, height, {}};
  for (size_t i = 0; i < rgba.size(); i += 4)
    image.rgb.insert(image.rgb.end(), &rgba[i], &rgba[i + 3]);
  return encode::write_image(dir + "/" + name + ".exr", image);
}

std::string file_stem(const std::string& path) {
  std::string name = path.substr(path.find_last_of('/') + 1);
  return name.substr(0, name.find('.'));
}

Status run(int argc, char** argv) {
  DDGI_ASSIGN_OR_RETURN(Flags flags, Flags::parse(argc, argv,
                                                  {"width", "height", "spp", "warmup", "frames",
                                                   "configs", "field", "out-dir", "backend"},
                                                  {"help"}));
  if (flags.has("help") || flags.positional().empty()) {
    std::fputs(kUsage, stdout);
    return flags.has("help") ? ok_status() : invalid_argument("no scene given");
  }
  set_log_level(LogLevel::kWarning);
  DDGI_ASSIGN_OR_RETURN(const int64_t width, flags.get_int("width", 480, 11, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t height, flags.get_int("height", 270, 11, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t spp, flags.get_int("spp", 1024, 1, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(const int64_t warmup, flags.get_int("warmup", 64, 0, 100000));
  DDGI_ASSIGN_OR_RETURN(const int64_t frames, flags.get_int("frames", 10, 1, 10000));
  DDGI_ASSIGN_OR_RETURN(const std::string configs_text, flags.get_string("configs", "default:"));
  DDGI_ASSIGN_OR_RETURN(const std::vector<Config> configs, parse_configs(configs_text));
  DDGI_ASSIGN_OR_RETURN(const std::string out_dir, flags.get_string("out-dir", ""));
  DDGI_ASSIGN_OR_RETURN(const std::string backend_text, flags.get_string("backend", "auto"));
  DDGI_ASSIGN_OR_RETURN(const auto forced_backend, vk::parse_backend(backend_text));

  vk::ContextOptions options;
  options.backend = forced_backend;
  DDGI_ASSIGN_OR_RETURN(auto context, vk::Context::create(options));
  const vk::TraceBackend backend = context->default_backend();
  std::printf("device: %s, backend %s, %lldx%lld, reference %lld spp, %lld warm-up updates\n\n",
              context->caps().device_name.c_str(), vk::backend_name(backend),
              static_cast<long long>(width), static_cast<long long>(height),
              static_cast<long long>(spp), static_cast<long long>(warmup));
  std::printf(
      "| scene | configuration | probes traced / sleeping / off | full: PSNR | SSIM | FLIP | "
      "indirect: PSNR | SSIM | FLIP | field ms | frame ms |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n");

  for (const std::string& scene_path : flags.positional()) {
    DDGI_ASSIGN_OR_RETURN(const Scene scene, load_scene(scene_path));
    DDGI_ASSIGN_OR_RETURN(auto gpu_scene, GpuScene::create(*context, scene));
    const std::string stem = file_stem(scene_path);
    PathTraceSettings pt;
    pt.width = static_cast<uint32_t>(width);
    pt.height = static_cast<uint32_t>(height);
    pt.camera = default_camera(scene);
    pt.jitter = false;  // the DDGI frame traces pixel centres too
    DDGI_ASSIGN_OR_RETURN(auto tracer, PathTracer::create(*context, *gpu_scene, backend));
    // The full reference first: it sets the exposure both references are tone-mapped with.
    auto accumulate = [&](PathTraceView view) -> Status {
      pt.view = view;
      for (int64_t done = 0; done < spp;) {
        const uint32_t batch = static_cast<uint32_t>(std::min<int64_t>(64, spp - done));
        DDGI_TRY(tracer->accumulate(pt, batch));
        done += batch;
      }
      return ok_status();
    };
    PathTraceImage references[2];
    DDGI_TRY(accumulate(PathTraceView::kFull));
    DDGI_ASSIGN_OR_RETURN(const PathTraceImage linear, tracer->read(Tonemap::kAces, 1.0f));
    const float exposure = auto_exposure(linear.radiance);
    DDGI_ASSIGN_OR_RETURN(references[0], tracer->read(Tonemap::kAces, exposure));
    DDGI_TRY(accumulate(PathTraceView::kFieldIndirect));
    DDGI_ASSIGN_OR_RETURN(references[1], tracer->read(Tonemap::kAces, exposure));
    DDGI_TRY(write_exr(out_dir, stem + ".reference", pt.width, pt.height, references[0].radiance));
    DDGI_TRY(write_exr(out_dir, stem + ".reference-indirect", pt.width, pt.height,
                       references[1].radiance));

    for (const Config& config : configs) {
      IrradianceFieldParams params = default_field_params(scene);
      DDGI_TRY(field_param_table().apply(params, flags.get_all("field")));
      DDGI_TRY(field_param_table().apply(params, config.assignments));
      DDGI_ASSIGN_OR_RETURN(auto field,
                            IrradianceField::create(*context, *gpu_scene, params, backend));
      DDGI_ASSIGN_OR_RETURN(auto renderer,
                            Renderer::create(*context, *gpu_scene, field.get(), backend));
      DDGI_TRY(field->warm_up(static_cast<uint32_t>(warmup), DirectMode::kTracedShadows));
      FrameSettings settings;
      settings.width = pt.width;
      settings.height = pt.height;
      settings.camera = pt.camera;
      settings.exposure = exposure;
      std::vector<double> field_ms, frame_ms;
      FrameResult full, indirect;
      for (int64_t f = 0; f < frames; ++f) {
        settings.view = View::kFull;
        DDGI_ASSIGN_OR_RETURN(full, renderer->render(settings));
        double field_total = 0.0, frame_total = 0.0;
        for (const vk::PassTime& t : full.pass_times) {
          const bool field_pass =
              t.name.rfind("field", 0) == 0 || t.name.rfind("blend", 0) == 0 || t.name == "borders";
          (field_pass ? field_total : frame_total) += t.milliseconds;
        }
        field_ms.push_back(field_total);
        frame_ms.push_back(frame_total);
      }
      settings.view = View::kIndirect;
      DDGI_ASSIGN_OR_RETURN(indirect, renderer->render(settings));
      DDGI_ASSIGN_OR_RETURN(const Scores s_full,
                            score(references[0].ldr, full.ldr, pt.width, pt.height));
      DDGI_ASSIGN_OR_RETURN(const Scores s_ind,
                            score(references[1].ldr, indirect.ldr, pt.width, pt.height));
      std::string tag = config.name;
      std::replace(tag.begin(), tag.end(), ' ', '-');
      DDGI_TRY(write_exr(out_dir, stem + "." + tag, pt.width, pt.height, full.radiance));
      DDGI_TRY(write_exr(out_dir, stem + "." + tag + "-indirect", pt.width, pt.height,
                         indirect.radiance));
      const ProbeStateCounts c = field->probe_counts();
      std::printf(
          "| %s | %s | %llu / %llu / %llu | %.2f | %.4f | %.4f | %.2f | %.4f | %.4f | %.3f | "
          "%.3f |\n",
          stem.c_str(), config.name.c_str(), static_cast<unsigned long long>(c.active()),
          static_cast<unsigned long long>(c.sleeping), static_cast<unsigned long long>(c.off),
          s_full.psnr, s_full.ssim, s_full.flip, s_ind.psnr, s_ind.ssim, s_ind.flip,
          median(field_ms), median(frame_ms));
      std::fflush(stdout);
    }
  }
  return ok_status();
}

}  // namespace
}  // namespace ddgi

int main(int argc, char** argv) {
  const ddgi::Status status = ddgi::run(argc, argv);
  if (!status.ok()) {
    std::fprintf(stderr, "ddgi-eval: %s\n", status.error().message.c_str());
    return 2;
  }
  return 0;
}
