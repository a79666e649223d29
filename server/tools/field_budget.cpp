// A session's candidate configurations, their calibration and its cache key (tools/field_budget.h).
#include "tools/field_budget.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/hash.h"
#include "core/log.h"
#include "gi/field_params.h"
#include "gi/param_table.h"
#include "gi/shadow_params.h"
#include "render/renderer.h"
#include "tools/eval_job.h"
#include "tools/reference_render.h"
#include "tools/tool_support.h"

namespace ddgi::tools {
namespace {

// Half the probes per axis over the same extent (at least two where there were two or more),
// as assignments written by the parameter table itself (text it reads back exactly).
std::vector<std::string> coarse_grid(const IrradianceFieldParams& base) {
  IrradianceFieldParams coarse = base;
  for (int axis = 0; axis < 3; ++axis) {
    const int n = base.counts[axis];
    if (n < 3) continue;
    coarse.counts[axis] = (n + 1) / 2;
    coarse.spacing[axis] = base.spacing[axis] * float(n - 1) / float(coarse.counts[axis] - 1);
  }
  std::vector<std::string> assignments;
  for (const char* name : {"counts", "spacing"}) {
    assignments.push_back(std::string(name) + "=" + field_param_table().get(coarse, name).value());
  }
  return assignments;
}

bool coarser_grid_exists(const IrradianceFieldParams& base) {
  return base.cascades == 1 && base.static_volumes.empty() &&
         glm::any(glm::greaterThanEqual(base.counts, glm::ivec3(3)));
}

// One axis's value: its name in a candidate's name ("" for the base's) and assignments.
struct Axis {
  std::string name;
  std::vector<std::string> assignments;
};

// A candidate of one value per axis: names joined by ", " ("static default" for none).
BudgetCandidate combine(std::initializer_list<Axis> values) {
  BudgetCandidate c;
  for (const Axis& v : values) {
    if (!v.name.empty()) c.name += (c.name.empty() ? "" : ", ") + v.name;
    c.assignments.insert(c.assignments.end(), v.assignments.begin(), v.assignments.end());
  }
  if (c.name.empty()) c.name = "static default";
  return c;
}

// Emitter light sampled or carried by the field, whichever the base does not do; a base that
// takes several samples also gets one: unbiased as well, at half the shadow rays per pixel and
// probe-ray hit. Only the base's where the scene has no emissive surface.
std::vector<Axis> emitter_axis(const Scene& scene, const IrradianceFieldParams& base) {
  std::vector<Axis> axis = {{"", {}}};
  if (!scene.has_emissive_surfaces()) return axis;
  if (base.emitter_samples == 0) {
    axis.push_back({"emitters " + std::to_string(kSceneEmitterSamples),
                    {"emitter_samples=" + std::to_string(kSceneEmitterSamples)}});
    return axis;
  }
  if (base.emitter_samples > 1) axis.push_back({"emitters 1", {"emitter_samples=1"}});
  axis.push_back({"emitters via field", {"emitter_samples=0"}});
  return axis;
}

// Untimed frames before a candidate's timed ones: the first candidate follows the reference's
// readback and a clock that may have fallen (kClockRampUp); the later ones follow a warm-up
// and a small image's scoring, a GPU idle for far less than the 1.4 s after which the clock
// was seen to fall, so a tenth of a second is enough.
std::chrono::milliseconds untimed_before(size_t candidate_index) {
  return candidate_index == 0 ? kClockRampUp : std::chrono::milliseconds(100);
}

// The medians of the timed frames of the budget's size, one field update each (with the shadow
// field's, where the session has one), after untimed ones for `untimed` (clocks up after the
// CPU-side work before). A first frame over `options.slow_frame_ms` is the only one.
Status time_frames(GiStack& gi, Renderer& renderer, FrameSettings settings,
                   const CalibrationOptions& options, std::chrono::milliseconds untimed,
                   CalibratedCandidate& out) {
  settings.read_radiance = false;
  DDGI_TRY(render_for(renderer, settings, untimed));
  PassTable table;
  for (uint32_t f = 0; f < options.timed_frames; ++f) {
    DDGI_ASSIGN_OR_RETURN(const auto update, gi.frame_update(settings.direct_mode, {}));
    DDGI_ASSIGN_OR_RETURN(const FrameResult frame, renderer.render(settings, update));
    table.add(frame.pass_times);
    out.timed_frames = f + 1;
    out.shadow_ms = table.group_median(vk::PassGroup::kShadowField);
    out.field_ms = table.group_median(vk::PassGroup::kIrradianceField);
    out.frame_ms = table.group_median(vk::PassGroup::kFrame);
    if (f == 0 && out.cost_ms() > options.slow_frame_ms) break;
  }
  return ok_status();
}

// The mean of `values` and its standard error (sample deviation / sqrt(n)).
std::pair<double, double> mean_and_error(const std::vector<double>& values) {
  double mean = 0.0;
  for (const double v : values) mean += v;
  mean /= double(values.size());
  double squares = 0.0;
  for (const double v : values) squares += (v - mean) * (v - mean);
  const double n = double(values.size());
  return {mean, n > 1 ? std::sqrt(squares / (n - 1) / n) : 0.0};
}

// Scores options.scored_frames frames of the scored size, one more field update before each
// after the first: their mean errors and the noise of those means.
Status score_frames(GiStack& gi, Renderer& renderer, FrameSettings settings,
                    const ReferencePair& reference, const CalibrationOptions& options,
                    CalibratedCandidate& out) {
  const PathTraceSettings& view = reference.settings;
  settings.width = view.width;
  settings.height = view.height;
  settings.read_radiance = true;
  std::vector<double> flips, ratios;
  for (uint32_t f = 0; f < options.scored_frames; ++f) {
    if (f > 0) DDGI_TRY(gi.update(1));
    DDGI_ASSIGN_OR_RETURN(const FrameResult frame, renderer.render(settings));
    DDGI_ASSIGN_OR_RETURN(const ImageScores scores,
                          score(reference.full.ldr, reference.full.radiance, frame.ldr,
                                frame.radiance, view.width, view.height));
    flips.push_back(scores.flip);
    ratios.push_back(scores.mean_ratio);
  }
  std::tie(out.flip, out.flip_noise) = mean_and_error(flips);
  double frames_noise = 0.0;
  std::tie(out.mean_ratio, frames_noise) = mean_and_error(ratios);
  out.mean_ratio_noise = std::hypot(frames_noise, out.mean_ratio * reference.mean_noise);
  return ok_status();
}

// One candidate: the field set to it and warmed up, timed (or its injected cost), then frames
// of the scored size compared with the reference.
Result<CalibratedCandidate> measure(GiStack& gi, Renderer& renderer, const GiStackOptions& base,
                                    const BudgetCandidate& candidate, size_t index,
                                    const ReferencePair& reference,
                                    const CalibrationOptions& options) {
  IrradianceFieldParams params = base.field;
  DDGI_TRY(field_param_table().apply(params, candidate.assignments));
  DDGI_TRY(gi.field()->set_params(params));
  gi.track(reference.settings.camera.position);  // a tracking field is placed around the view
  DDGI_TRY(gi.warm_up(options.warmup_updates));
  CalibratedCandidate out{candidate};
  FrameSettings settings;
  settings.camera = reference.settings.camera;
  settings.direct_mode = base.direct_mode;
  settings.exposure = reference.exposure;
  if (options.injected_ms.empty()) {
    settings.width = options.width;
    settings.height = options.height;
    DDGI_TRY(time_frames(gi, renderer, settings, options, untimed_before(index), out));
  } else {
    out.frame_ms = options.injected_ms[index];
  }
  DDGI_TRY(score_frames(gi, renderer, settings, reference, options, out));
  return out;
}

using ddgi::fnv1a;  // beside the overload below, not hidden by it

template <typename T>
uint64_t fnv1a(uint64_t hash, const std::vector<T>& values) {
  return fnv1a(hash, values.data(), values.size() * sizeof(T));
}

// What decides a calibration's result in the scene: geometry, placement, materials, lights.
uint64_t scene_hash(const Scene& scene) {
  uint64_t hash = kFnv1aSeed;
  for (const Mesh& mesh : scene.meshes) {
    for (const Primitive& primitive : mesh.primitives) {
      hash = fnv1a(hash, primitive.positions);
      hash = fnv1a(hash, primitive.indices);
      hash = fnv1a(hash, &primitive.material, sizeof(primitive.material));
    }
  }
  for (const Instance& instance : scene.instances) {
    hash = fnv1a(hash, &instance.mesh, sizeof(instance.mesh));
    hash = fnv1a(hash, &instance.transform, sizeof(instance.transform));
  }
  for (const Material& material : scene.materials) {
    hash = fnv1a(hash, &material.base_color, sizeof(material.base_color));
    hash = fnv1a(hash, &material.emissive, sizeof(material.emissive));
    hash = fnv1a(hash, &material.base_color_texture, sizeof(material.base_color_texture));
  }
  for (const Light& light : scene.lights) {
    // Member by member: the struct holds a name (a pointer) and padding.
    for (const float value :
         {float(light.type), light.color.x, light.color.y, light.color.z, light.intensity,
          light.range, light.inner_cone_angle, light.outer_cone_angle, light.position.x,
          light.position.y, light.position.z, light.direction.x, light.direction.y,
          light.direction.z, light.radius}) {
      hash = fnv1a(hash, &value, sizeof(value));
    }
  }
  // Textures and the environment image by size only: hashing their pixels would cost more than
  // it saves on every load, and a scene that changes only its pixels is rare.
  for (const Texture& texture : scene.textures) {
    hash = fnv1a(hash, &texture.width, sizeof(texture.width));
    hash = fnv1a(hash, &texture.height, sizeof(texture.height));
  }
  const Environment& environment = scene.environment;
  hash = fnv1a(hash, &environment.color, sizeof(environment.color));
  hash = fnv1a(hash, &environment.intensity, sizeof(environment.intensity));
  hash = fnv1a(hash, &environment.rotation_y, sizeof(environment.rotation_y));
  const uint32_t image_width = environment.image ? environment.image->width : 0;
  return fnv1a(hash, &image_width, sizeof(image_width));
}

// Every parameter of the table as text, in its order.
template <typename P>
std::string params_text(const ParamTable<P>& table, const P& params) {
  std::string text;
  for (const auto& spec : table.specs()) text += spec.name + "=" + spec.format(params) + ";";
  return text;
}

// The scored size: the budget's frame scaled down to at most 320 pixels wide.
void score_size(const CalibrationOptions& options, uint32_t& width, uint32_t& height) {
  const double scale = std::min(1.0, 320.0 / options.width);
  width = std::max(16u, static_cast<uint32_t>(std::lround(options.width * scale)));
  height = std::max(16u, static_cast<uint32_t>(std::lround(options.height * scale)));
}

}  // namespace

std::vector<BudgetCandidate> budget_candidates(const Scene& scene,
                                               const IrradianceFieldParams& base,
                                               const std::vector<std::string>& fixed) {
  const auto is_fixed = [&](std::initializer_list<const char*> names) {
    for (const std::string& f : fixed) {
      const std::string name = f.substr(0, f.find('='));
      for (const char* n : names) {
        if (name == n) return true;
      }
    }
    return false;
  };
  std::vector<Axis> gathering = {{"", {}}};
  if (!is_fixed({"probe_bounces", "self_shadow_bias", "irradiance_gamma"})) {
    gathering.push_back({"bias 0.5", {"self_shadow_bias=0.5"}});
    gathering.push_back({"paths 1", {"probe_bounces=1"}});
    gathering.push_back({"paths 1, bias 0.5", {"probe_bounces=1", "self_shadow_bias=0.5"}});
    gathering.push_back({"paths 1, gamma 1", {"probe_bounces=1", "irradiance_gamma=1"}});
  }
  std::vector<Axis> rays = {{"", {}}};
  if (!is_fixed({"rays_per_probe"})) {
    for (const uint32_t r : {32u, 64u, 256u}) {
      if (r != base.rays_per_probe) {
        rays.push_back({"rays " + std::to_string(r), {"rays_per_probe=" + std::to_string(r)}});
      }
    }
  }
  const std::vector<Axis> emitters =
      is_fixed({"emitter_samples"}) ? std::vector<Axis>{{"", {}}} : emitter_axis(scene, base);
  std::vector<BudgetCandidate> candidates;
  for (size_t g = 0; g < gathering.size(); ++g) {
    // Emitter sampling only beside the static and one-bounce gathering: the others change
    // what the field keeps, not what a pixel samples.
    const size_t emitter_count = (g == 0 || gathering[g].name == "paths 1") ? emitters.size() : 1;
    for (const Axis& r : rays) {
      for (size_t e = 0; e < emitter_count; ++e) {
        candidates.push_back(combine({gathering[g], r, emitters[e]}));
      }
    }
  }
  if (coarser_grid_exists(base) && !is_fixed({"counts", "spacing", "origin"})) {
    const Axis coarse{"coarse", coarse_grid(base)};
    const Axis few_rays = rays.size() > 1 ? rays[1] : rays[0];  // 32 rays unless fixed
    for (const Axis& e : emitters) candidates.push_back(combine({few_rays, coarse, e}));
  }
  if (!is_fixed({"pixel_paths", "pixel_path_vertices"})) {
    for (const uint32_t paths : kPixelPathCounts) {
      const std::string count = std::to_string(paths),
                        vertices = std::to_string(kPixelPathVertices);
      candidates.push_back(
          combine({{"pixel paths " + count + "x" + vertices,
                    {"pixel_paths=" + count, "pixel_path_vertices=" + vertices}}}));
    }
  }
  return candidates;
}

Status validate(const CalibrationOptions& o) {
  auto in = [](uint32_t v, uint32_t lo, uint32_t hi) { return v >= lo && v <= hi; };
  if (!in(o.width, 16, 16384) || !in(o.height, 16, 16384)) {
    return invalid_argument("the budget's frame must be 16..16384 pixels each way (got " +
                            std::to_string(o.width) + "x" + std::to_string(o.height) + ")");
  }
  if (!in(o.reference_spp, 1, 65536)) {
    return invalid_argument("calibration reference_spp must be in [1, 65536]");
  }
  if (!in(o.warmup_updates, 1, 4096)) {
    return invalid_argument("calibration warmup_updates must be in [1, 4096]");
  }
  if (!in(o.timed_frames, 1, 1000)) {
    return invalid_argument("calibration timed_frames must be in [1, 1000]");
  }
  if (!in(o.scored_frames, 2, 16)) {
    return invalid_argument("calibration scored_frames must be in [2, 16]");
  }
  if (!(o.slow_frame_ms >= 1.0 && o.slow_frame_ms <= kMaxBudgetMs)) {
    return invalid_argument("calibration slow_frame_ms must be in [1, 1e6]");
  }
  return ok_status();
}

Result<Calibration> calibrate(vk::Context& context, const Scene& scene, const Camera& camera,
                              const GiStackOptions& base,
                              const std::vector<BudgetCandidate>& candidates,
                              const CalibrationOptions& options) {
  DDGI_TRY(validate(options));
  if (!base.gi) return failed_precondition("a time budget needs the irradiance field (gi on)");
  if (candidates.empty()) return invalid_argument("no candidate configurations to calibrate");
  if (!options.injected_ms.empty() && options.injected_ms.size() != candidates.size()) {
    return invalid_argument("injected costs: " + std::to_string(options.injected_ms.size()) +
                            " for " + std::to_string(candidates.size()) + " candidates");
  }
  const auto start = std::chrono::steady_clock::now();
  DDGI_ASSIGN_OR_RETURN(auto gi, GiStack::create(context, scene, base));
  DDGI_ASSIGN_OR_RETURN(auto renderer, Renderer::create(context, gi->scene(), gi->field(),
                                                        base.backend, gi->shadow_field()));
  ReferencePairOptions scored;  // the full image alone, at the scored size
  score_size(options, scored.width, scored.height);
  scored.camera = camera;
  scored.full_spp = options.reference_spp;
  scored.second_spp = 0;
  scored.exposure = auto_exposure;
  scored.estimate_mean_noise = true;
  DDGI_ASSIGN_OR_RETURN(const ReferencePair reference,
                        reference_pair(context, gi->scene(), scored));
  Calibration calibration;
  calibration.device = context.caps().device_name;
  calibration.width = options.width;
  calibration.height = options.height;
  calibration.reference_mean = mean_luminance(reference.full.radiance);
  calibration.reference_noise = reference.mean_noise;
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (options.hooks.cancelled && options.hooks.cancelled()) {
      return unavailable("the calibration was cancelled: nobody waits for it");
    }
    DDGI_ASSIGN_OR_RETURN(CalibratedCandidate point,
                          measure(*gi, *renderer, base, candidates[i], i, reference, options));
    LOG_INFO << options.purpose << " calibration " << i + 1 << "/" << candidates.size() << " '"
             << point.candidate.name << "': " << point.cost_ms() << " ms (shadow "
             << point.shadow_ms << " + field " << point.field_ms << " + frame " << point.frame_ms
             << "), FLIP " << point.flip << " +- " << point.flip_noise << ", mean/ref "
             << point.mean_ratio << " +- " << point.mean_ratio_noise;
    calibration.candidates.push_back(std::move(point));
    if (options.hooks.progress) options.hooks.progress(i + 1, candidates.size());
  }
  calibration.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return calibration;
}

