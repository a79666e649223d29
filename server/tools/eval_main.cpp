// ddgi-eval: image quality of DDGI frames against the path-traced reference, with GPU time.
// For every scene: a reference (full image, and the part the irradiance field must supply:
// everything but punctual direct light), then for every field configuration a warmed-up DDGI
// frame, compared with PSNR, SSIM and FLIP on the tone-mapped images. One markdown table.
// With --dynamic: how many frames each configuration (and the path tracer restarted at the
// change) needs after a light or an object moves (tools/dynamic_response.h). With --budgets:
// the time budget's choice against the measured trade (tools/budget_eval.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "core/flags.h"
#include "core/log.h"
#include "gi/field_params.h"
#include "gi/gi_stack.h"
#include "gpu_scene/camera_fit.h"
#include "gpu_scene/gpu_scene.h"
#include "render/path_tracer.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "tools/budget_eval.h"
#include "tools/dynamic_response.h"
#include "tools/eval_job.h"
#include "tools/image_upscale.h"
#include "tools/pareto.h"
#include "tools/path_eval.h"
#include "tools/reference_render.h"
#include "tools/session_defaults_eval.h"
#include "tools/tool_support.h"
#include "vk/context.h"

namespace ddgi {
namespace {

using tools::auto_exposure;
using tools::Config;
using tools::EvalJob;
using tools::make_gi_stack;
using tools::score;
using tools::write_exr;

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
                        dense:counts=12,12,12"; and how the frame is made:
                        direct=MODE (shadow-rays, unshadowed, shadow-field, ao; the
                        direct light of the frame and of probe-ray hits) [shadow-rays],
                        shadow.NAME=VALUE (a shadow field parameter, e.g. shadow.texels=8),
                        frame_downscale=N (drawn at 1/N the size each way, upscaled to be
                        scored; not with --dynamic or --path)
                                                                        [default:]
  --field NAME=VALUE    applied to every configuration first (repeatable)
  --out-dir DIR         also write every reference and frame as EXR there
  --pareto DIR          also time the path tracer at 1/16, 1/4 (one sample at a quarter and
                        half the size each way, upscaled), 1, 2, 4, ... --pt-max-spp samples
                        per pixel, and write per scene DIR/SCENE.json (every configuration, the
                        Pareto front of FLIP against GPU ms, each front point's FLIP over the
                        path tracer's at the same ms) and DIR/SCENE.svg and .png (the plot);
                        DIR must exist
  --pt-max-spp N        the path tracer's largest sample count for --pareto      [64]
  --dynamic CHANGE      instead of the table above: warm each configuration up, apply CHANGE
                        (light:INDEX:dx,dy,dz or object:INDEX:dx,dy,dz), render
                        --response-frames frames (one field update each) and score each
                        frame's indirect view against the changed scene's field-part
                        reference (relative L1 of linear radiance: the direct light follows
                        at once, the field lags); the path tracer restarted at the change (1
                        spp per frame, same part) is the baseline. Prints per method its
                        steady error (the configuration warmed up on the changed scene), the
                        frames and GPU ms until the error stays within 10% of it (the path
                        tracer: of the best configuration's), judged on 10-frame means; writes
                        DIR/SCENE.response.svg, .png and .csv with --pareto DIR, and
                        DIR/SCENE.rays.svg and .png: the probe rays each frame's update
                        traced
  --response-static N   --dynamic: N frames of the scene as loaded first (scored against
                        its own reference), then the change                      [0]
  --path FILE           instead of the table above: walk one scene's camera path (a
                        *.path.json, docs/sidecar-format.md) with each configuration, one
                        field update and frame per 1/--path-rate s of the path (a tracking
                        field follows the camera); score the frame every --path-every s
                        against a path-traced reference of that view; print per view and per
                        configuration its errors, field ms and the frame-to-frame change of
                        the indirect view at scroll events and otherwise; with --out-dir also
                        DIR/SCENE.path.svg, .png and .csv (FLIP along the path)
  --path-rate N         frames per second of the path                  [30]
  --path-every S        seconds between scored views                   [10]
  --budgets LIST        the time budget (budget_ms) checked: the table's configurations
                        are the budget's candidates for each scene; then the server's
                        calibration runs and, per budget in LIST (ms per frame, comma-
                        separated), its choice is printed beside the measurements: the
                        chosen configuration's measured ms over the budget and its FLIP
                        over the best measured configuration within the budget
  --session-defaults    every configuration gets what a ddgi-server session chooses over it
                        for the scene at the server's default budget (4 ms at --width x
                        --height): the calibrated choice of lowest error that fits; the
                        row's name says what (not with --budgets, --dynamic or --path)
  --backend B           auto | query | pipeline                         [auto]
)";

// A frame drawn at 1/frame_downscale of the job's size (Config::frame_downscale), stretched to
// the job's size as the path tracer's cheaper points are, so it is scored against the same
// reference; one drawn at the job's size as it is.
FrameResult frame_at_job_size(FrameResult frame, const EvalJob& job) {
  // Frames whose radiance is not read back (the unscored timed ones) are left as they are.
  if (frame.radiance.empty() || (frame.width == job.width && frame.height == job.height)) {
    return frame;
  }
  const PathTraceImage drawn{frame.width, frame.height, 1, std::move(frame.radiance),
                             std::move(frame.ldr)};
  PathTraceImage stretched = tools::upscaled(drawn, job.width, job.height);
  frame.width = job.width;
  frame.height = job.height;
  frame.radiance = std::move(stretched.radiance);
  frame.ldr = std::move(stretched.ldr);
  return frame;
}

// One table row: a warmed-up field of `config`, `frames` timed full frames (one update each),
// then the indirect view, both scored against the references.
Result<tools::ConfigPoint> evaluate_config(vk::Context& context, const EvalJob& job,
                                           const Scene& scene, const std::string& stem,
                                           const ReferencePair& refs, const Config& config) {
  DDGI_ASSIGN_OR_RETURN(auto gi, make_gi_stack(context, job, scene, scene, config));
  DDGI_ASSIGN_OR_RETURN(auto renderer, tools::make_renderer(context, *gi));
  gi->track(refs.settings.camera.position);
  DDGI_TRY(gi->warm_up(static_cast<uint32_t>(job.warmup)));
  FrameSettings settings;
  settings.width = job.width / config.frame_downscale;
  settings.height = job.height / config.frame_downscale;
  settings.camera = refs.settings.camera;
  settings.exposure = refs.exposure;
  settings.direct_mode = config.direct_mode;
  auto frame = [&](View view) -> Result<FrameResult> {
    settings.view = view;
    DDGI_ASSIGN_OR_RETURN(const auto update, gi->frame_update(settings.direct_mode, {}));
    DDGI_ASSIGN_OR_RETURN(FrameResult result, renderer->render(settings, update));
    return frame_at_job_size(std::move(result), job);
  };
  // Frames (without field updates) for kClockRampUp before timing: scoring the previous
  // configuration on the CPU left the GPU idle for seconds and its clocks low (the H200 timed a
  // scene's first configuration at 0.8 ms per frame and the next ones at 4-6 ms without this).
  settings.read_radiance = false;
  settings.view = View::kFull;
  DDGI_TRY(tools::render_for(*renderer, settings, tools::kClockRampUp));
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
  tools::ConfigPoint point{config.name, job.field_assignments};
  const std::vector<std::string> own = config.all_assignments();
  point.assignments.insert(point.assignments.end(), own.begin(), own.end());
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

// One point of the equal-time baseline: `spp` samples per pixel at 1/downscale of the frame's
// size each way (pixel centres, as the frames and the reference), made --frames times (the
// median GPU time counts); the last image, upscaled to the frame's size, scored against the
// reference.
Result<tools::PathTracePoint> path_trace_point(PathTracer& tracer, const EvalJob& job,
                                               const ReferencePair& refs, uint32_t spp,
                                               uint32_t downscale) {
  PathTraceSettings settings = refs.settings;
  settings.width = job.width / downscale;
  settings.height = job.height / downscale;
  // Untimed images first: scoring the previous point left the GPU idle and its clocks low.
  DDGI_TRY(tools::keep_gpu_busy(tools::kClockRampUp, [&] {
    tracer.reset();
    return tracer.accumulate(settings, spp);
  }));
  std::vector<double> times;  // one image per timed frame; the median counts
  for (int64_t run = 0; run < job.frames; ++run) {
    tracer.reset();
    DDGI_TRY(tracer.accumulate(settings, spp));
    times.push_back(tracer.last_accumulate_ms());
  }
  std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
  DDGI_ASSIGN_OR_RETURN(const PathTraceImage traced, tracer.read(Tonemap::kAces, refs.exposure));
  const PathTraceImage image =
      downscale == 1 ? traced : tools::upscaled(traced, job.width, job.height);
  DDGI_ASSIGN_OR_RETURN(
      const tools::ImageScores scores,
      score(refs.full.ldr, refs.full.radiance, image.ldr, image.radiance, job.width, job.height));
  return tools::PathTracePoint{spp, downscale, times[times.size() / 2], scores};
}

// The equal-time baseline: the path tracer at 1/16 and 1/4 sample per pixel (one sample at a
// quarter and at half the frame's size each way, where that divides it into at least 8 pixels
// each way, upscaled: a path tracer's only way to take less time than one sample per pixel),
// then at 1, 2, 4, ... job.pt_max_spp.
Result<std::vector<tools::PathTracePoint>> path_trace_curve(vk::Context& context,
                                                            const EvalJob& job, const Scene& scene,
                                                            const ReferencePair& refs) {
  DDGI_ASSIGN_OR_RETURN(auto gpu, GpuScene::create(context, scene));
  DDGI_ASSIGN_OR_RETURN(auto tracer, PathTracer::create(context, *gpu, context.default_backend()));
  std::vector<tools::PathTracePoint> curve;
  for (const uint32_t downscale : {4u, 2u}) {
    if (job.width % downscale != 0 || job.height % downscale != 0 || job.width / downscale < 8 ||
        job.height / downscale < 8) {
      continue;
    }
    DDGI_ASSIGN_OR_RETURN(tools::PathTracePoint point,
                          path_trace_point(*tracer, job, refs, 1, downscale));
    curve.push_back(point);
  }
  for (uint32_t spp = 1; spp <= job.pt_max_spp; spp *= 2) {
    DDGI_ASSIGN_OR_RETURN(tools::PathTracePoint point,
                          path_trace_point(*tracer, job, refs, spp, 1));
    curve.push_back(point);
  }
  return curve;
}

// A field of `config` warmed up on `scene` and its renderer, drawing the indirect view (the
// field's part: the direct light follows a change at once) of the references' camera.
struct WarmField {
  std::unique_ptr<GiStack> gi;
  std::unique_ptr<Renderer> renderer;
  FrameSettings settings;

  // The probe rays the next frame's field update will trace (adaptive rays trace fewer).
  Result<double> next_update_rays() {
    DDGI_ASSIGN_OR_RETURN(const std::vector<uint8_t> lit, gi->field()->probes_lit_by_next_update());
    const double probes = double(std::count(lit.begin(), lit.end(), uint8_t{1}));
    return probes * gi->field()->params().rays_per_probe;
  }

  // One frame with one field update: its error against `refs`' field part, and its GPU ms.
  Result<std::pair<double, double>> frame(const ReferencePair& refs) {
    DDGI_ASSIGN_OR_RETURN(const auto update, gi->frame_update(settings.direct_mode, {}));
    DDGI_ASSIGN_OR_RETURN(const FrameResult result, renderer->render(settings, update));
    tools::PassTable table;
    table.add(result.pass_times);
    return std::make_pair(tools::relative_l1(result.radiance, refs.second.radiance),
                          table.group_median(vk::PassGroup::kIrradianceField) +
                              table.group_median(vk::PassGroup::kFrame));
  }
};

Result<WarmField> warm_field(vk::Context& context, const EvalJob& job, const Scene& fitted,
                             const Scene& scene, const ReferencePair& refs, const Config& config) {
  WarmField w;
  DDGI_ASSIGN_OR_RETURN(w.gi, make_gi_stack(context, job, fitted, scene, config));
  DDGI_ASSIGN_OR_RETURN(w.renderer, tools::make_renderer(context, *w.gi));
  w.gi->track(refs.settings.camera.position);
  DDGI_TRY(w.gi->warm_up(static_cast<uint32_t>(job.warmup)));
  w.settings.width = job.width;
  w.settings.height = job.height;
  w.settings.camera = refs.settings.camera;
  w.settings.exposure = refs.exposure;
  w.settings.direct_mode = config.direct_mode;
  w.settings.view = View::kIndirect;
  return w;
}

// --dynamic: a field warmed up on `scene`, --response-static frames of it scored against
// `before` (the unchanged scene's reference), then `change` applied and one frame (with one
// field update) after another scored against the changed scene's reference; its steady error is
// the median over kSteadyFrames of the same configuration warmed up on the changed scene.
Result<tools::ResponseCurve> field_response(vk::Context& context, const EvalJob& job,
                                            const Scene& scene, const Scene& changed,
                                            const tools::SceneChange& change,
                                            const ReferencePair& refs, const ReferencePair* before,
                                            const Config& config) {
  constexpr int kSteadyFrames = 11;
  tools::ResponseCurve curve{config.name, {}, {}};
  {
    DDGI_ASSIGN_OR_RETURN(WarmField converged,
                          warm_field(context, job, scene, changed, refs, config));
    std::vector<double> errors;
    for (int f = 0; f < kSteadyFrames; ++f) {
      DDGI_ASSIGN_OR_RETURN(const auto frame, converged.frame(refs));
      errors.push_back(frame.first);
    }
    std::nth_element(errors.begin(), errors.begin() + kSteadyFrames / 2, errors.end());
    curve.steady = errors[kSteadyFrames / 2];
  }
  DDGI_ASSIGN_OR_RETURN(WarmField w, warm_field(context, job, scene, scene, refs, config));
  auto record = [&](const ReferencePair& reference) -> Status {
    DDGI_ASSIGN_OR_RETURN(const double rays, w.next_update_rays());
    DDGI_ASSIGN_OR_RETURN(const auto frame, w.frame(reference));
    curve.error.push_back(frame.first);
    curve.ms.push_back(frame.second);
    curve.rays.push_back(rays);
    return ok_status();
  };
  for (int64_t f = 0; f < job.response_static; ++f) DDGI_TRY(record(*before));
  curve.change_frame = job.response_static;
  if (change.kind == tools::SceneChange::Kind::kLight) {
    DDGI_TRY(w.gi->scene().set_lights(changed.lights));
  } else {
    DDGI_TRY(w.gi->scene().set_instance_transform(change.index,
                                                  changed.instances[change.index].transform));
  }
  for (int64_t f = 0; f < job.response_frames; ++f) DDGI_TRY(record(refs));
  return curve;
}

// The baseline: the path tracer on the changed scene, restarted at the change, one sample per
// pixel per frame.
Result<tools::ResponseCurve> path_trace_response(vk::Context& context, const EvalJob& job,
                                                 const Scene& changed, const ReferencePair& refs) {
  DDGI_ASSIGN_OR_RETURN(auto gpu, GpuScene::create(context, changed));
  DDGI_ASSIGN_OR_RETURN(auto tracer, PathTracer::create(context, *gpu, context.default_backend()));
  PathTraceSettings settings = refs.settings;
  settings.view = PathTraceView::kFieldIndirect;
  tools::ResponseCurve curve{"path tracing, 1 spp per frame", {}, {}};
  for (int64_t f = 0; f < job.response_frames; ++f) {
    DDGI_TRY(tracer->accumulate(settings, 1));
    DDGI_ASSIGN_OR_RETURN(const PathTraceImage image, tracer->read(Tonemap::kAces, refs.exposure));
    curve.error.push_back(tools::relative_l1(image.radiance, refs.second.radiance));
    curve.ms.push_back(tracer->last_accumulate_ms());
  }
  return curve;
}

// The path tracer (last) is measured against the best configuration's steady error.
void print_response(const std::string& stem, const std::vector<tools::ResponseCurve>& curves) {
  double best = 1e300;
  for (size_t i = 0; i + 1 < curves.size(); ++i) best = std::min(best, curves[i].steady);
  for (size_t i = 0; i < curves.size(); ++i) {
    const tools::ResponseCurve& c = curves[i];
    const double target = i + 1 == curves.size() ? best : c.steady;
    const int64_t frames = c.frames_until_within(target);
    std::printf("| %s | %s | %.4f | %.4f | %s | %s |\n", stem.c_str(), c.name.c_str(),
                c.error[size_t(c.change_frame)], target,
                frames < 0 ? "never" : std::to_string(frames).c_str(),
                frames < 0 ? "-" : std::to_string(c.ms_until(frames)).substr(0, 7).c_str());
  }
  std::fflush(stdout);
}

Status run_dynamic(vk::Context& context, const EvalJob& job,
                   const std::vector<std::string>& scene_paths) {
  std::printf(
      "| scene | method | error, first frame | steady error (path tracing: the best "
      "configuration's) | frames until within 10%% | GPU ms until then "
      "|\n|---|---|---|---|---|---|\n");
  for (const std::string& scene_path : scene_paths) {
    DDGI_ASSIGN_OR_RETURN(const Scene scene, load_scene(scene_path));
    DDGI_ASSIGN_OR_RETURN(const tools::SceneChange change,
                          tools::parse_scene_change(job.dynamic, scene));
    const Scene changed = tools::changed_scene(scene, change);
    const std::string stem = tools::file_stem(scene_path);
    std::fprintf(stderr, "%s: %s\n", stem.c_str(), tools::describe(scene, change).c_str());
    DDGI_ASSIGN_OR_RETURN(
        const ReferencePair refs,
        tools::make_references(context, job, changed, default_camera(changed), stem + ".changed"));
    std::optional<ReferencePair> before;
    if (job.response_static > 0) {
      DDGI_ASSIGN_OR_RETURN(
          before, tools::make_references(context, job, scene, default_camera(changed), stem));
    }
    std::vector<tools::ResponseCurve> curves;
    for (const Config& config : job.configs) {
      DDGI_ASSIGN_OR_RETURN(tools::ResponseCurve curve,
                            field_response(context, job, scene, changed, change, refs,
                                           before ? &*before : nullptr, config));
      curves.push_back(std::move(curve));
    }
    DDGI_ASSIGN_OR_RETURN(tools::ResponseCurve traced,
                          path_trace_response(context, job, changed, refs));
    curves.push_back(std::move(traced));
    print_response(stem, curves);
    if (!job.pareto_dir.empty())
      DDGI_TRY(tools::write_response_files(job.pareto_dir, stem, curves));
  }
  return ok_status();
}

std::string optional_text(std::optional<double> value) {
  char buffer[32] = "-";
  if (value) std::snprintf(buffer, sizeof(buffer), "%.4g", *value);
  return buffer;
}

// After the table: per scene, each front point against the path tracer: its FLIP at the same
// ms, and the ms it needs for the same FLIP ("-": outside the traced spp range).
void print_fronts(const std::vector<tools::SceneTrade>& trades) {
  std::printf(
      "\n| scene | front point | GPU ms | FLIP | path tracing FLIP, same ms | ratio | path "
      "tracing ms, same FLIP |\n|---|---|---|---|---|---|---|\n");
  for (const tools::SceneTrade& trade : trades) {
    for (size_t i : tools::pareto_front(trade.configs)) {
      const tools::ConfigPoint& c = trade.configs[i];
      const std::optional<double> traced =
          tools::path_trace_flip_at(trade.path_tracing, c.total_ms());
      std::printf("| %s | %s | %.3f | %.4f | %s | %s | %s |\n", trade.scene.c_str(), c.name.c_str(),
                  c.total_ms(), c.full.flip, optional_text(traced).c_str(),
                  optional_text(tools::ratio_of(c.full.flip, traced)).c_str(),
                  optional_text(tools::path_trace_ms_for(trade.path_tracing, c.full.flip)).c_str());
    }
  }
}

// The issue's figure: at 1, 2 and 5 ms per frame, the best configuration within the time over
// the path tracer at that time.
void print_equal_time(const std::vector<tools::SceneTrade>& trades) {
  std::printf(
      "\n| scene | ms | best DDGI FLIP within | path tracing FLIP at ms | DDGI / path tracing "
      "|\n|---|---|---|---|---|\n");
  for (const tools::SceneTrade& trade : trades) {
    for (const tools::EqualTimePoint& p : tools::equal_time_points(trade)) {
      std::printf("| %s | %g | %s | %s | %s |\n", trade.scene.c_str(), p.ms,
                  optional_text(p.best_flip_within).c_str(),
                  optional_text(p.path_trace_flip).c_str(),
                  optional_text(p.flip_over_path_trace).c_str());
    }
  }
}

Status run(int argc, char** argv) {
  DDGI_ASSIGN_OR_RETURN(
      Flags flags,
      Flags::parse(argc, argv,
                   {"width", "height", "spp", "warmup", "frames", "configs", "field", "out-dir",
                    "backend", "pareto", "pt-max-spp", "dynamic", "response-frames",
                    "response-static", "path", "path-rate", "path-every", "budgets"},
                   {"help", "session-defaults"}));
  if (flags.has("help") || flags.positional().empty()) {
    std::fputs(kUsage, stdout);
    return flags.has("help") ? ok_status() : invalid_argument("no scene given");
  }
  set_log_level(LogLevel::kWarning);
  DDGI_ASSIGN_OR_RETURN(const EvalJob job, tools::parse_job(flags));
  DDGI_ASSIGN_OR_RETURN(auto context, tools::context_from_flags(flags));
  std::printf("device: %s, backend %s, %ux%u, reference %lld spp, %lld warm-up updates\n\n",
              context->caps().device_name.c_str(), vk::backend_name(context->default_backend()),
              job.width, job.height, static_cast<long long>(job.spp),
              static_cast<long long>(job.warmup));
  if (!job.dynamic.empty()) return run_dynamic(*context, job, flags.positional());
  if (!job.camera_path.empty()) {
    if (flags.positional().size() != 1) return invalid_argument("--path takes one scene");
    return tools::run_path(*context, job, flags.positional().front());
  }
  std::printf(
      "| scene | configuration | probes traced / sleeping / off | full: PSNR | SSIM | FLIP | "
      "mean/ref | indirect: PSNR | SSIM | FLIP | mean/ref | field ms | frame ms |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<tools::SceneTrade> trades;
  std::vector<std::string> budget_rows;
  for (const std::string& scene_path : flags.positional()) {
    DDGI_ASSIGN_OR_RETURN(const Scene scene, load_scene(scene_path));
    const std::string stem = tools::file_stem(scene_path);
    DDGI_ASSIGN_OR_RETURN(
        const ReferencePair refs,
        tools::make_references(*context, job, scene, default_camera(scene), stem));
    tools::SceneTrade trade{stem, job.width, job.height, static_cast<uint32_t>(job.spp), {}, {}};
    std::vector<Config> configs = job.configs;
    if (!job.budgets.empty()) {
      DDGI_ASSIGN_OR_RETURN(configs, tools::budget_configs(*context, job, scene));
    }
    if (job.session_defaults) {
      DDGI_ASSIGN_OR_RETURN(configs, tools::session_default_configs(
                                         *context, job, scene, default_camera(scene), configs));
    }
    for (const Config& config : configs) {
      DDGI_ASSIGN_OR_RETURN(tools::ConfigPoint point,
                            evaluate_config(*context, job, scene, stem, refs, config));
      trade.configs.push_back(std::move(point));
    }
    if (!job.budgets.empty()) {
      DDGI_ASSIGN_OR_RETURN(const auto rows,
                            tools::budget_rows(*context, job, scene, stem, trade.configs));
      budget_rows.insert(budget_rows.end(), rows.begin(), rows.end());
    }
    if (job.pareto_dir.empty()) continue;
    DDGI_ASSIGN_OR_RETURN(trade.path_tracing, path_trace_curve(*context, job, scene, refs));
    DDGI_TRY(tools::write_scene_trade(trade, job.pareto_dir));
    trades.push_back(std::move(trade));
  }
  if (!trades.empty()) {
    print_fronts(trades);
    print_equal_time(trades);
  }
  if (!budget_rows.empty()) tools::print_budget_table(budget_rows);
  return ok_status();
}

}  // namespace
}  // namespace ddgi

int main(int argc, char** argv) {
  return ddgi::tools::tool_main("ddgi-eval", ddgi::run, argc, argv);
}
