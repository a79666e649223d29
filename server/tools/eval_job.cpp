// ddgi-eval's shared parts: the flags a job is made of, the field configurations it compares,
// and how a frame is scored against its reference (see eval_job.h).
#include "tools/eval_job.h"
#include "tools/field_budget.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string_view>

#include "encode/write_image.h"
#include "metrics/flip.h"
#include "metrics/pixel_error.h"
#include "metrics/ssim.h"

namespace ddgi::tools {
namespace {

// sRGB-encoded [0,1] floats from RGBA8, the form the metrics take.
std::vector<float> to_unit_rgb(const std::vector<uint8_t>& rgba) {
  std::vector<float> rgb;
  rgb.reserve(rgba.size() / 4 * 3);
  for (size_t i = 0; i < rgba.size(); i += 4) {
    for (int c = 0; c < 3; ++c) rgb.push_back(rgba[i + c] / 255.0f);
  }
  return rgb;
}

// A configuration's shadow field parameters are named with this in front ("shadow.texels=8").
constexpr std::string_view kShadowPrefix = "shadow.";

// Sorts one "name=value" of a configuration: a choice of the frame's (direct=, frame_downscale=,
// shadow.NAME=) or a field assignment, checked later by the field's parameter table.
Status add_assignment(Config& config, const std::string& assignment) {
  const size_t equals = assignment.find('=');
  const std::string name = assignment.substr(0, equals), value = assignment.substr(equals + 1);
  const std::string context = "--configs '" + config.name + "'";
  if (name == "direct") {
    Result<DirectMode> mode = parse_direct_mode(value);
    if (!mode.ok()) return mode.error().with_context(context);
    config.direct_mode = *mode;
  } else if (name == "frame_downscale") {
    char* end = nullptr;
    const long n = std::strtol(value.c_str(), &end, 10);
    if (value.empty() || *end != '\0' || n < 1 || n > 8) {
      return invalid_argument(
          context + ": frame_downscale must be a whole number in [1, 8] (got '" + value + "')");
    }
    config.frame_downscale = static_cast<uint32_t>(n);
  } else if (name.starts_with(kShadowPrefix)) {
    config.shadow_assignments.push_back(assignment.substr(kShadowPrefix.size()));
  } else {
    config.assignments.push_back(assignment);
  }
  return ok_status();
}

// A smaller frame is made only for the table and --pareto (the references of --dynamic and
// --path are compared with every frame as drawn), at a size it divides into at least 8 pixels.
Status check_frame_downscale(const EvalJob& job, const Config& config) {
  const uint32_t n = config.frame_downscale;
  if (n == 1) return ok_status();
  const std::string context =
      "--configs '" + config.name + "': frame_downscale=" + std::to_string(n);
  if (!job.dynamic.empty() || !job.camera_path.empty()) {
    return invalid_argument(context + " is for the table and --pareto, not --dynamic or --path");
  }
  if (job.width % n != 0 || job.height % n != 0 || job.width / n < 8 || job.height / n < 8) {
    return invalid_argument(context + " must divide --width " + std::to_string(job.width) +
                            " and --height " + std::to_string(job.height) +
                            " into at least 8 pixels each");
  }
  return ok_status();
}

}  // namespace

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

std::vector<std::string> Config::all_assignments() const {
  std::vector<std::string> all = assignments;
  for (const std::string& a : shadow_assignments) all.push_back(std::string(kShadowPrefix) + a);
  if (direct_mode != DirectMode::kTracedShadows) {
    all.push_back(std::string("direct=") + direct_mode_name(direct_mode));
  }
  if (frame_downscale != 1) all.push_back("frame_downscale=" + std::to_string(frame_downscale));
  return all;
}

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
    // Assignments are comma-separated, and so are vector values (counts=8,8,8): a piece with
    // no '=' continues the value before it.
    std::vector<std::string> assignments;
    std::stringstream items(entry.substr(colon + 1));
    std::string item;
    while (std::getline(items, item, ',')) {
      if (item.find('=') != std::string::npos) {
        assignments.push_back(item);
      } else if (!assignments.empty()) {
        assignments.back() += "," + item;
      } else if (!item.empty()) {
        return invalid_argument("--configs entry '" + entry + "': '" + item +
                                "' is not NAME=VALUE");
      }
    }
    Config c{entry.substr(0, colon), {}};
    for (const std::string& a : assignments) DDGI_TRY(add_assignment(c, a));
    configs.push_back(c);
  }
  if (configs.empty()) return invalid_argument("--configs names no configuration");
  return configs;
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

// PSNR, SSIM and FLIP of the tone-mapped images, and the mean linear luminance over the
// reference's.
Result<ImageScores> score_ldr(const std::vector<uint8_t>& reference,
                              const std::vector<uint8_t>& test, uint32_t width, uint32_t height) {
  const std::vector<float> a = to_unit_rgb(reference), b = to_unit_rgb(test);
  const metrics::RgbImageView va{width, height, a}, vb{width, height, b};
  ImageScores s;
  DDGI_ASSIGN_OR_RETURN(s.psnr, metrics::psnr(va, vb));
  DDGI_ASSIGN_OR_RETURN(s.ssim, metrics::ssim(va, vb));
  DDGI_ASSIGN_OR_RETURN(const metrics::FlipResult f, metrics::flip(va, vb));
  s.flip = f.mean;
  return s;
}

