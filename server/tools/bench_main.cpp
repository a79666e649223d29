// ddgi-bench: GPU timing of the field update and frame passes over a matrix of scenes, probe
// grids, rays per probe and update paths. Prints one markdown table row per configuration
// (medians over --frames frames, each frame = one field update + the frame passes), with the
// raw-ray baselines traced in the same submissions: the update's blended rays and the frame's
// camera rays traced by kernels that only record hit distances. `update / raw` and
// `primary / raw` are the figures of merit: what lighting and blending cost over the rays.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "core/flags.h"
#include "core/log.h"
#include "gi/field_params.h"
#include "gi/gi_stack.h"
#include "gpu_scene/camera_fit.h"
#include "gpu_scene/gpu_scene.h"
#include "render/frame_target.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "tools/field_choice.h"
#include "tools/tool_support.h"
#include "vk/context.h"

namespace ddgi {
namespace {

constexpr const char* kUsage = R"(usage: ddgi-bench SCENE... [flags]

Times the irradiance-field update passes and the frame passes on the GPU for every SCENE and
every combination of --grids and --rays. Prints a markdown table (median milliseconds).

  --width N --height N  frame size                                     [1920 x 1080]
  --frames N            timed frames per configuration                 [20]
  --warmup N            field updates, then as many untimed frames, before timing [8]
  --grids LIST          probe grids: 'auto' (fitted, --probes target) or XxYxZ (fitted to the
                        scene bounds with exactly these counts), separated by ';' [auto]
  --probes N            target probe count of 'auto' grids              [512]
  --rays LIST           rays per probe, comma-separated                 [64,128,256]
  --paths LIST          field update paths, comma-separated: fused (the service's: trace,
                        hit light in the shade column, per-probe blend) and/or
                        split (trace, shade, per-texel blends, borders)  [fused]
  --backend B           auto | query | pipeline                        [auto]
  --field NAME=VALUE    any other field parameter (repeatable)
  --scroll-every N      also scroll the field one cell along x (alternately + and -) before
                        every Nth timed frame, started in that frame's update as a tracking
                        field's are, and print a second table: the call's wall ms and the
                        field's GPU ms in frames with a scroll (clearing, relocating and
                        classifying the entering plane, then the update) and in the others;
                        0: no scrolling                                  [0]
  --session-defaults    instead of --grids and --rays, one row per scene at what a
                        ddgi-server session chooses for it: the fitted field with --field's
                        parameters (kept), calibrated and chosen within the server's default
                        budget (4 ms) at --width x --height; the choice goes to stderr
  --shader-stats        also print what the driver reports of every kernel it compiled
                        (registers, shared memory...: VK_KHR_pipeline_executable_properties)
  --device NAME         Vulkan device name filter
)";

// A grid with the given counts spread over the scene bounds, cell-centred.
Result<IrradianceFieldParams> grid_for(const Scene& scene, const std::string& spec,
                                       uint32_t target_probes) {
  if (spec == "auto") return fit_grid_to_bounds(scene.world_bounds(), target_probes);
  const std::vector<std::string> c = split(spec, 'x');
  if (c.size() != 3) return invalid_argument("grid '" + spec + "' is not auto or XxYxZ");
  IrradianceFieldParams p = fit_grid_to_bounds(scene.world_bounds(), target_probes);
  const Bounds b = scene.world_bounds();
  for (int axis = 0; axis < 3; ++axis) {
    DDGI_ASSIGN_OR_RETURN(const int64_t n, parse_int(c[axis], "grid " + spec));
    if (n < 1 || n > 512) return invalid_argument("grid counts must be in [1, 512]");
    p.counts[axis] = static_cast<int>(n);
    const float extent = std::max(b.extent()[axis], 1e-6f);
    p.spacing[axis] = extent / float(n);
    p.origin[axis] = b.min[axis] + 0.5f * p.spacing[axis];
  }
  return p;
}

// What the flags ask for.
struct BenchJob {
  FrameSettings settings;
  int64_t frames = 20;
  int64_t warmup = 8;
  uint32_t probes = 512;
  std::vector<std::string> grids;
  std::vector<uint32_t> ray_counts;
  std::vector<FieldUpdatePath> paths;
  std::vector<std::string> field_assignments;
  int64_t scroll_every = 0;
  bool session_defaults = false;  // --session-defaults: the session's choice, one row per scene
};

