// ddgi-ao-eval: the ambient-occlusion modes against AO traced with many rays, with GPU time and
// memory (docs/world-cache.md): AO traced per pixel (1, 4, 16 rays), the shadow field's AO and
// the world cache's AO. Every scene is lit by a white sky alone (its lights removed), GI off,
// so a pixel's radiance is its albedo x AO; prints one markdown table for all scenes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/flags.h"
#include "core/log.h"
#include "gi/gi_stack.h"
#include "gi/world_cache.h"
#include "gpu_scene/camera_fit.h"
#include "render/renderer.h"
#include "tools/tool_support.h"
#include "vk/context.h"

namespace ddgi {
namespace {

constexpr const char* kUsage = R"(usage: ddgi-ao-eval SCENE... [flags]

For each SCENE (lights removed, lit by a white sky, GI off, its default camera), traces the
reference AO with --reference-spp rays per pixel, then renders each AO mode: ao-traced with 1,
4 and 16 rays per pixel, ao (the shadow field's AO, updated once per frame after --warmup
updates) and ao-cache (the world cache, fed once per frame, after --warmup frames). Each mode is
timed over --frames frames after the GPU's clocks are up (medians of GPU time: the frame's
passes plus, for ao, the shadow field's update) and scored: the mean |mode - reference| over
the linear image's RGB, and the largest mean over 16x16-pixel blocks (a local artefact).

