// A session's loaded scene: loading, lights, frames (service/session_scene.h).
#include "service/session_scene.h"

#include <algorithm>

#include "core/log.h"
#include "gpu_scene/camera_fit.h"
#include "scene/gltf_loader.h"

namespace ddgi::service {
namespace {

Result<Scene> read_scene(const SceneRequest& request, const ServiceLimits& limits) {
  SceneLimits scene_limits;
  if (request.path.empty()) {
    scene_limits.max_file_bytes = std::max<uint64_t>(limits.max_upload_bytes, 1024);
    return load_glb_from_memory(request.upload, request.label, scene_limits);
  }
  return ::ddgi::load_scene(request.path, scene_limits);
}

void log_budget(const tools::BudgetChoice& c, const std::string& session_id,
                const std::string& label) {
  LOG_INFO << "time budget session=" << session_id << " scene=" << label
           << " budget_ms=" << c.budget_ms << " chosen='" << c.chosen.candidate.name
           << "' cost_ms=" << c.chosen.cost_ms() << " (field " << c.chosen.field_ms << " + frame "
           << c.chosen.frame_ms << " at " << c.width << "x" << c.height
           << ") flip=" << c.chosen.flip << " candidates=" << c.candidates
           << (c.from_cache ? " calibration=cached" : " calibration_s=")
           << (c.from_cache ? "" : std::to_string(c.calibration_seconds));
}

}  // namespace

// The energy calibration's choice over `gi_options` (before a budget's, which then varies rays
// and grid over it), where the server runs it and the session set none of its parameters. A
// calibration that fails leaves the static default and a warning: the session asked for nothing.
Status SessionScene::choose_energy(vk::Context& context, const Scene& scene,
                                   const SessionOptions& options, BudgetService& budget,
                                   const std::string& session_id, const std::string& label,
                                   GiStackOptions& gi_options) {
  if (!budget.energy || !options.gi || tools::sets_energy_params(options.field_assignments)) {
    return ok_status();
  }
  Result<tools::EnergyChoice> choice = tools::apply_energy(
      context, scene, default_camera_, gi_options, budget.energy_calibration, budget.cache);
  if (!choice.ok()) {
    if (context.device_lost()) return choice.error();
    LOG_WARNING << "energy calibration failed session=" << session_id << " scene=" << label << ": "
                << choice.error().message << "; the field keeps its static defaults";
    return ok_status();
  }
  energy_ = std::move(*choice);
  LOG_INFO << "energy calibration session=" << session_id << " scene=" << label << " "
           << tools::describe(*energy_);
  return ok_status();
}

Result<std::unique_ptr<SessionScene>> SessionScene::load(
    vk::Context& context, const SceneRequest& request, const SessionOptions& options,
    const ServiceLimits& limits, BudgetService& budget, const std::string& session_id) {
  DDGI_ASSIGN_OR_RETURN(Scene scene, read_scene(request, limits));
  for (const std::string& warning : scene.warnings) {
    LOG_WARNING << "scene warning session=" << session_id << " scene=" << request.label << ": "
                << warning;
  }
  DDGI_ASSIGN_OR_RETURN(
      GiStackOptions gi_options,
      fitted_gi_options(scene, options.gi, options.direct_mode, options.field_assignments,
                        options.shadow_assignments, context.default_backend()));
  std::unique_ptr<SessionScene> loaded(new SessionScene());
  loaded->default_camera_ = ::ddgi::default_camera(scene);
  DDGI_TRY(loaded->choose_energy(context, scene, options, budget, session_id, request.label,
                                 gi_options));
  const double budget_ms = options.budget_ms.value_or(budget.default_ms);
  if (budget_ms > 0.0 && !options.gi && options.budget_ms) {
    return failed_precondition(
        "budget_ms chooses the irradiance field's configuration; this session has gi false");
  }
  if (budget_ms > 0.0 && options.gi) {  // the server's default skips sessions without a field
    loaded->budget_base_ = gi_options.field;
    DDGI_ASSIGN_OR_RETURN(loaded->budget_,
                          tools::apply_budget(context, scene, loaded->default_camera_, gi_options,
                                              budget_ms, budget.calibration, budget.cache));
    log_budget(*loaded->budget_, session_id, request.label);
  }
  DDGI_ASSIGN_OR_RETURN(loaded->gi_, GiStack::create(context, scene, gi_options));
  // As ddgi-render does: fast convergence first, then the configured hysteresis.
  DDGI_TRY(loaded->gi_->warm_up(request.warmup_updates));
  loaded->context_ = &context;
  loaded->label_ = request.label;
  loaded->warnings_ = scene.warnings;
  loaded->lights_ = LightSet(loaded->gpu_scene().scene().lights);
  IrradianceField* field = loaded->field();
  LOG_INFO << "scene loaded session=" << session_id << " scene=" << request.label
           << " triangles=" << loaded->gpu_scene().triangle_count()
           << " lights=" << loaded->lights_.size()
           << " gpu_bytes=" << loaded->gpu_scene().gpu_bytes() + (field ? field->gpu_bytes() : 0)
           << " warmup=" << (field ? request.warmup_updates : 0);
  return loaded;
}

Status SessionScene::set_field_budget(const IrradianceFieldParams& params, DirectMode direct_mode,
                                      double budget_ms, bool ends_budget_only,
                                      BudgetService& budget, const std::string& session_id) {
  if (budget_ms == 0.0) {
    // Ending a budget alone keeps the field as it is: no restart for the same parameters.
    if (!ends_budget_only) DDGI_TRY(field()->set_params(params));
    budget_.reset();
    return ok_status();
  }
  GiStackOptions base;
  base.direct_mode = direct_mode;
  base.backend = context_->default_backend();
  base.field = params;
  if (shadow_field()) base.shadow = shadow_field()->params();
  DDGI_ASSIGN_OR_RETURN(tools::BudgetChoice choice,
                        tools::apply_budget(*context_, gpu_scene().scene(), default_camera_, base,
                                            budget_ms, budget.calibration, budget.cache));
  DDGI_TRY(field()->set_params(base.field));
  budget_ = std::move(choice);
  budget_base_ = params;
  log_budget(*budget_, session_id, label_);
  return ok_status();
}

uint64_t SessionScene::gpu_bytes() const {
  return gpu_scene().gpu_bytes() + (field() ? field()->gpu_bytes() : 0) +
         (shadow_field() ? shadow_field()->gpu_bytes() : 0);
}

Status SessionScene::upload_lights(const std::vector<Light>& lights) {
  return gpu_scene().set_lights(lights);
}

Result<LightSlot> SessionScene::add_light(const Light& light) {
  return lights_.add(light, [this](const auto& lights) { return upload_lights(lights); });
}

Result<LightSlot> SessionScene::update_light(uint32_t id, const Light& light) {
  return lights_.update(id, light, [this](const auto& lights) { return upload_lights(lights); });
}

Result<LightSlot> SessionScene::remove_light(uint32_t id) {
  return lights_.remove(id, [this](const auto& lights) { return upload_lights(lights); });
}

Result<PendingFrame> SessionScene::submit(const FrameSettings& settings, FrameTarget& target,
                                          bool field_due) {
  if (!renderer_) {
    DDGI_ASSIGN_OR_RETURN(renderer_, Renderer::create(*context_, gi_->scene(), field(),
                                                      context_->default_backend(), shadow_field()));
  }
  std::vector<vk::Pass> update;
  if (field_due) {
    DDGI_ASSIGN_OR_RETURN(update, gi_->frame_update(settings.direct_mode, {}));
  }
  return renderer_->submit(settings, target, update);
}

}  // namespace ddgi::service