// The scroll table's row of one configuration.
struct ScrollRow {
  std::string scene;
  glm::ivec3 counts{0};
  uint32_t rays = 0;
  size_t scrolls = 0;
  double scroll_ms = 0.0;           // median wall time of IrradianceField::scroll()
  double update_after_ms = 0.0;     // field GPU ms median, frames whose update starts a scroll
  double update_ordinary_ms = 0.0;  // the same, every other frame
};

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

const char* path_name(FieldUpdatePath path) {
  return path == FieldUpdatePath::kFused ? "fused" : "split";
}

Result<BenchJob> parse_job(const Flags& flags) {
  BenchJob job;
  DDGI_ASSIGN_OR_RETURN(const int64_t width, flags.get_int("width", 1920, 1, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t height, flags.get_int("height", 1080, 1, 16384));
  job.settings.width = static_cast<uint32_t>(width);
  job.settings.height = static_cast<uint32_t>(height);
  DDGI_ASSIGN_OR_RETURN(job.frames, flags.get_int("frames", 20, 1, 10000));
  DDGI_ASSIGN_OR_RETURN(job.warmup, flags.get_int("warmup", 8, 0, 10000));
  DDGI_ASSIGN_OR_RETURN(const int64_t probes, flags.get_int("probes", 512, 1, 4'194'304));
  job.probes = static_cast<uint32_t>(probes);
  DDGI_ASSIGN_OR_RETURN(const std::string grids_text, flags.get_string("grids", "auto"));
  job.grids = split(grids_text, ';');
  DDGI_ASSIGN_OR_RETURN(const std::string rays_text, flags.get_string("rays", "64,128,256"));
  for (const std::string& r : split(rays_text, ',')) {
    DDGI_ASSIGN_OR_RETURN(const int64_t n, parse_int(r, "--rays"));
    job.ray_counts.push_back(static_cast<uint32_t>(n));
  }
  DDGI_ASSIGN_OR_RETURN(const std::string paths_text, flags.get_string("paths", "fused"));
  for (const std::string& name : split(paths_text, ',')) {
    if (name != "fused" && name != "split") {
      return invalid_argument("--paths: '" + name + "' is not fused or split");
    }
    job.paths.push_back(name == "fused" ? FieldUpdatePath::kFused : FieldUpdatePath::kSplit);
  }
  if (job.paths.empty()) return invalid_argument("--paths: no update path given");
  job.field_assignments = flags.get_all("field");
  job.session_defaults = flags.has("session-defaults");
  DDGI_ASSIGN_OR_RETURN(job.scroll_every, flags.get_int("scroll-every", 0, 0, 10000));
  return job;
}

// The row of one configuration (columns: see run()).
void print_row(const tools::PassTable& table, const GiStack& gi, const std::string& scene_path,
               FieldUpdatePath path) {
  const double field_ms = table.group_median(vk::PassGroup::kIrradianceField);
  const double raw_ms = table.pass_median("field raw trace");
  const double primary_ms = table.pass_median("primary");
  const double primary_raw_ms = table.pass_median("primary raw trace");
  const IrradianceField& field = *gi.field();
  const IrradianceFieldParams& p = field.params();
  const std::string name = scene_path.substr(scene_path.find_last_of('/') + 1);
  const ProbeStateCounts counts = field.probe_counts();
  const double blend_ms = table.pass_median("field blend") + table.pass_median("blend irradiance") +
                          table.pass_median("blend distance") + table.pass_median("borders");
  // The split path's shade pass; the fused path's hit-light pass (the previous field's light at
  // each hit; none when paths are traced from the hits, which the trace lights itself).
  char shade[32] = "—";
  if (path == FieldUpdatePath::kSplit) {
    std::snprintf(shade, sizeof(shade), "%.3f", table.pass_median("field shade"));
  } else if (p.probe_bounces == 0) {
    std::snprintf(shade, sizeof(shade), "%.3f", table.pass_median("field hit light"));
  }
  std::printf(
      "| %s | %u | %dx%dx%d | %llu / %llu / %llu | %u | %s | %.1f | %.3f | %s | %.3f | %.3f | "
      "%.3f | %.2f | %.0f | %.3f | %.3f | %.2f | %.3f | %.3f | %.3f | %.3f |\n",
      name.c_str(), gi.scene().triangle_count(), p.counts.x, p.counts.y, p.counts.z,
      static_cast<unsigned long long>(counts.active()),
      static_cast<unsigned long long>(counts.sleeping), static_cast<unsigned long long>(counts.off),
      p.rays_per_probe, path_name(path), double(field.gpu_bytes()) / (1 << 20),
      table.pass_median("field trace"), shade, blend_ms, field_ms, raw_ms, field_ms / raw_ms,
      double(field.rays_per_update()) / (field_ms * 1e3), primary_ms, primary_raw_ms,
      primary_ms / primary_raw_ms, table.pass_median("direct"), table.pass_median("indirect"),
      table.pass_median("tonemap"), table.others_median(vk::PassGroup::kIrradianceField));
  std::fflush(stdout);
}

// One table row: a GI stack for the configuration, warmed up, then `frames` timed frames, each
// with both raw-ray baselines recorded after the update in the same submission.
Status bench_row(vk::Context& context, const BenchJob& job, const std::string& scene_path,
                 const Scene& scene, const std::string& grid, uint32_t rays, FieldUpdatePath path,
                 std::vector<ScrollRow>& scroll_rows) {
  DDGI_ASSIGN_OR_RETURN(
      GiStackOptions options,
      fitted_gi_options(scene, true, job.settings.direct_mode, {}, {}, context.default_backend()));
  if (job.session_defaults) {
    // As a session: the fitted field and --field's parameters, then the rule's choice over them.
    DDGI_TRY(field_param_table().apply(options.field, job.field_assignments));
    tools::CalibrationOptions calibration;
    calibration.width = job.settings.width;
    calibration.height = job.settings.height;
    calibration.purpose = "session";
    tools::BudgetCache cache;
    DDGI_ASSIGN_OR_RETURN(
        const tools::BudgetChoice choice,
        tools::apply_budget(context, scene, job.settings.camera, options, job.field_assignments,
                            tools::kDefaultBudgetMs, calibration, cache));
    std::fprintf(stderr, "%s, session default: %s\n", scene_path.c_str(),
                 tools::describe(choice).c_str());
  } else {
    DDGI_ASSIGN_OR_RETURN(options.field, grid_for(scene, grid, job.probes));
    options.field.rays_per_probe = rays;
    DDGI_TRY(field_param_table().apply(options.field, job.field_assignments));
  }
  DDGI_ASSIGN_OR_RETURN(auto gi, GiStack::create(context, scene, options));
  IrradianceField& field = *gi->field();
  DDGI_TRY(field.set_update_path(path));
  DDGI_ASSIGN_OR_RETURN(auto renderer, Renderer::create(context, gi->scene(), gi->field(),
                                                        context.default_backend()));
  DDGI_ASSIGN_OR_RETURN(auto target,
                        FrameTarget::create(context, job.settings.width, job.settings.height));
  gi->track(job.settings.camera.position);
  DDGI_TRY(gi->warm_up(static_cast<uint32_t>(job.warmup)));
  tools::PassTable table, after_scroll, ordinary;
  std::vector<double> scroll_ms;
  // The warm-up's frames are the timed ones, untimed: the clocks rise under this very load
  // (field-only warm-up updates, each waited for, leave the GPU idle between them).
  for (int64_t f = -job.warmup; f < job.frames; ++f) {
    const bool scrolls = job.scroll_every > 0 && f >= 0 && f % job.scroll_every == 0;
    if (scrolls) {
      // Back and forth, so that the grid stays on the scene.
      const int step = scroll_ms.size() % 2 == 0 ? 1 : -1;
      const auto start = std::chrono::steady_clock::now();
      DDGI_TRY(field.scroll(0, {step, 0, 0}, IrradianceField::ScrollStart::kInNextUpdate));
      scroll_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count());
    }
    DDGI_ASSIGN_OR_RETURN(std::vector<vk::Pass> before,
                          gi->frame_update(job.settings.direct_mode, {}));
    DDGI_ASSIGN_OR_RETURN(std::vector<vk::Pass> raw_field, field.raw_trace_passes());
    DDGI_ASSIGN_OR_RETURN(std::vector<vk::Pass> raw_primary,
                          renderer->raw_primary_passes(job.settings, *target));
    for (vk::Pass& p : raw_field) before.push_back(std::move(p));
    for (vk::Pass& p : raw_primary) before.push_back(std::move(p));
    DDGI_ASSIGN_OR_RETURN(const FrameResult frame, renderer->render(job.settings, *target, before));
    if (f >= 0) table.add(frame.pass_times);
    if (f >= 0) (scrolls ? after_scroll : ordinary).add(frame.pass_times);
  }
  print_row(table, *gi, scene_path, path);
  if (job.scroll_every > 0) {
    scroll_rows.push_back({scene_path.substr(scene_path.find_last_of('/') + 1),
                           field.params().counts, rays, scroll_ms.size(), median(scroll_ms),
                           after_scroll.group_median(vk::PassGroup::kIrradianceField),
                           ordinary.group_median(vk::PassGroup::kIrradianceField)});
  }
  return ok_status();
}

