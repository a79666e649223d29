// ddgi-shadow-eval: the direct-lighting modes (shadow rays, the shadow field at several
// resolutions, unshadowed) against the path-traced reference, with GPU time, and the shadow
// field's per-pass times. Everything is printed as markdown in one run (docs/shadow-field.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/flags.h"
#include "core/log.h"
#include "encode/write_image.h"
#include "gi/gi_stack.h"
#include "gi/shadow_field.h"
#include "gi/shadow_params.h"
#include "gpu_scene/camera_fit.h"
#include "gpu_scene/gpu_scene.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "tools/eval_job.h"
#include "tools/reference_render.h"
#include "tools/scatter_plot.h"
#include "tools/tool_support.h"
#include "vk/context.h"

namespace ddgi {
namespace {

constexpr const char* kUsage = R"(usage: ddgi-shadow-eval SCENE[@x0,y0,z0,x1,y1,z1]... [flags]

Measures the direct-lighting modes against the path-traced reference. For each SCENE:
 1. path-trace the direct-only reference (emission seen + punctual lights: what the frame's
    direct view shows) and the full image, --spp samples each;
 2. set up every mode: shadow-rays, unshadowed, shadow-field at every --resolutions entry, and
    the first resolution again with split updates, ao on the second; each mode gets its own
    irradiance field
    (for the full image; its probe rays lit in that mode) and shadow field, warmed up;
 3. render --frames frames of each mode, the modes taking turns (so that all see the same GPU
    clocks), after as many untimed ones; median GPU ms of the direct light (direct pass +
    shadow-field update) and of the whole frame;
 4. score the full and the direct view with PSNR, SSIM and mean FLIP on ACES-tone-mapped images
    (one exposure per scene: the reference's 95th-percentile luminance maps to 0.8).
Then the shadow field's per-pass times (the thesis's Table 7.8). All of it as markdown. A box
after @ is what the shadow grids are fitted to (default: the scene's bounds).

  --width N --height N  image size                                     [480 x 270]
  --spp N               reference samples per pixel                    [1024]
  --full-spp N          samples per pixel of the full reference (indirect light converges
                        slower than direct)                            [--spp]
  --warmup N            irradiance- and shadow-field updates before measuring [64]
  --frames N            timed frames per mode                          [10]
  --resolutions LIST    shadow fields as CELLS:TEXELS separated by ';': a grid of about CELLS
                        cells fitted to the scene, TEXELS^2 maps       [64:8;512:16;4096:16]
  --light-samples N     shadow rays per spherical light in the shadow-rays mode [1]
  --shadow-field NAME=VALUE  any other shadow-field parameter, for every field (repeatable)
  --gi on|off           irradiance field in the full images            [on]
  --svg FILE            also write the plot: FLIP of the direct image vs its GPU ms, as
                        FILE (ending in .svg) and the same name ending in .png
  --out-dir DIR         also write every reference and frame as PNG there
  --backend B           auto | query | pipeline                        [auto]
)";

struct Resolution {
  uint32_t cells = 512;
  uint32_t texels = 16;
};

Result<std::vector<Resolution>> parse_resolutions(const std::string& text) {
  std::vector<Resolution> list;
  std::stringstream entries(text);
  std::string entry;
  while (std::getline(entries, entry, ';')) {
    if (entry.empty()) continue;
    const size_t colon = entry.find(':');
    if (colon == std::string::npos) {
      return invalid_argument("--resolutions entry '" + entry + "' is not CELLS:TEXELS");
    }
    DDGI_ASSIGN_OR_RETURN(const int64_t cells, parse_int(entry.substr(0, colon), "--resolutions"));
    DDGI_ASSIGN_OR_RETURN(const int64_t texels,
                          parse_int(entry.substr(colon + 1), "--resolutions"));
    if (cells < 1 || cells > 1'000'000 || texels < 4 || texels > 64) {
      return invalid_argument("--resolutions entry '" + entry +
                              "': CELLS must be in [1, 1000000], TEXELS in [4, 64]");
    }
    list.push_back({static_cast<uint32_t>(cells), static_cast<uint32_t>(texels)});
  }
  if (list.empty()) return invalid_argument("--resolutions names no shadow field");
  return list;
}

// One row of the table: a direct mode, with the shadow field it samples (if any).
struct ModeRun {
  std::string name;
  DirectMode mode = DirectMode::kTracedShadows;
  bool has_shadow_field = false;
  ShadowFieldParams shadow;
};

// Exposure that maps the reference's 95th-percentile luminance to 0.8. Not the log-average:
// a black background or a black shadow would pull it down and expose everything else into
// white, hiding what these modes differ in.
float reference_exposure(const std::vector<float>& radiance) {
  std::vector<float> luminance;
  for (size_t i = 0; i + 2 < radiance.size(); i += 4) {
    luminance.push_back(0.2126f * radiance[i] + 0.7152f * radiance[i + 1] +
                        0.0722f * radiance[i + 2]);
  }
  if (luminance.empty()) return 1.0f;
  const size_t k = luminance.size() * 95 / 100;
  std::nth_element(luminance.begin(), luminance.begin() + k, luminance.end());
  const float high = luminance[k];
  return high > 0.0f ? std::clamp(0.8f / high, 1e-6f, 1e6f) : 1.0f;
}

Status write_png(const std::string& dir, const std::string& name, uint32_t width, uint32_t height,
                 const std::vector<uint8_t>& rgba) {
  if (dir.empty()) return ok_status();
  return encode::write_image(dir + "/" + name + ".png", encode::ImageRgba8{width, height, rgba});
}

std::string fixed(double value, int digits) {
  if (!std::isfinite(value)) return value > 0 ? "inf" : "-";
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.*f", digits, value);
  return buffer;
}

// Per-pass medians of one shadow field, for the Table 7.8 analogue.
struct PassRow {
  std::string scene;
  std::string field;
  uint64_t rays = 0;
  std::map<std::string, double> ms;
};

struct Options {
  uint32_t width = 480, height = 270, spp = 1024, full_spp = 1024, warmup = 64, frames = 10,
           light_samples = 1;
  bool gi = true;
  std::string out_dir;
  std::vector<Resolution> resolutions;
  std::vector<std::string> shadow_assignments;
};

// "PATH" or "PATH@x0,y0,z0,x1,y1,z1": a scene and the box its shadow fields are fitted to
// (default: the scene's bounds; a huge ground plane would spread the probes too thin).
struct SceneArg {
  std::string path;
  std::optional<Bounds> region;
};

Result<SceneArg> parse_scene_arg(const std::string& text) {
  const size_t at = text.rfind('@');
  if (at == std::string::npos) return SceneArg{text, std::nullopt};
  std::vector<double> v;
  std::stringstream items(text.substr(at + 1));
  std::string item;
  while (std::getline(items, item, ',')) {
    DDGI_ASSIGN_OR_RETURN(const double value, parse_double(item, "scene region"));
    v.push_back(value);
  }
  if (v.size() != 6 || !(v[0] < v[3] && v[1] < v[4] && v[2] < v[5])) {
    return invalid_argument("'" + text +
                            "': the region after @ must be x0,y0,z0,x1,y1,z1 with "
                            "each minimum below its maximum");
  }
  Bounds region;
  region.grow(glm::vec3(v[0], v[1], v[2]));
  region.grow(glm::vec3(v[3], v[4], v[5]));
  return SceneArg{text.substr(0, at), region};
}

// The path-traced references of a scene's default view: the full image, which sets the
// exposure of both, and the punctual direct light that the direct modes approximate.
Result<ReferencePair> make_references(vk::Context& context, const Scene& scene, const Options& o,
                                      const std::string& stem) {
  ReferencePairOptions options;
  options.width = o.width;
  options.height = o.height;
  options.camera = default_camera(scene);
  options.full_spp = o.full_spp;
  options.second_view = PathTraceView::kPunctualDirect;
  options.second_spp = o.spp;
  options.exposure = reference_exposure;
  DDGI_ASSIGN_OR_RETURN(ReferencePair refs, reference_pair(context, scene, options));
  DDGI_TRY(write_png(o.out_dir, stem + ".reference", o.width, o.height, refs.full.ldr));
  DDGI_TRY(write_png(o.out_dir, stem + ".reference-direct", o.width, o.height, refs.second.ldr));
  return refs;
}

// The modes compared: traced shadows, unshadowed, the shadow field at every resolution (the
// first also split), and the AO mode on the second resolution: the lights as in shadow-field,
// plus one AO ray per surfel. With GI the sky arrives through the irradiance field, so AO adds
// only cost there; without (--gi off) it adds the sky term.
Result<std::vector<ModeRun>> mode_runs(const Scene& scene, const SceneArg& arg, const Options& o) {
  std::vector<ModeRun> runs = {{"shadow-rays", DirectMode::kTracedShadows, false, {}},
                               {"unshadowed", DirectMode::kUnshadowed, false, {}}};
  auto shadow_params = [&](const Resolution& resolution) -> Result<ShadowFieldParams> {
    ShadowFieldParams p =
        fit_shadow_grid(arg.region.value_or(scene.world_bounds()), resolution.cells);
    p.texels = resolution.texels;
    DDGI_TRY(shadow_param_table().apply(p, o.shadow_assignments));
    return p;
  };
  for (size_t r = 0; r < o.resolutions.size(); ++r) {
    DDGI_ASSIGN_OR_RETURN(ShadowFieldParams p, shadow_params(o.resolutions[r]));
    runs.push_back({"shadow-field", DirectMode::kShadowField, true, p});
    if (r == 0) {
      p.split_update = true;
      runs.push_back({"shadow-field split", DirectMode::kShadowField, true, p});
    }
  }
  DDGI_ASSIGN_OR_RETURN(
      const ShadowFieldParams ao,
      shadow_params(o.resolutions[std::min<size_t>(1, o.resolutions.size() - 1)]));
  runs.push_back({"ao", DirectMode::kAmbientOcclusion, true, ao});
  return runs;
}

// One mode's GI stack (its irradiance field's probe rays are lit in the mode too), renderer and
// measurements.
struct Live {
  std::unique_ptr<GiStack> gi;
  std::unique_ptr<Renderer> renderer;
  std::vector<double> direct_ms, frame_ms;
  std::map<std::string, std::vector<double>> shadow_passes;
  FrameResult full;
};

Result<Live> make_live(vk::Context& context, const Scene& scene, const Options& o,
                       const ModeRun& run) {
  Live live;
  GiStackOptions options;
  options.gi = o.gi;
  options.direct_mode = run.mode;
  options.field = default_field_params(scene);
  options.shadow = run.shadow;
  options.backend = context.default_backend();
  DDGI_ASSIGN_OR_RETURN(live.gi, GiStack::create(context, scene, options));
  DDGI_TRY(live.gi->update(o.warmup));
  DDGI_ASSIGN_OR_RETURN(live.renderer, Renderer::create(context, live.gi->scene(), live.gi->field(),
                                                        options.backend, live.gi->shadow_field()));
  return live;
}

// Every mode's frames in turn, `frames` untimed rounds first (drivers may compile pipelines at
// their first dispatch): a GPU's clocks follow its load, and timing one mode after another made
// whichever came after a pause (a pipeline compile, a warm-up) up to 2.5x slower on the H100.
// Taking turns gives every mode the same conditions.
Status time_modes(const std::vector<ModeRun>& runs, std::vector<Live>& live, const Options& o,
                  FrameSettings settings) {
  settings.view = View::kFull;
  for (uint32_t f = 0; f < 2 * o.frames; ++f) {
    const bool timed = f >= o.frames;
    for (size_t m = 0; m < runs.size(); ++m) {
      settings.direct_mode = runs[m].mode;
      DDGI_ASSIGN_OR_RETURN(const auto update, live[m].gi->frame_update(runs[m].mode, {}));
      DDGI_ASSIGN_OR_RETURN(live[m].full, live[m].renderer->render(settings, update));
      if (!timed) continue;
      double direct_total = 0.0, frame_total = 0.0;
      for (const vk::PassTime& t : live[m].full.pass_times) {
        frame_total += t.milliseconds;
        const bool shadow_pass = t.group == vk::PassGroup::kShadowField;
        if (t.name == "direct" || shadow_pass) direct_total += t.milliseconds;
        if (shadow_pass) live[m].shadow_passes[t.name].push_back(t.milliseconds);
      }
      live[m].direct_ms.push_back(direct_total);
      live[m].frame_ms.push_back(frame_total);
    }
  }
  return ok_status();
}

// A mode's table row, pass-table row and plot point.
Status report_mode(const ModeRun& run, Live& l, const ReferencePair& refs, const Options& o,
                   const std::string& stem, FrameSettings settings, std::vector<PassRow>& pass_rows,
                   PlotSeries& series) {
  settings.direct_mode = run.mode;
  settings.view = View::kDirect;
  DDGI_ASSIGN_OR_RETURN(const auto update, l.gi->frame_update(run.mode, {}));
  DDGI_ASSIGN_OR_RETURN(const FrameResult direct, l.renderer->render(settings, update));
  DDGI_ASSIGN_OR_RETURN(const tools::ImageScores d,
                        tools::score_ldr(refs.second.ldr, direct.ldr, o.width, o.height));
  DDGI_ASSIGN_OR_RETURN(const tools::ImageScores f,
                        tools::score_ldr(refs.full.ldr, l.full.ldr, o.width, o.height));
  std::string grid = "-", label = run.name == "shadow-rays" ? "rays" : "none";
  if (run.has_shadow_field) {
    const glm::ivec3 c = run.shadow.counts;
    const std::string counts =
        std::to_string(c.x) + "x" + std::to_string(c.y) + "x" + std::to_string(c.z);
    grid = counts + ", " + std::to_string(run.shadow.texels) + "^2";
    const bool ao_mode = run.mode == DirectMode::kAmbientOcclusion;
    const std::string kind = run.shadow.split_update ? "split" : ao_mode ? "ao" : "";
    label = (kind.empty() ? "" : kind + " ") + counts + "/" + std::to_string(run.shadow.texels);
    PassRow row{stem,
                grid + (kind.empty() ? "" : ", " + kind),
                l.gi->shadow_field()->rays_per_update(run.mode),
                {}};
    for (auto& [name, values] : l.shadow_passes) row.ms[name] = tools::median(values);
    pass_rows.push_back(row);
  }
  std::string tag = run.name + (run.has_shadow_field ? "-" + std::to_string(run.shadow.counts.x) +
                                                           "x" + std::to_string(run.shadow.texels)
                                                     : "");
  std::replace(tag.begin(), tag.end(), ' ', '-');
  DDGI_TRY(write_png(o.out_dir, stem + "." + tag, o.width, o.height, l.full.ldr));
  DDGI_TRY(write_png(o.out_dir, stem + "." + tag + "-direct", o.width, o.height, direct.ldr));
  const ShadowField* shadow = l.gi->shadow_field();
  const double shadow_mib = shadow ? double(shadow->gpu_bytes()) / (1 << 20) : 0.0;
  const double direct_ms = tools::median(l.direct_ms);
  std::printf("| %s | %s | %s | %.1f | %s | %.4f | %.4f | %s | %.4f | %.4f | %.3f | %.3f |\n",
              stem.c_str(), run.name.c_str(), grid.c_str(), shadow_mib, fixed(d.psnr, 2).c_str(),
              d.ssim, d.flip, fixed(f.psnr, 2).c_str(), f.ssim, f.flip, direct_ms,
              tools::median(l.frame_ms));
  std::fflush(stdout);
  series.points.push_back({direct_ms, d.flip, label});
  return ok_status();
}

Status evaluate_scene(vk::Context& context, const SceneArg& arg, const Options& o,
                      std::vector<PassRow>& pass_rows, ScatterPlot& plot) {
  DDGI_ASSIGN_OR_RETURN(const Scene scene, load_scene(arg.path));
  const std::string stem = tools::file_stem(arg.path);
  DDGI_ASSIGN_OR_RETURN(const ReferencePair refs, make_references(context, scene, o, stem));
  DDGI_ASSIGN_OR_RETURN(const std::vector<ModeRun> runs, mode_runs(scene, arg, o));
  // Every mode's stack and renderer first, then their frames in turn (time_modes).
  std::vector<Live> live;
  for (const ModeRun& run : runs) {
    DDGI_ASSIGN_OR_RETURN(Live l, make_live(context, scene, o, run));
    live.push_back(std::move(l));
  }
  FrameSettings settings;
  settings.width = o.width;
  settings.height = o.height;
  settings.camera = refs.settings.camera;
  settings.exposure = refs.exposure;
  settings.light_samples = o.light_samples;
  DDGI_TRY(time_modes(runs, live, o, settings));
  PlotSeries series{stem, {}};
  for (size_t m = 0; m < runs.size(); ++m) {
    DDGI_TRY(report_mode(runs[m], live[m], refs, o, stem, settings, pass_rows, series));
  }
  plot.series.push_back(series);
  return ok_status();
}

void print_pass_table(const std::vector<PassRow>& rows) {
  std::printf(
      "\nShadow-field update, median GPU ms per pass (split: one pass traces the previous "
      "update's shadow rays and this update's probe rays)\n\n"
      "| scene | field | rays/update | trace | shadow rays | trace+rays (split) | blend | "
      "borders | total | Mrays/s |\n|---|---|---|---|---|---|---|---|---|---|\n");
  for (const PassRow& r : rows) {
    auto ms = [&](const char* name) {
      const auto it = r.ms.find(name);
      return it == r.ms.end() ? std::string("-") : fixed(it->second, 3);
    };
    double total = 0.0;
    for (const auto& [name, value] : r.ms) total += value;
    std::printf(
        "| %s | %s | %llu | %s | %s | %s | %s | %s | %.3f | %.0f |\n", r.scene.c_str(),
        r.field.c_str(), static_cast<unsigned long long>(r.rays), ms("shadow trace").c_str(),
        ms("shadow rays").c_str(), ms("shadow trace+rays").c_str(), ms("shadow blend").c_str(),
        ms("shadow borders").c_str(), total, total > 0.0 ? double(r.rays) / (total * 1e3) : 0.0);
  }
}

Status run(int argc, char** argv) {
  DDGI_ASSIGN_OR_RETURN(
      Flags flags,
      Flags::parse(argc, argv,
                   {"width", "height", "spp", "full-spp", "warmup", "frames", "resolutions",
                    "light-samples", "shadow-field", "gi", "svg", "out-dir", "backend"},
                   {"help"}));
  if (flags.has("help") || flags.positional().empty()) {
    std::fputs(kUsage, stdout);
    return flags.has("help") ? ok_status() : invalid_argument("no scene given");
  }
  set_log_level(LogLevel::kWarning);
  Options o;
  DDGI_ASSIGN_OR_RETURN(const int64_t width, flags.get_int("width", 480, 11, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t height, flags.get_int("height", 270, 11, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t spp, flags.get_int("spp", 1024, 1, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(const int64_t full_spp, flags.get_int("full-spp", spp, 1, 1 << 20));
  DDGI_ASSIGN_OR_RETURN(const int64_t warmup, flags.get_int("warmup", 64, 0, 100000));
  DDGI_ASSIGN_OR_RETURN(const int64_t frames, flags.get_int("frames", 10, 1, 10000));
  DDGI_ASSIGN_OR_RETURN(const int64_t samples, flags.get_int("light-samples", 1, 1, 64));
  o.width = static_cast<uint32_t>(width);
  o.height = static_cast<uint32_t>(height);
  o.spp = static_cast<uint32_t>(spp);
  o.full_spp = static_cast<uint32_t>(full_spp);
  o.warmup = static_cast<uint32_t>(warmup);
  o.frames = static_cast<uint32_t>(frames);
  o.light_samples = static_cast<uint32_t>(samples);
  DDGI_ASSIGN_OR_RETURN(const std::string gi, flags.get_string("gi", "on"));
  if (gi != "on" && gi != "off") return invalid_argument("--gi must be on or off");
  o.gi = gi == "on";
  DDGI_ASSIGN_OR_RETURN(const std::string resolutions,
                        flags.get_string("resolutions", "64:8;512:16;4096:16"));
  DDGI_ASSIGN_OR_RETURN(o.resolutions, parse_resolutions(resolutions));
  o.shadow_assignments = flags.get_all("shadow-field");
  DDGI_ASSIGN_OR_RETURN(o.out_dir, flags.get_string("out-dir", ""));
  DDGI_ASSIGN_OR_RETURN(const std::string svg_path, flags.get_string("svg", ""));
  if (!svg_path.empty() && !svg_path.ends_with(".svg")) {
    return invalid_argument(
        "--svg must name a file ending in .svg (the PNG is written beside it "
        "with .png): got '" +
        svg_path + "'");
  }
  // Fail on a bad assignment before any GPU work.
  ShadowFieldParams check;
  DDGI_TRY(shadow_param_table().apply(check, o.shadow_assignments));
  DDGI_ASSIGN_OR_RETURN(auto context, tools::context_from_flags(flags));
  std::printf(
      "device: %s (%s), backend %s, %ux%u, references %u spp (direct) and %u spp (full), %u "
      "warm-up updates, %u frames, GI %s\n\n",
      context->caps().device_name.c_str(), context->caps().driver_name.c_str(),
      vk::backend_name(context->default_backend()), o.width, o.height, o.spp, o.full_spp, o.warmup,
      o.frames, gi.c_str());
  std::printf(
      "| scene | mode | shadow field | MiB | direct: PSNR | SSIM | FLIP | full: PSNR | SSIM | FLIP "
      "| direct ms | frame ms |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");

  std::vector<PassRow> pass_rows;
  ScatterPlot plot;
  plot.title = "Direct light: error vs GPU time (" + context->caps().device_name + ")";
  plot.x_label = "direct light GPU ms per frame (direct pass + shadow-field update), log scale";
  plot.y_label = "mean FLIP of the direct image vs the path-traced reference";
  for (const std::string& text : flags.positional()) {
    DDGI_ASSIGN_OR_RETURN(const SceneArg arg, parse_scene_arg(text));
    DDGI_TRY(evaluate_scene(*context, arg, o, pass_rows, plot));
  }
  print_pass_table(pass_rows);
  if (!svg_path.empty()) {
    DDGI_TRY(write_scatter_plot(svg_path.substr(0, svg_path.size() - 4), plot));
  }
  return ok_status();
}

}  // namespace
}  // namespace ddgi

int main(int argc, char** argv) {
  return ddgi::tools::tool_main("ddgi-shadow-eval", ddgi::run, argc, argv);
}
