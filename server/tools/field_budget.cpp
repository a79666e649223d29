// The time budget's candidates, calibration, choice and cache (tools/field_budget.h).
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

// Untimed frames before a candidate's timed ones: the first candidate follows the reference's
// readback and a clock that may have fallen (kClockRampUp); the later ones follow a warm-up
// and a small image's scoring, a GPU idle for far less than the 1.4 s after which the clock
// was seen to fall, so a tenth of a second is enough.
std::chrono::milliseconds untimed_before(size_t candidate_index) {
  return candidate_index == 0 ? kClockRampUp : std::chrono::milliseconds(100);
}

// The medians of `frames` timed frames of the budget's size, one field update each, after
// untimed ones for `untimed` (clocks up after the CPU-side work before).
Status time_frames(GiStack& gi, Renderer& renderer, FrameSettings settings, uint32_t frames,
                   std::chrono::milliseconds untimed, CalibratedCandidate& out) {
  settings.read_radiance = false;
  DDGI_TRY(render_for(renderer, settings, untimed));
  PassTable table;
  for (uint32_t f = 0; f < frames; ++f) {
    DDGI_ASSIGN_OR_RETURN(const auto update, gi.frame_update(settings.direct_mode, {}));
    DDGI_ASSIGN_OR_RETURN(const FrameResult frame, renderer.render(settings, update));
    table.add(frame.pass_times);
  }
  out.field_ms = table.group_median(vk::PassGroup::kIrradianceField);
  out.frame_ms = table.group_median(vk::PassGroup::kFrame);
  return ok_status();
}