  --width N --height N   image size                                  [1920 x 1080]
  --reference-spp N      AO rays per pixel of the reference, 1..4096  [256]
  --warmup N             shadow-field updates / cache frames first    [64]
  --frames N             timed frames per mode, 1..1000               [16]
  --ao-distance D        AO rays longer than D are open (the shadow field's and the cache's;
                         closed rooms need a finite D, else their AO is all 0)  [1e30]
  --world-cache NAME=VALUE  a world-cache parameter (repeatable); --world-cache help
  --backend B --device NAME --validation --log-level L
)";

struct AoJob {
  std::vector<std::string> scenes;
  uint32_t width = 1920;
  uint32_t height = 1080;
  uint32_t reference_spp = 256;
  uint32_t warmup = 64;
  uint32_t frames = 16;
  float ao_distance = 1e30f;
  WorldCacheParams cache;
};

Result<AoJob> parse_job(const Flags& flags) {
  AoJob job;
  job.scenes = flags.positional();
  if (job.scenes.empty()) return invalid_argument("name at least one SCENE (see --help)");
  DDGI_ASSIGN_OR_RETURN(const int64_t width, flags.get_int("width", 1920, 1, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t height, flags.get_int("height", 1080, 1, 16384));
  DDGI_ASSIGN_OR_RETURN(const int64_t spp, flags.get_int("reference-spp", 256, 1, 4096));
  DDGI_ASSIGN_OR_RETURN(const int64_t warmup, flags.get_int("warmup", 64, 0, 100000));
  DDGI_ASSIGN_OR_RETURN(const int64_t frames, flags.get_int("frames", 16, 1, 1000));
  DDGI_ASSIGN_OR_RETURN(const double distance, flags.get_double("ao-distance", 1e30, 1e-30, 1e30));
  job.width = uint32_t(width);
  job.height = uint32_t(height);
  job.reference_spp = uint32_t(spp);
  job.warmup = uint32_t(warmup);
  job.frames = uint32_t(frames);
  job.ao_distance = float(distance);
  job.cache.ao_distance = job.ao_distance;
  DDGI_TRY(world_cache_param_table().apply(job.cache, flags.get_all("world-cache")));
  return job;
}

struct Score {
  double mean = 0.0;        // mean |a - b| over RGB
  double worst_tile = 0.0;  // the largest such mean over 16x16-pixel tiles
};

Score score(const std::vector<float>& image, const std::vector<float>& reference, uint32_t width,
            uint32_t height) {
  constexpr uint32_t kTile = 16;
  Score s;
  double total = 0.0;
  for (uint32_t ty = 0; ty < height; ty += kTile) {
    for (uint32_t tx = 0; tx < width; tx += kTile) {
      double tile = 0.0;
      uint32_t count = 0;
      for (uint32_t y = ty; y < std::min(height, ty + kTile); ++y) {
        for (uint32_t x = tx; x < std::min(width, tx + kTile); ++x) {
          const size_t i = (size_t(y) * width + x) * 4;
          for (size_t c = 0; c < 3; ++c) tile += std::abs(image[i + c] - reference[i + c]);
          count += 3;
        }
      }
      total += tile;
      s.worst_tile = std::max(s.worst_tile, tile / count);
    }
  }
  s.mean = total / (double(width) * height * 3);
  return s;
}

struct Mode {
  std::string name;
  DirectMode direct;
  uint32_t ao_samples;
};

// One mode: warmed up, timed (after the clocks are up), its last image scored.
Status measure_mode(const AoJob& job, const std::string& scene_name, GiStack& gi,
                    Renderer& renderer, FrameSettings settings, const Mode& mode,
                    const std::vector<float>& reference) {
  settings.direct_mode = mode.direct;
  settings.ao_samples = mode.ao_samples;
  const bool shadow = mode.direct == DirectMode::kAmbientOcclusion;
  const bool cache = mode.direct == DirectMode::kAoCache;
  auto one_frame = [&]() -> Result<FrameResult> {
    DDGI_ASSIGN_OR_RETURN(const auto update, gi.frame_update(mode.direct, {0, 1}));
    return renderer.render(settings, update);
  };
  for (uint32_t i = 0; i < (cache ? job.warmup : 1u); ++i) DDGI_TRY(one_frame());
  const auto untimed = [&]() -> Status {
    auto frame = one_frame();
    if (!frame.ok()) return frame.error();
    return ok_status();
  };
  DDGI_TRY(tools::keep_gpu_busy(tools::kClockRampUp, untimed));
  tools::PassTable table;
  FrameResult last;
  for (uint32_t i = 0; i < job.frames; ++i) {
    DDGI_ASSIGN_OR_RETURN(last, one_frame());
    table.add(last.pass_times);
  }
  const double frame_ms =
      table.group_median(vk::PassGroup::kFrame) + table.group_median(vk::PassGroup::kShadowField);
  const Score s = score(last.radiance, reference, settings.width, settings.height);
  const uint64_t bytes = shadow  ? gi.shadow_field()->gpu_bytes()
                         : cache ? renderer.world_cache()->gpu_bytes()
                                 : 0;
  std::printf("| %s | %s | %.3f | %.4f | %.4f | %.1f |\n", scene_name.c_str(), mode.name.c_str(),
              frame_ms, s.mean, s.worst_tile, double(bytes) / (1 << 20));
  std::fflush(stdout);
  return ok_status();
}

Status measure_scene(const AoJob& job, vk::Context& context, const std::string& path) {
  DDGI_ASSIGN_OR_RETURN(Scene scene, tools::load_scene_logged(path));
  scene.lights.clear();
  scene.environment.color = glm::vec3(1.0f);
  scene.environment.image.reset();
  scene.environment.intensity = 1.0f;
  DDGI_ASSIGN_OR_RETURN(const GiStackOptions options,
                        fitted_gi_options(scene, false, DirectMode::kAmbientOcclusion, {},
                                          {"ao_distance=" + param_detail::exact(job.ao_distance)},
                                          context.default_backend()));
  DDGI_ASSIGN_OR_RETURN(auto gi, GiStack::create(context, scene, options));
  DDGI_ASSIGN_OR_RETURN(auto renderer,
                        Renderer::create(context, gi->scene(), nullptr, context.default_backend(),
                                         gi->shadow_field()));
  DDGI_TRY(renderer->set_world_cache_params(job.cache));
  DDGI_TRY(gi->warm_up(job.warmup));
  FrameSettings settings;
  settings.width = job.width;
  settings.height = job.height;
  settings.camera = default_camera(scene);
  settings.view = View::kDirect;
  settings.tonemap = Tonemap::kClamp;
  settings.read_radiance = true;
  settings.direct_mode = DirectMode::kAoTraced;
  settings.ao_samples = job.reference_spp;
  DDGI_ASSIGN_OR_RETURN(const FrameResult reference, renderer->render(settings));
  const std::string name = tools::file_stem(path);
  const std::vector<Mode> modes = {{"ao-traced 1 ray", DirectMode::kAoTraced, 1},
                                   {"ao-traced 4 rays", DirectMode::kAoTraced, 4},
                                   {"ao-traced 16 rays", DirectMode::kAoTraced, 16},
                                   {"ao (shadow field)", DirectMode::kAmbientOcclusion, 1},
                                   {"ao-cache", DirectMode::kAoCache, 1}};
  for (const Mode& mode : modes) {
    DDGI_TRY(measure_mode(job, name, *gi, *renderer, settings, mode, reference.radiance));
  }
  return ok_status();
}

Status run(int argc, char** argv) {
  DDGI_ASSIGN_OR_RETURN(
      const Flags flags,
      Flags::parse(argc, argv,
                   {"width", "height", "reference-spp", "warmup", "frames", "ao-distance",
                    "world-cache", "backend", "device", "log-level"},
                   {"validation", "help"}));
  if (flags.has("help")) {
    std::fputs(kUsage, stdout);
    return ok_status();
  }
  const std::vector<std::string> cache_assignments = flags.get_all("world-cache");
  if (!cache_assignments.empty() && cache_assignments.front() == "help") {
    std::fputs(world_cache_param_table().help().c_str(), stdout);
    return ok_status();
  }
  DDGI_ASSIGN_OR_RETURN(const AoJob job, parse_job(flags));
  DDGI_ASSIGN_OR_RETURN(auto context, tools::context_from_flags(flags));
  std::printf("%ux%u, reference %u AO rays per pixel, AO distance %g, device %s\n\n", job.width,
              job.height, job.reference_spp, double(job.ao_distance),
              context->caps().device_name.c_str());
  std::printf("| scene | mode | GPU ms per frame | mean error | worst 16x16 tile | MiB |\n");
  std::printf("| --- | --- | ---: | ---: | ---: | ---: |\n");
  for (const std::string& path : job.scenes) DDGI_TRY(measure_scene(job, *context, path));
  return context->no_validation_messages();
}

}  // namespace
}  // namespace ddgi

int main(int argc, char** argv) {
  return ddgi::tools::tool_main("ddgi-ao-eval", ddgi::run, argc, argv);
}
