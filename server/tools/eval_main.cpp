// ddgi-eval: image quality of DDGI frames against the path-traced reference, with GPU time.
// For every scene: a reference (full image, and the part the irradiance field must supply:
// everything but punctual direct light), then for every field configuration a warmed-up DDGI
// frame, compared with PSNR, SSIM and FLIP on the tone-mapped images. One markdown table.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
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
#include "tools/pareto.h"
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
of a field update and of the frame's own passes (primary, direct, indirect, tone mapping;
readbacks not included).

  --width N --height N  image size                                     [480 x 270]
  --spp N               reference samples per pixel                    [1024]
  --warmup N            field updates before measuring                 [64]
  --frames N            timed frames per configuration                 [10]
  --configs LIST        NAME:ASSIGNMENTS entries separated by ';', ASSIGNMENTS being
                        comma-separated field parameters (vectors keep their commas), e.g.
                        "default:;no management:classification=false,relocation_iterations=0;
                        dense:counts=12,12,12"
                                                                        [default:]
  --field NAME=VALUE    applied to every configuration first (repeatable)
  --out-dir DIR         also write every reference and frame as EXR there
  --pareto DIR          also time the path tracer at 1, 2, 4, ... --pt-max-spp samples per
                        pixel, and write per scene DIR/SCENE.json (every configuration, the
                        Pareto front of FLIP against GPU ms, each front point's FLIP over the
                        path tracer's at the same ms) and DIR/SCENE.svg (the plot); DIR must
                        exist
  --pt-max-spp N        the path tracer's largest sample count for --pareto      [64]
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
    // Assignments are comma-separated, and so are vector values (counts=8,8,8): a piece with
    // no '=' continues the value before it.
    std::stringstream items(entry.substr(colon + 1));
    std::string item;
    while (std::getline(items, item, ',')) {
      if (item.find('=') != std::string::npos) {
        c.assignments.push_back(item);
      } else if (!c.assignments.empty()) {
        c.assignments.back() += "," + item;
      } else if (!item.empty()) {
        return invalid_argument("--configs entry '" + entry + "': '" + item +
                                "' is not NAME=VALUE");
      }
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

// PSNR, SSIM and FLIP of the tone-mapped images, and the mean linear luminance over the
// reference's.
Result<tools::ImageScores> score(const std::vector<uint8_t>& reference,
                                 const std::vector<float>& reference_radiance,
                                 const std::vector<uint8_t>& test,
                                 const std::vector<float>& test_radiance, uint32_t width,
                                 uint32_t height) {
  const std::vector<float> a = to_unit_rgb(reference), b = to_unit_rgb(test);
  const metrics::RgbImageView va{width, height, a}, vb{width, height, b};
  tools::ImageScores s;
  DDGI_ASSIGN_OR_RETURN(s.psnr, metrics::psnr(va, vb));
  DDGI_ASSIGN_OR_RETURN(s.ssim, metrics::ssim(va, vb));
  DDGI_ASSIGN_OR_RETURN(const metrics::FlipResult f, metrics::flip(va, vb));
  s.flip = f.mean;
  s.mean_ratio = mean_ratio(test_radiance, reference_radiance);
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
  std::string pareto_dir;  // empty: no --pareto
  uint32_t pt_max_spp = 64;
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
  DDGI_ASSIGN_OR_RETURN(job.pareto_dir, flags.get_string("pareto", ""));
  DDGI_ASSIGN_OR_RETURN(const int64_t pt_max_spp, flags.get_int("pt-max-spp", 64, 1, 65536));
  job.pt_max_spp = static_cast<uint32_t>(pt_max_spp);
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
Result<tools::ConfigPoint> evaluate_config(vk::Context& context, const EvalJob& job,
                                           const Scene& scene, const std::string& stem,
                                           const ReferencePair& refs, const Config& config) {
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
  // Frames (without field updates) for half a second before timing: scoring the previous
  // configuration on the CPU left the GPU idle for seconds and its clocks low (the H200 timed a
  // scene's first configuration at 0.8 ms per frame and the next ones at 4-6 ms without this).
  settings.read_radiance = false;
  const auto warm_until = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
  settings.view = View::kFull;
  while (std::chrono::steady_clock::now() < warm_until) {
    DDGI_TRY(renderer->render(settings));  // no field update: the field stays as warmed up
  }
  tools::PassTable table;
  FrameResult full;
  for (int64_t f = 0; f < job.frames; ++f) {
    // Only the last frame is scored: the others skip the 16-bytes-per-pixel HDR readback, whose
    // host copies would leave the GPU idle (and its clocks falling) between timed frames.
    settings.read_radiance = f + 1 == job.frames;
    DDGI_ASSIGN_OR_RETURN(full, frame(View::kFull));
    table.add(full.pass_times);
  }
  settings.read_radiance = true;
  DDGI_ASSIGN_OR_RETURN(const FrameResult indirect, frame(View::kIndirect));
  tools::ConfigPoint point{config.name, assignments};
  DDGI_ASSIGN_OR_RETURN(point.full, score(refs.full.ldr, refs.full.radiance, full.ldr,
                                          full.radiance, job.width, job.height));
  DDGI_ASSIGN_OR_RETURN(point.indirect, score(refs.second.ldr, refs.second.radiance, indirect.ldr,
                                              indirect.radiance, job.width, job.height));
  point.field_ms = table.group_median(vk::PassGroup::kIrradianceField);
  point.frame_ms = table.group_median(vk::PassGroup::kFrame);
  point.field_mib = double(field_gpu_bytes(gi->field()->params())) / (1024.0 * 1024.0);
  std::string tag = config.name;
  std::replace(tag.begin(), tag.end(), ' ', '-');
  DDGI_TRY(write_exr(job.out_dir, stem + "." + tag, job.width, job.height, full.radiance));
  DDGI_TRY(write_exr(job.out_dir, stem + "." + tag + "-indirect", job.width, job.height,
                     indirect.radiance));
  const ProbeStateCounts c = gi->field()->probe_counts();
  const tools::ImageScores &f = point.full, &i = point.indirect;
  std::printf(
      "| %s | %s | %llu / %llu / %llu | %.2f | %.4f | %.4f | %.3f | %.2f | %.4f | %.4f | %.3f | "
      "%.3f | %.3f |\n",
      stem.c_str(), config.name.c_str(), static_cast<unsigned long long>(c.active()),
      static_cast<unsigned long long>(c.sleeping), static_cast<unsigned long long>(c.off), f.psnr,
      f.ssim, f.flip, f.mean_ratio, i.psnr, i.ssim, i.flip, i.mean_ratio, point.field_ms,
      point.frame_ms);
  std::fflush(stdout);
  return point;
}

// The equal-time baseline: the path tracer at 1, 2, 4, ... job.pt_max_spp samples per pixel
// (pixel centres, as the frames and the reference), each image made --frames times (the median
// GPU time counts) and the last scored against the reference.
Result<std::vector<tools::PathTracePoint>> path_trace_curve(vk::Context& context,
                                                            const EvalJob& job, const Scene& scene,
                                                            const ReferencePair& refs) {
  DDGI_ASSIGN_OR_RETURN(auto gpu, GpuScene::create(context, scene));
  DDGI_ASSIGN_OR_RETURN(auto tracer, PathTracer::create(context, *gpu, context.default_backend()));
  // Untimed images first, so the GPU's clocks are up when timing starts.
  for (int warm = 0; warm < 4; ++warm) DDGI_TRY(tracer->accumulate(refs.settings, 4));
  std::vector<tools::PathTracePoint> curve;
  for (uint32_t spp = 1; spp <= job.pt_max_spp; spp *= 2) {
    std::vector<double> times;  // one image per timed frame; the median counts
    for (int64_t run = 0; run < job.frames; ++run) {
      tracer->reset();
      DDGI_TRY(tracer->accumulate(refs.settings, spp));
      times.push_back(tracer->last_accumulate_ms());
    }
    std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
    const double ms = times[times.size() / 2];
    DDGI_ASSIGN_OR_RETURN(const PathTraceImage image, tracer->read(Tonemap::kAces, refs.exposure));
    DDGI_ASSIGN_OR_RETURN(
        const tools::ImageScores scores,
        score(refs.full.ldr, refs.full.radiance, image.ldr, image.radiance, job.width, job.height));
    curve.push_back({spp, ms, scores});
  }
  return curve;
}

// After the table: per scene, each front point against the path tracer: its FLIP at the same
// ms, and the ms it needs for the same FLIP ("-": outside the traced spp range).
void print_fronts(const std::vector<tools::SceneTrade>& trades) {
  std::printf(
      "\n| scene | front point | GPU ms | FLIP | path tracing FLIP, same ms | ratio | path "
      "tracing ms, same FLIP |\n|---|---|---|---|---|---|---|\n");
  auto text = [](std::optional<double> value) {
    char buffer[32] = "-";
    if (value) std::snprintf(buffer, sizeof(buffer), "%.4g", *value);
    return std::string(buffer);
  };
  for (const tools::SceneTrade& trade : trades) {
    for (size_t i : tools::pareto_front(trade.configs)) {
      const tools::ConfigPoint& c = trade.configs[i];
      const std::optional<double> traced =
          tools::path_trace_flip_at(trade.path_tracing, c.total_ms());
      const std::optional<double> ratio =
          traced && *traced > 0.0 ? std::optional<double>(c.full.flip / *traced) : std::nullopt;
      std::printf("| %s | %s | %.3f | %.4f | %s | %s | %s |\n", trade.scene.c_str(), c.name.c_str(),
                  c.total_ms(), c.full.flip, text(traced).c_str(), text(ratio).c_str(),
                  text(tools::path_trace_ms_for(trade.path_tracing, c.full.flip)).c_str());
    }
  }
}

Status run(int argc, char** argv) {
  DDGI_ASSIGN_OR_RETURN(
      Flags flags, Flags::parse(argc, argv,
                                {"width", "height", "spp", "warmup", "frames", "configs", "field",
                                 "out-dir", "backend", "pareto", "pt-max-spp"},
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
  std::vector<tools::SceneTrade> trades;
  for (const std::string& scene_path : flags.positional()) {
    DDGI_ASSIGN_OR_RETURN(const Scene scene, load_scene(scene_path));
    const std::string stem = tools::file_stem(scene_path);
    DDGI_ASSIGN_OR_RETURN(const ReferencePair refs, make_references(*context, job, scene, stem));
    tools::SceneTrade trade{stem, job.width, job.height, static_cast<uint32_t>(job.spp), {}, {}};
    for (const Config& config : job.configs) {
      DDGI_ASSIGN_OR_RETURN(tools::ConfigPoint point,
                            evaluate_config(*context, job, scene, stem, refs, config));
      trade.configs.push_back(std::move(point));
    }
    if (job.pareto_dir.empty()) continue;
    DDGI_ASSIGN_OR_RETURN(trade.path_tracing, path_trace_curve(*context, job, scene, refs));
    DDGI_TRY(tools::write_scene_trade(trade, job.pareto_dir));
    trades.push_back(std::move(trade));
  }
  if (!trades.empty()) print_fronts(trades);
  return ok_status();
}

}  // namespace
}  // namespace ddgi

int main(int argc, char** argv) {
  return ddgi::tools::tool_main("ddgi-eval", ddgi::run, argc, argv);
}