// One candidate: the field set to it and warmed up, timed (or its injected cost), then a frame
// of the scored size compared with the reference.
Result<CalibratedCandidate> measure(GiStack& gi, Renderer& renderer, const GiStackOptions& base,
                                    const BudgetCandidate& candidate, size_t index,
                                    const ReferencePair& reference,
                                    const CalibrationOptions& options) {
  const PathTraceSettings& view = reference.settings;
  IrradianceFieldParams params = base.field;
  DDGI_TRY(field_param_table().apply(params, candidate.assignments));
  DDGI_TRY(gi.field()->set_params(params));
  gi.track(view.camera.position);  // a tracking field is placed around the view, as in a session
  DDGI_TRY(gi.warm_up(options.warmup_updates));
  CalibratedCandidate out{candidate};
  FrameSettings settings;
  settings.camera = view.camera;
  settings.direct_mode = base.direct_mode;
  settings.exposure = reference.exposure;
  if (options.injected_ms.empty()) {
    settings.width = options.width;
    settings.height = options.height;
    DDGI_TRY(time_frames(gi, renderer, settings, options.timed_frames, untimed_before(index), out));
  } else {
    out.field_ms = 0.0;
    out.frame_ms = options.injected_ms[index];
  }
  settings.width = view.width;
  settings.height = view.height;
  settings.read_radiance = true;
  DDGI_ASSIGN_OR_RETURN(const FrameResult frame, renderer.render(settings));
  DDGI_ASSIGN_OR_RETURN(const ImageScores scores,
                        score(reference.full.ldr, reference.full.radiance, frame.ldr,
                              frame.radiance, view.width, view.height));
  out.flip = scores.flip;
  out.mean_ratio = scores.mean_ratio;
  if (options.score_indirect) {
    settings.view = View::kIndirect;
    DDGI_ASSIGN_OR_RETURN(const FrameResult indirect, renderer.render(settings));
    out.indirect_ratio = mean_ratio(indirect.radiance, reference.second.radiance);
  }
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
                                               const IrradianceFieldParams& base) {
  std::vector<std::pair<std::string, std::vector<std::string>>> grids = {{"", {}}};
  if (coarser_grid_exists(base)) grids.push_back({", coarse", coarse_grid(base)});
  // Emitter light sampled or carried by the field, whichever the base does not do; a base that
  // takes several samples also gets one: unbiased as well, at half the shadow rays per pixel and
  // probe-ray hit (per pixel: an estimated half of staircase's 1080p frame).
  std::vector<std::pair<std::string, std::vector<std::string>>> emitters = {{"", {}}};
  if (scene.has_emissive_surfaces() && base.emitter_samples == 0) {
    emitters.push_back({", emitters " + std::to_string(kSceneEmitterSamples),
                        {"emitter_samples=" + std::to_string(kSceneEmitterSamples)}});
  } else if (scene.has_emissive_surfaces()) {
    if (base.emitter_samples > 1) emitters.push_back({", emitters 1", {"emitter_samples=1"}});
    emitters.push_back({", emitters via field", {"emitter_samples=0"}});
  }
  std::vector<BudgetCandidate> candidates;
  for (const uint32_t rays : {32u, 64u, 128u, 256u}) {
    for (const auto& [grid_name, grid] : grids) {
      for (const auto& [emitter_name, emitter] : emitters) {
        BudgetCandidate c{"rays " + std::to_string(rays) + grid_name + emitter_name,
                          {"rays_per_probe=" + std::to_string(rays)}};
        c.assignments.insert(c.assignments.end(), grid.begin(), grid.end());
        c.assignments.insert(c.assignments.end(), emitter.begin(), emitter.end());
        candidates.push_back(std::move(c));
      }
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
  scored.second_spp = options.score_indirect ? options.reference_spp : 0;
  scored.exposure = auto_exposure;
  DDGI_ASSIGN_OR_RETURN(const ReferencePair reference,
                        reference_pair(context, gi->scene(), scored));
  Calibration calibration;
  calibration.device = context.caps().device_name;
  calibration.width = options.width;
  calibration.height = options.height;
  for (size_t i = 0; i < candidates.size(); ++i) {
    DDGI_ASSIGN_OR_RETURN(CalibratedCandidate point,
                          measure(*gi, *renderer, base, candidates[i], i, reference, options));
    LOG_INFO << options.purpose << " calibration " << i + 1 << "/" << candidates.size() << " '"
             << point.candidate.name << "': " << point.cost_ms() << " ms (field " << point.field_ms
             << " + frame " << point.frame_ms << "), FLIP " << point.flip << ", mean/ref "
             << point.mean_ratio
             << (options.score_indirect ? ", indirect " + std::to_string(point.indirect_ratio)
                                        : "");
    calibration.candidates.push_back(std::move(point));
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

Result<size_t> choose_within_budget(const Calibration& calibration, double budget_ms) {
  DDGI_TRY(check_budget_ms(budget_ms));
  if (calibration.candidates.empty()) return invalid_argument("the calibration has no candidates");
  std::optional<size_t> best;
  size_t cheapest = 0;
  for (size_t i = 0; i < calibration.candidates.size(); ++i) {
    const CalibratedCandidate& c = calibration.candidates[i];
    if (c.cost_ms() < calibration.candidates[cheapest].cost_ms()) cheapest = i;
    if (c.cost_ms() > budget_ms) continue;
    const CalibratedCandidate* b = best ? &calibration.candidates[*best] : nullptr;
    if (!b || c.flip < b->flip || (c.flip == b->flip && c.cost_ms() < b->cost_ms())) best = i;
  }
  if (best) return *best;
  const CalibratedCandidate& c = calibration.candidates[cheapest];
  char text[320];
  std::snprintf(text, sizeof text,
                "budget_ms %g cannot be met: the cheapest configuration measured for this scene "
                "on %s at %ux%u, '%s', costs %.3f ms per frame (field %.3f + frame %.3f)",
                budget_ms, calibration.device.c_str(), calibration.width, calibration.height,
                c.candidate.name.c_str(), c.cost_ms(), c.field_ms, c.frame_ms);
  return failed_precondition(text);
}

std::string calibration_key(const vk::Context& context, const Scene& scene,
                            const GiStackOptions& base, const CalibrationOptions& options) {
  std::ostringstream key;
  key << std::hex << scene_hash(scene) << std::dec << "|" << context.caps().device_name << "|"
      << context.caps().driver_name << "|" << options.width << "x" << options.height << "|"
      << options.reference_spp << "|" << options.warmup_updates << "|" << options.timed_frames
      << "|" << options.score_indirect << "|" << static_cast<int>(base.direct_mode) << "|"
      << static_cast<int>(base.backend) << "|" << params_text(field_param_table(), base.field);
  // The shadow field's parameters count only where there is one.
  if (uses_shadow_field(shadow_field_mode(base.direct_mode, &base.field))) {
    key << "|" << params_text(shadow_param_table(), base.shadow);
  }
  for (const double ms : options.injected_ms) key << "|" << ms;
  return key.str();
}

Result<BudgetChoice> apply_budget(vk::Context& context, const Scene& scene, const Camera& camera,
                                  GiStackOptions& base, double budget_ms,
                                  const CalibrationOptions& options, BudgetCache& cache) {
  DDGI_TRY(check_budget_ms(budget_ms));  // before seconds of calibration, not after
  BudgetChoice choice;
  choice.budget_ms = budget_ms;
  const std::vector<BudgetCandidate> candidates = budget_candidates(scene, base.field);
  DDGI_ASSIGN_OR_RETURN(
      const Calibration calibration,
      cache.get_or_measure(
          calibration_key(context, scene, base, options),
          [&] { return calibrate(context, scene, camera, base, candidates, options); },
          choice.from_cache));
  DDGI_ASSIGN_OR_RETURN(const size_t index, choose_within_budget(calibration, budget_ms));
  choice.chosen = calibration.candidates[index];
  choice.device = calibration.device;
  choice.width = calibration.width;
  choice.height = calibration.height;
  choice.candidates = calibration.candidates.size();
  choice.calibration_seconds = calibration.seconds;
  DDGI_TRY(field_param_table().apply(base.field, choice.chosen.candidate.assignments));
  return choice;
}

}  // namespace ddgi::tools