// What a scroll costs (docs/cascades.md): the call (CPU bookkeeping, wall time) and the field's
// GPU time in the frames whose update carries it (the entering plane cleared, relocated and
// classified, then the update) against the other frames'.
void print_scroll_table(const std::vector<ScrollRow>& rows) {
  std::printf(
      "\n| scene | probes | rays/probe | scrolls | entering probes | scroll call (wall ms) | "
      "field in a frame with a scroll | field otherwise | difference (the scroll's start) | "
      "with / otherwise |\n"
      "|---|---|---|---|---|---|---|---|---|---|\n");
  for (const ScrollRow& r : rows) {
    std::printf("| %s | %dx%dx%d | %u | %zu | %d | %.3f | %.3f | %.3f | %.3f | %.3f |\n",
                r.scene.c_str(), r.counts.x, r.counts.y, r.counts.z, r.rays, r.scrolls,
                r.counts.y * r.counts.z, r.scroll_ms, r.update_after_ms, r.update_ordinary_ms,
                r.update_after_ms - r.update_ordinary_ms, r.update_after_ms / r.update_ordinary_ms);
  }
}

Status run(int argc, char** argv) {
  DDGI_ASSIGN_OR_RETURN(
      Flags flags, Flags::parse(argc, argv,
                                {"width", "height", "frames", "warmup", "grids", "probes", "rays",
                                 "paths", "backend", "field", "device", "scroll-every"},
                                {"help", "shader-stats", "session-defaults"}));
  if (flags.has("help") || flags.positional().empty()) {
    std::fputs(kUsage, stdout);
    return flags.has("help") ? ok_status() : invalid_argument("no scene given");
  }
  set_log_level(LogLevel::kWarning);
  DDGI_ASSIGN_OR_RETURN(BenchJob job, parse_job(flags));
  vk::ContextOptions options;
  options.shader_statistics = flags.has("shader-stats");
  DDGI_ASSIGN_OR_RETURN(auto context, tools::context_from_flags(flags, options));
  std::printf("device: %s (%s), backend %s, %ux%u, %lld frames after %lld warm-up updates\n\n",
              context->caps().device_name.c_str(), context->caps().driver_name.c_str(),
              vk::backend_name(context->default_backend()), job.settings.width, job.settings.height,
              static_cast<long long>(job.frames), static_cast<long long>(job.warmup));
  std::printf(
      "| scene | triangles | probes | traced / sleeping / off | rays/probe | path | field MiB | "
      "trace | shade | blend | field total | raw trace | update / raw | Mrays/s | primary | "
      "primary raw | primary / raw | direct | indirect | tonemap | frame total |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  std::vector<ScrollRow> scroll_rows;
  for (const std::string& scene_path : flags.positional()) {
    DDGI_ASSIGN_OR_RETURN(const Scene scene, load_scene(scene_path));
    job.settings.camera = default_camera(scene);
    if (job.session_defaults) {
      DDGI_TRY(
          bench_row(*context, job, scene_path, scene, "auto", 0, job.paths.front(), scroll_rows));
      continue;
    }
    for (const std::string& grid : job.grids) {
      for (uint32_t rays : job.ray_counts) {
        for (FieldUpdatePath path : job.paths) {
          DDGI_TRY(bench_row(*context, job, scene_path, scene, grid, rays, path, scroll_rows));
        }
      }
    }
  }
  if (!scroll_rows.empty()) print_scroll_table(scroll_rows);
  if (flags.has("shader-stats")) {
    std::printf("\nShader statistics\n\n%s",
                vk::shader_statistics_table(context->shader_statistics()).c_str());
  }
  return ok_status();
}

}  // namespace
}  // namespace ddgi

int main(int argc, char** argv) {
  return ddgi::tools::tool_main("ddgi-bench", ddgi::run, argc, argv);
}