Status check_budget_ms(double budget_ms) {
  if (budget_ms > 0.0 && budget_ms <= kMaxBudgetMs) return ok_status();
  std::ostringstream text;
  text << "budget_ms must be in (0, " << kMaxBudgetMs << "] milliseconds per frame (got "
       << budget_ms << ")";
  return invalid_argument(text.str());
}

std::string calibration_key(const vk::Context& context, const Scene& scene,
                            const GiStackOptions& base, const CalibrationOptions& options,
                            const std::vector<std::string>& fixed) {
  std::ostringstream key;
  key << kCalibrationFormat << "|";
  key << std::hex << scene_hash(scene) << std::dec << "|" << context.caps().device_name << "|"
      << context.caps().driver_name << "|" << options.width << "x" << options.height << "|"
      << options.reference_spp << "|" << options.warmup_updates << "|" << options.timed_frames
      << "|" << options.scored_frames << "|" << options.slow_frame_ms << "|"
      << static_cast<int>(base.direct_mode) << "|" << static_cast<int>(base.backend) << "|"
      << params_text(field_param_table(), base.field);
  // The shadow field's parameters count only where there is one.
  if (uses_shadow_field(shadow_field_mode(base.direct_mode, &base.field))) {
    key << "|" << params_text(shadow_param_table(), base.shadow);
  }
  for (const std::string& f : fixed) key << "|fixed " << f;
  for (const double ms : options.injected_ms) key << "|" << ms;
  return key.str();
}

}  // namespace ddgi::tools