Result<ImageScores> score(const std::vector<uint8_t>& reference,
                          const std::vector<float>& reference_radiance,
                          const std::vector<uint8_t>& test, const std::vector<float>& test_radiance,
                          uint32_t width, uint32_t height) {
  DDGI_ASSIGN_OR_RETURN(ImageScores s, score_ldr(reference, test, width, height));
  s.mean_ratio = mean_ratio(test_radiance, reference_radiance);
  return s;
}

Status write_exr(const std::string& dir, const std::string& name, uint32_t width, uint32_t height,
                 const std::vector<float>& rgba) {
  if (dir.empty()) return ok_status();
  return encode::write_image(dir + "/" + name + ".exr", encode::rgb_from_rgba(width, height, rgba));
}

Result<EvalJob> parse_job(const Flags& flags) {
  EvalJob job;
  DDGI_ASSIGN_OR_RETURN(const int64_t width, flags.get_int("width", 480, 11, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t height, flags.get_int("height", 270, 11, 16384));
  job.width = static_cast<uint32_t>(width);
  job.height = static_cast<uint32_t>(height);
  DDGI_ASSIGN_OR_RETURN(job.spp, flags.get_int("spp", 1024, 1, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(job.warmup, flags.get_int("warmup", kConvergedWarmupUpdates, 0, 100000));
  DDGI_ASSIGN_OR_RETURN(job.frames, flags.get_int("frames", 10, 1, 10000));
  DDGI_ASSIGN_OR_RETURN(const std::string configs_text, flags.get_string("configs", "default:"));
  DDGI_ASSIGN_OR_RETURN(job.configs, parse_configs(configs_text));
  DDGI_ASSIGN_OR_RETURN(job.out_dir, flags.get_string("out-dir", ""));
  DDGI_ASSIGN_OR_RETURN(job.pareto_dir, flags.get_string("pareto", ""));
  DDGI_ASSIGN_OR_RETURN(const int64_t pt_max_spp, flags.get_int("pt-max-spp", 64, 1, 65536));
  job.pt_max_spp = static_cast<uint32_t>(pt_max_spp);
  job.field_assignments = flags.get_all("field");
  DDGI_ASSIGN_OR_RETURN(job.dynamic, flags.get_string("dynamic", ""));
  DDGI_ASSIGN_OR_RETURN(job.response_frames, flags.get_int("response-frames", 120, 5, 100000));
  DDGI_ASSIGN_OR_RETURN(job.response_static, flags.get_int("response-static", 0, 0, 100000));
  DDGI_ASSIGN_OR_RETURN(job.camera_path, flags.get_string("path", ""));
  DDGI_ASSIGN_OR_RETURN(job.path_rate, flags.get_double("path-rate", 30.0, 1.0, 1000.0));
  DDGI_ASSIGN_OR_RETURN(job.path_every, flags.get_double("path-every", 10.0, 0.01, 1e6));
  DDGI_ASSIGN_OR_RETURN(job.budgets, flags.get_doubles("budgets", 1, 16));
  for (const double budget : job.budgets) DDGI_TRY(check_budget_ms(budget));
  if (!job.budgets.empty() && flags.has("configs")) {
    return invalid_argument("--budgets measures the budget's own candidates: drop --configs");
  }
  job.session_defaults = flags.has("session-defaults");
  if (job.session_defaults &&
      (!job.budgets.empty() || !job.dynamic.empty() || !job.camera_path.empty())) {
    return invalid_argument(
        "--session-defaults applies to the table's configurations: not with --budgets, --dynamic "
        "or --path");
  }
  for (const Config& c : job.configs) DDGI_TRY(check_frame_downscale(job, c));
  return job;
}

// --field's assignments, then the configuration's own.
std::vector<std::string> config_assignments(const EvalJob& job, const Config& config) {
  std::vector<std::string> assignments = job.field_assignments;
  assignments.insert(assignments.end(), config.assignments.begin(), config.assignments.end());
  return assignments;
}

// A GI stack of `config` on `scene`, its grid fitted to `fitted` (the scene as loaded, so that a
// moved object does not move the grid).
Result<std::unique_ptr<GiStack>> make_gi_stack(vk::Context& context, const EvalJob& job,
                                               const Scene& fitted, const Scene& scene,
                                               const Config& config) {
  DDGI_ASSIGN_OR_RETURN(
      const GiStackOptions options,
      fitted_gi_options(fitted, true, config.direct_mode, config_assignments(job, config),
                        config.shadow_assignments, context.default_backend()));
  return GiStack::create(context, scene, options);
}

Result<std::unique_ptr<Renderer>> make_renderer(vk::Context& context, GiStack& gi) {
  return Renderer::create(context, gi.scene(), gi.field(), context.default_backend(),
                          gi.shadow_field());
}

Result<ReferencePair> make_references(vk::Context& context, const EvalJob& job, const Scene& scene,
                                      const Camera& camera, const std::string& stem) {
  ReferencePairOptions options;
  options.width = job.width;
  options.height = job.height;
  options.camera = camera;
  options.full_spp = options.second_spp = static_cast<uint32_t>(job.spp);
  options.second_view = PathTraceView::kFieldIndirect;
  options.exposure = auto_exposure;
  DDGI_ASSIGN_OR_RETURN(ReferencePair refs, reference_pair(context, scene, options));
  DDGI_TRY(write_exr(job.out_dir, stem + ".reference", job.width, job.height, refs.full.radiance));
  DDGI_TRY(write_exr(job.out_dir, stem + ".reference-indirect", job.width, job.height,
                     refs.second.radiance));
  return refs;
}

}  // namespace ddgi::tools
