// ddgi-bench: GPU timing of the field update and frame passes over a matrix of scenes, probe
// grids and rays per probe. Prints one markdown table row per configuration (medians over
// --frames frames, each frame = one field update + the frame passes).
#include <algorithm>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/flags.h"
#include "core/log.h"
#include "gi/field_params.h"
#include "gi/irradiance_field.h"
#include "gpu_scene/camera_fit.h"
#include "gpu_scene/gpu_scene.h"
#include "render/renderer.h"
#include "scene/gltf_loader.h"
#include "vk/context.h"

namespace ddgi {
namespace {

constexpr const char* kUsage = R"(usage: ddgi-bench SCENE... [flags]

Times the irradiance-field update passes and the frame passes on the GPU for every SCENE and
every combination of --grids and --rays. Prints a markdown table (median milliseconds).

  --width N --height N  frame size                                     [1920 x 1080]
  --frames N            timed frames per configuration                 [20]
  --warmup N            field updates before timing                    [8]
  --grids LIST          probe grids: 'auto' (fitted, --probes target) or XxYxZ (fitted to the
                        scene bounds with exactly these counts), separated by ';' [auto]
  --probes N            target probe count of 'auto' grids              [512]
  --rays LIST           rays per probe, comma-separated                 [64,128,256]
  --backend B           auto | query | pipeline                        [auto]
  --field NAME=VALUE    any other field parameter (repeatable)
  --device NAME         Vulkan device name filter
)";

// Passes of one field update (IrradianceField::record_update); the rest are frame passes.
const std::string kFieldPasses[] = {"field trace", "field shade", "blend irradiance",
                                    "blend distance", "borders"};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, separator)) {
    if (!item.empty()) parts.push_back(item);
  }
  return parts;
}

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

