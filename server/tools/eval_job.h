// ddgi-eval's shared parts: the job its flags describe, the field configurations it compares
// (each a GI stack fitted to the scene with assignments over it) and how a frame is scored
// against the path-traced reference. The table, --pareto and --dynamic (eval_main.cpp) and
// --path (path_eval.cpp) use them alike.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/flags.h"
#include "core/result.h"
#include "gi/gi_stack.h"
#include "gpu_scene/frame_types.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "tools/pareto.h"
#include "tools/reference_render.h"
#include "vk/context.h"

namespace ddgi::tools {

// One configuration a user can choose: a name for the tables, its "name=value" field
// assignments, and how the frame is made (the issue 14 sweep's direct modes, shadow field
// resolutions and frame sizes, beside the field's own parameters).
struct Config {
  std::string name;
  std::vector<std::string> assignments;                 // field parameters (field_param_table)
  std::vector<std::string> shadow_assignments;          // "shadow.NAME=VALUE": shadow_param_table
  DirectMode direct_mode = DirectMode::kTracedShadows;  // "direct=MODE" (parse_direct_mode)
  // "frame_downscale=N", N in [1, 8]: the frame drawn at 1/N of the width and height, then
  // upscaled to the reference's size to be scored (a stream's cheaper frame, as the path
  // tracer's 1/16 and 1/4 spp points are made). It must divide both.
  uint32_t frame_downscale = 1;

  // Every choice as "name=value" text, field assignments first: what the JSON records.
  std::vector<std::string> all_assignments() const;
};

// --configs: NAME:ASSIGNMENTS entries separated by ';'.
Result<std::vector<Config>> parse_configs(const std::string& text);

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
  std::string dynamic;  // empty: no --dynamic
  int64_t response_frames = 120;
  int64_t response_static = 0;    // --dynamic: frames before the change
  std::string camera_path;        // empty: no --path
  double path_rate = 30.0;        // field updates (and frames) per second of the path
  double path_every = 10.0;       // seconds of the path between scored frames
  std::vector<double> budgets;    // --budgets: ms per frame; empty: none
  bool session_defaults = false;  // --session-defaults: a session's choice per configuration
};

Result<EvalJob> parse_job(const Flags& flags);

// --field's assignments, then the configuration's own field assignments.
std::vector<std::string> config_assignments(const EvalJob& job, const Config& config);

// A GI stack of `config` on `scene`, its grid fitted to `fitted` (the scene as loaded, so that a
// moved object does not move the grid).
Result<std::unique_ptr<GiStack>> make_gi_stack(vk::Context& context, const EvalJob& job,
                                               const Scene& fitted, const Scene& scene,
                                               const Config& config);

// The renderer of `gi`'s scene, field and shadow field (which the shadow-field and AO direct
// modes read), on the context's default backend.
Result<std::unique_ptr<Renderer>> make_renderer(vk::Context& context, GiStack& gi);

// Exposure that maps the log-average luminance of `radiance` (RGBA) to 0.18.
float auto_exposure(const std::vector<float>& radiance);

// The mean Rec. 709 luminance of linear RGBA radiance.
double mean_luminance(const std::vector<float>& rgba);

// The mean Rec. 709 luminance of linear RGBA `test` over `reference`'s ("mean/ref": 1 when a
// frame neither loses nor adds light); 0 for a black reference.
double mean_ratio(const std::vector<float>& test, const std::vector<float>& reference);

// PSNR, SSIM and FLIP of two tone-mapped images (RGBA8); mean_ratio is left 0.
Result<ImageScores> score_ldr(const std::vector<uint8_t>& reference,
                              const std::vector<uint8_t>& test, uint32_t width, uint32_t height);

// score_ldr() of the tone-mapped images, and the mean linear luminance of `test_radiance` over
// the reference's.
Result<ImageScores> score(const std::vector<uint8_t>& reference,
                          const std::vector<float>& reference_radiance,
                          const std::vector<uint8_t>& test, const std::vector<float>& test_radiance,
                          uint32_t width, uint32_t height);

// The path-traced full image and field part (everything but punctual direct light) of `scene`
// seen by `camera`, --spp samples each, exposure from the full image; written as
// DIR/STEM.reference.exr and STEM.reference-indirect.exr with --out-dir.
Result<ReferencePair> make_references(vk::Context& context, const EvalJob& job, const Scene& scene,
                                      const Camera& camera, const std::string& stem);

// DIR/NAME.exr of linear RGBA (RGB kept); nothing when `dir` is empty.
Status write_exr(const std::string& dir, const std::string& name, uint32_t width, uint32_t height,
                 const std::vector<float>& rgba);

}  // namespace ddgi::tools
