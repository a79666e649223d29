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
#include "gi/gi_stack.h"
#include "gpu_scene/camera_fit.h"
#include "gpu_scene/gpu_scene.h"
#include "metrics/flip.h"
#include "metrics/pixel_error.h"
#include "metrics/ssim.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "tools/reference_render.h"
#include "tools/tool_support.h"
#include "vk/context.h"

namespace ddgi {
namespace {

constexpr const char* kUsage = R"(usage: ddgi-eval SCENE... [flags]

Measures DDGI frames against the path-traced reference. For each SCENE: path-trace the full
image and its field part (everything but punctual direct light) with --spp samples; then for
each configuration, warm a field up, render the full and the indirect view, and print PSNR,
SSIM and mean FLIP (on the tone-mapped images, one exposure per scene chosen from the
reference so its log-average luminance maps to 0.18), the mean linear luminance over the
reference's ("mean/ref": 1 when the field neither loses nor adds light) and the median GPU ms
of a frame.

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

// Mean Rec. 709 luminance of linear RGBA radiance.
double mean_luminance(const std::vector<float>& rgba) {
  double sum = 0.0;
  for (size_t i = 0; i < rgba.size(); i += 4) {
    sum += 0.2126 * rgba[i] + 0.7152 * rgba[i + 1] + 0.0722 * rgba[i + 2];
  }
  return rgba.empty() ? 0.0 : sum / double(rgba.size() / 4);
}

double mean_ratio(const std::vector<float>& test, const std::vector<float>& reference) {
  const double ref = mean_luminance(reference);
  return ref > 0.0 ? mean_luminance(test) / ref : 0.0;
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

Status write_exr(const std::string& dir, const std::string& name, uint32_t width, uint32_t height,
                 const std::vector<float>& rgba) {
  if (dir.empty()) return ok_status();
  return encode::write_image(dir + "/" + name + ".exr", encode::rgb_from_rgba(width, height, rgba));
}

// What the flags ask for.
struct EvalJob {
  uint32_t width = 480, height = 270;
  int64_t spp = 1024;
  int64_t warmup = 64;
  int64_t frames = 10;
  std::vector<Config> configs;
  std::vector<std::string> field_assignments;  // before every configuration's own
  std::string out_dir;
};

Result<EvalJob> parse_job(const Flags& flags) {
  EvalJob job;
  DDGI_ASSIGN_OR_RETURN(const int64_t width, flags.get_int("width", 480, 11, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t height, flags.get_int("height", 270, 11, 16384));
  job.width = static_cast<uint32_t>(width);
  job.height = static_cast<uint32_t>(height);
  DDGI_ASSIGN_OR_RETURN(job.spp, flags.get_int("spp", 1024, 1, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(job.warmup, flags.get_int("warmup", 64, 0, 100000));
  DDGI_ASSIGN_OR_RETURN(job.frames, flags.get_int("frames", 10, 1, 10000));
  DDGI_ASSIGN_OR_RETURN(const std::string configs_text, flags.get_string("configs", "default:"));
  DDGI_ASSIGN_OR_RETURN(job.configs, parse_configs(configs_text));
  DDGI_ASSIGN_OR_RETURN(job.out_dir, flags.get_string("out-dir", ""));
  job.field_assignments = flags.get_all("field");
  return job;
}

Result<ReferencePair> make_references(vk::Context& context, const EvalJob& job, const Scene& scene,
                                      const std::string& stem) {
  ReferencePairOptions options;
  options.width = job.width;
  options.height = job.height;
  options.camera = default_camera(scene);
  options.full_spp = options.second_spp = static_cast<uint32_t>(job.spp);
  options.second_view = PathTraceView::kFieldIndirect;
  options.exposure = auto_exposure;
  DDGI_ASSIGN_OR_RETURN(ReferencePair refs, reference_pair(context, scene, options));
  DDGI_TRY(write_exr(job.out_dir, stem + ".reference", job.width, job.height, refs.full.radiance));
  DDGI_TRY(write_exr(job.out_dir, stem + ".reference-indirect", job.width, job.height,
                     refs.second.radiance));
  return refs;
}

// One table row: a warmed-up field of `config`, `frames` timed full frames (one update each),
// then the indirect view, both scored against the references.
Status evaluate_config(vk::Context& context, const EvalJob& job, const Scene& scene,
                       const std::string& stem, const ReferencePair& refs, const Config& config) {
  std::vector<std::string> assignments = job.field_assignments;
  assignments.insert(assignments.end(), config.assignments.begin(), config.assignments.end());
  DDGI_ASSIGN_OR_RETURN(const GiStackOptions options,
                        fitted_gi_options(scene, true, DirectMode::kTracedShadows, assignments, {},
                                          context.default_backend()));
  DDGI_ASSIGN_OR_RETURN(auto gi, GiStack::create(context, scene, options));
  DDGI_ASSIGN_OR_RETURN(auto renderer, Renderer::create(context, gi->scene(), gi->field(),
                                                        context.default_backend()));
  DDGI_TRY(gi->warm_up(static_cast<uint32_t>(job.warmup)));
  FrameSettings settings;
  settings.width = job.width;
  settings.height = job.height;
  settings.camera = refs.settings.camera;
  settings.exposure = refs.exposure;
  auto frame = [&](View view) -> Result<FrameResult> {
    settings.view = view;
    DDGI_ASSIGN_OR_RETURN(const auto update, gi->frame_update(settings.direct_mode, {}));
    return renderer->render(settings, update);
  };
  tools::PassTable table;
  FrameResult full;
  for (int64_t f = 0; f < job.frames; ++f) {
    DDGI_ASSIGN_OR_RETURN(full, frame(View::kFull));
    table.add(full.pass_times);
  }
  DDGI_ASSIGN_OR_RETURN(const FrameResult indirect, frame(View::kIndirect));
  DDGI_ASSIGN_OR_RETURN(const Scores s_full, score(refs.full.ldr, full.ldr, job.width, job.height));
  DDGI_ASSIGN_OR_RETURN(const Scores s_ind,
                        score(refs.second.ldr, indirect.ldr, job.width, job.height));
  std::string tag = config.name;
  std::replace(tag.begin(), tag.end(), ' ', '-');
  DDGI_TRY(write_exr(job.out_dir, stem + "." + tag, job.width, job.height, full.radiance));
  DDGI_TRY(write_exr(job.out_dir, stem + "." + tag + "-indirect", job.width, job.height,
                     indirect.radiance));
  const ProbeStateCounts c = gi->field()->probe_counts();
  std::printf(
      "| %s | %s | %llu / %llu / %llu | %.2f | %.4f | %.4f | %.3f | %.2f | %.4f | %.4f | %.3f | "
      "%.3f | %.3f |\n",
      stem.c_str(), config.name.c_str(), static_cast<unsigned long long>(c.active()),
      static_cast<unsigned long long>(c.sleeping), static_cast<unsigned long long>(c.off),
      s_full.psnr, s_full.ssim, s_full.flip, mean_ratio(full.radiance, refs.full.radiance),
      s_ind.psnr, s_ind.ssim, s_ind.flip, mean_ratio(indirect.radiance, refs.second.radiance),
      table.group_median(vk::PassGroup::kIrradianceField),
      table.others_median(vk::PassGroup::kIrradianceField));
  std::fflush(stdout);
  return ok_status();
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
  DDGI_ASSIGN_OR_RETURN(const EvalJob job, parse_job(flags));
  DDGI_ASSIGN_OR_RETURN(auto context, tools::context_from_flags(flags));
  std::printf("device: %s, backend %s, %ux%u, reference %lld spp, %lld warm-up updates\n\n",
              context->caps().device_name.c_str(), vk::backend_name(context->default_backend()),
              job.width, job.height, static_cast<long long>(job.spp),
              static_cast<long long>(job.warmup));
  std::printf(
      "| scene | configuration | probes traced / sleeping / off | full: PSNR | SSIM | FLIP | "
      "mean/ref | indirect: PSNR | SSIM | FLIP | mean/ref | field ms | frame ms |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& scene_path : flags.positional()) {
    DDGI_ASSIGN_OR_RETURN(const Scene scene, load_scene(scene_path));
    const std::string stem = tools::file_stem(scene_path);
    DDGI_ASSIGN_OR_RETURN(const ReferencePair refs, make_references(*context, job, scene, stem));
    for (const Config& config : job.configs) {
      DDGI_TRY(evaluate_config(*context, job, scene, stem, refs, config));
    }
  }
  return ok_status();
}

}  // namespace
}  // namespace ddgi

int main(int argc, char** argv) {
  return ddgi::tools::tool_main("ddgi-eval", ddgi::run, argc, argv);
}