Status run(int argc, char** argv) {
  DDGI_ASSIGN_OR_RETURN(Flags flags, Flags::parse(argc, argv,
                                                  {"width", "height", "frames", "warmup", "grids",
                                                   "probes", "rays", "backend", "field", "device"},
                                                  {"help"}));
  if (flags.has("help") || flags.positional().empty()) {
    std::fputs(kUsage, stdout);
    return flags.has("help") ? ok_status() : invalid_argument("no scene given");
  }
  set_log_level(LogLevel::kWarning);
  FrameSettings settings;
  DDGI_ASSIGN_OR_RETURN(const int64_t width, flags.get_int("width", 1920, 1, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t height, flags.get_int("height", 1080, 1, 16384));
  settings.width = static_cast<uint32_t>(width);
  settings.height = static_cast<uint32_t>(height);
  DDGI_ASSIGN_OR_RETURN(const int64_t frames, flags.get_int("frames", 20, 1, 10000));
  DDGI_ASSIGN_OR_RETURN(const int64_t warmup, flags.get_int("warmup", 8, 0, 10000));
  DDGI_ASSIGN_OR_RETURN(const int64_t probes, flags.get_int("probes", 512, 1, 4'194'304));
  DDGI_ASSIGN_OR_RETURN(const std::string grids_text, flags.get_string("grids", "auto"));
  DDGI_ASSIGN_OR_RETURN(const std::string rays_text, flags.get_string("rays", "64,128,256"));
  DDGI_ASSIGN_OR_RETURN(const std::string backend_text, flags.get_string("backend", "auto"));
  DDGI_ASSIGN_OR_RETURN(const auto forced_backend, vk::parse_backend(backend_text));
  std::vector<int64_t> ray_counts;
  for (const std::string& r : split(rays_text, ',')) {
    DDGI_ASSIGN_OR_RETURN(const int64_t n, parse_int(r, "--rays"));
    ray_counts.push_back(n);
  }

  vk::ContextOptions options;
  options.backend = forced_backend;
  DDGI_ASSIGN_OR_RETURN(options.device_filter, flags.get_string("device", ""));
  DDGI_ASSIGN_OR_RETURN(auto context, vk::Context::create(options));
  std::printf("device: %s (%s), backend %s, %ux%u, %lld frames after %lld warm-up updates\n\n",
              context->caps().device_name.c_str(), context->caps().driver_name.c_str(),
              vk::backend_name(context->default_backend()), settings.width, settings.height,
              static_cast<long long>(frames), static_cast<long long>(warmup));
  std::printf(
      "| scene | triangles | probes | traced / sleeping / off | rays/probe | field MiB | trace | "
      "shade | blend irr. | blend dist. | borders | field total | Mrays/s | primary | direct | "
      "indirect | tonemap | frame total |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");

  for (const std::string& scene_path : flags.positional()) {
    DDGI_ASSIGN_OR_RETURN(const Scene scene, load_scene(scene_path));
    DDGI_ASSIGN_OR_RETURN(auto gpu_scene, GpuScene::create(*context, scene));
    settings.camera = default_camera(scene);
    for (const std::string& grid : split(grids_text, ';')) {
      for (int64_t rays : ray_counts) {
        DDGI_ASSIGN_OR_RETURN(IrradianceFieldParams params,
                              grid_for(scene, grid, static_cast<uint32_t>(probes)));
        params.rays_per_probe = static_cast<uint32_t>(rays);
        DDGI_TRY(field_param_table().apply(params, flags.get_all("field")));
        DDGI_ASSIGN_OR_RETURN(auto field, IrradianceField::create(*context, *gpu_scene, params,
                                                                  context->default_backend()));
        DDGI_ASSIGN_OR_RETURN(auto renderer, Renderer::create(*context, *gpu_scene, field.get(),
                                                              context->default_backend()));
        DDGI_TRY(field->warm_up(static_cast<uint32_t>(warmup), settings.direct_mode));
        std::map<std::string, std::vector<double>> times;
        std::vector<double> field_totals, frame_totals;
        for (int64_t f = 0; f < frames; ++f) {
          DDGI_ASSIGN_OR_RETURN(const FrameResult frame, renderer->render(settings));
          double field_ms = 0.0, frame_ms = 0.0;
          for (size_t p = 0; p < frame.pass_times.size(); ++p) {
            times[frame.pass_times[p].name].push_back(frame.pass_times[p].milliseconds);
            const bool field_pass = std::find(std::begin(kFieldPasses), std::end(kFieldPasses),
                                              frame.pass_times[p].name) != std::end(kFieldPasses);
            (field_pass ? field_ms : frame_ms) += frame.pass_times[p].milliseconds;
          }
          field_totals.push_back(field_ms);
          frame_totals.push_back(frame_ms);
        }
        const double field_ms = median(field_totals);
        const IrradianceFieldParams& p = field->params();
        const std::string name = scene_path.substr(scene_path.find_last_of('/') + 1);
        const ProbeStateCounts counts = field->probe_counts();
        std::printf(
            "| %s | %u | %dx%dx%d | %llu / %llu / %llu | %u | %.1f | %.3f | %.3f | %.3f | %.3f | "
            "%.3f | %.3f | %.0f | %.3f | %.3f | %.3f | %.3f | %.3f |\n",
            name.c_str(), gpu_scene->triangle_count(), p.counts.x, p.counts.y, p.counts.z,
            static_cast<unsigned long long>(counts.active()),
            static_cast<unsigned long long>(counts.sleeping),
            static_cast<unsigned long long>(counts.off), p.rays_per_probe,
            double(field->gpu_bytes()) / (1 << 20), median(times["field trace"]),
            median(times["field shade"]), median(times["blend irradiance"]),
            median(times["blend distance"]), median(times["borders"]), field_ms,
            double(field->rays_per_update()) / (field_ms * 1e3), median(times["primary"]),
            median(times["direct"]), median(times["indirect"]), median(times["tonemap"]),
            median(frame_totals));
        std::fflush(stdout);
      }
    }
  }
  return ok_status();
}

}  // namespace
}  // namespace ddgi

int main(int argc, char** argv) {
  const ddgi::Status status = ddgi::run(argc, argv);
  if (!status.ok()) {
    std::fprintf(stderr, "ddgi-bench: %s\n", status.error().message.c_str());
    return 2;
  }
  return 0;
}
