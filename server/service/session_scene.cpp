// A session's loaded scene: loading, lights, frames (service/session_scene.h).
#include "service/session_scene.h"

#include <algorithm>

#include "core/log.h"
#include "gi/field_params.h"
#include "gi/param_table.h"
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

// The server's default where the session set no budget (or 0).
double session_budget_ms(std::optional<double> own, const BudgetService& budget) {
  return own.value_or(0.0) > 0.0 ? *own : budget.default_ms;
}

}  // namespace

void SessionScene::take_cached_calibration(vk::Context& context, const Scene& scene,
                                           const SessionOptions& options, BudgetService& budget,
                                           GiStackOptions& gi_options) {
  if (!options.gi) return;
  if (!budget.calibrator) {
    calibration_off_ = budget.off_reason;
    return;
  }
  calibration_key_ = tools::calibration_key(context, scene, gi_options, budget.calibration, fixed_);
  std::optional<tools::Calibration> kept = budget.cache.find(calibration_key_);
  if (!kept) return;
  calibration_ = std::make_shared<const tools::Calibration>(std::move(*kept));
  calibration_from_cache_ = true;
  const Result<tools::BudgetChoice> choice = tools::choose_configuration(*calibration_, budget_ms_);
  if (!choice.ok()) return;  // an empty calibration file: the static default stays
  choice_ = *choice;
  choice_->from_cache = true;
  const Status applied =
      field_param_table().apply(gi_options.field, choice_->chosen.candidate.assignments);
  if (!applied.ok()) choice_.reset();  // a file of another parameter table: nothing applied
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
  loaded->base_ = gi_options;
  loaded->fixed_ = options.field_assignments;
  loaded->budget_ms_ = session_budget_ms(options.budget_ms, budget);
  if (options.budget_ms.value_or(0.0) > 0.0 && !options.gi) {
    return failed_precondition(
        "budget_ms chooses the irradiance field's configuration; this session has gi false");
  }
  loaded->take_cached_calibration(context, scene, options, budget, gi_options);
  DDGI_ASSIGN_OR_RETURN(loaded->gi_, GiStack::create(context, scene, gi_options));
  // As ddgi-render does: fast convergence first, then the configured hysteresis.
  DDGI_TRY(loaded->gi_->warm_up(request.warmup_updates));
  loaded->context_ = &context;
  loaded->label_ = request.label;
  loaded->warnings_ = scene.warnings;
  loaded->warmup_updates_ = request.warmup_updates;
  loaded->lights_ = LightSet(loaded->gpu_scene().scene().lights);
  loaded->loaded_at_ = std::chrono::steady_clock::now();
  IrradianceField* field = loaded->field();
  LOG_INFO << "scene loaded session=" << session_id << " scene=" << request.label
           << " triangles=" << loaded->gpu_scene().triangle_count()
           << " lights=" << loaded->lights_.size()
           << " gpu_bytes=" << loaded->gpu_scene().gpu_bytes() + (field ? field->gpu_bytes() : 0)
           << " warmup=" << (field ? request.warmup_updates : 0);
  if (loaded->choice_) {
    LOG_INFO << "configuration session=" << session_id << " scene=" << request.label << " "
             << tools::describe(*loaded->choice_);
  } else if (options.gi && budget.calibrator) {
    loaded->scene_to_calibrate_ = std::make_shared<const Scene>(std::move(scene));
  }
  return loaded;
}

void SessionScene::start_calibration(BudgetService& budget, std::function<void()> landed) {
  if (!scene_to_calibrate_) return;  // cached, no field, or no calibrator
  const std::vector<tools::BudgetCandidate> candidates =
      tools::budget_candidates(*scene_to_calibrate_, base_.field, fixed_);
  const std::string key = calibration_key_;
  auto measure = [context = context_, scene = scene_to_calibrate_, camera = default_camera_,
                  base = base_, candidates, options = budget.calibration, cache = &budget.cache,
                  key](tools::CalibrationOptions::Hooks hooks) -> Result<tools::Calibration> {
    tools::CalibrationOptions with_hooks = options;
    with_hooks.hooks = std::move(hooks);
    DDGI_ASSIGN_OR_RETURN(tools::Calibration calibration,
                          tools::calibrate(*context, *scene, camera, base, candidates, with_hooks));
    cache->put(key, calibration);
    return calibration;
  };
  Calibrator::Ticket ticket =
      budget.calibrator->request(key, candidates.size(), std::move(measure));
  job_ = std::move(ticket.job);
  wants_job_ = std::move(ticket.interest);
  job_->listen([landed = std::move(landed)](const CalibrationJob&) { landed(); });
}

Status SessionScene::adopt_calibration(const std::string& session_id) {
  using State = CalibrationJob::State;
  if (!job_ || job_->state() == State::kQueued || job_->state() == State::kRunning) {
    return ok_status();
  }
  const CalibrationJob& job = *job_;
  scene_to_calibrate_.reset();
  wants_job_.reset();
  if (job.state() != State::kDone) {
    calibration_error_ = job.error().empty() ? state_name(job.state()) : job.error();
    LOG_WARNING << "calibration failed session=" << session_id << " scene=" << label_ << ": "
                << calibration_error_ << "; the field keeps the static default";
    job_.reset();
    return ok_status();
  }
  calibration_ = job.result();
  job_.reset();
  if (hand_set_) return ok_status();  // set by hand meanwhile: a later budget_ms chooses
  DDGI_TRY(follow_choice({}, session_id));
  switched_after_s_ =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - loaded_at_).count();
  return ok_status();
}

Status SessionScene::follow_choice(const std::vector<std::string>& hand_set,
                                   const std::string& session_id) {
  DDGI_ASSIGN_OR_RETURN(tools::BudgetChoice choice,
                        tools::choose_configuration(*calibration_, budget_ms_));
  choice.from_cache = calibration_from_cache_;
  IrradianceFieldParams params = base_.field;
  DDGI_TRY(field_param_table().apply(params, choice.chosen.candidate.assignments));
  DDGI_TRY(field_param_table().apply(params, hand_set));
  const IrradianceFieldParams before = field()->params();
  DDGI_TRY(field()->set_params(params));
  // A new grid starts from nothing: warmed up as at load, not shown dark.
  if (before.counts != params.counts || before.spacing != params.spacing) {
    DDGI_TRY(gi_->warm_up(warmup_updates_));
  }
  choice_ = std::move(choice);
  hand_set_ = false;
  LOG_INFO << "configuration session=" << session_id << " scene=" << label_ << " "
           << tools::describe(*choice_);
  return ok_status();
}

Status SessionScene::set_field_budget(double budget_ms, const std::vector<std::string>& hand_set,
                                      const BudgetService& budget, const std::string& session_id) {
  budget_ms_ = session_budget_ms(budget_ms, budget);
  if (calibration_) return follow_choice(hand_set, session_id);
  // Not calibrated (yet): the parameters apply now, the budget once the calibration lands.
  IrradianceFieldParams params = field()->params();
  DDGI_TRY(field_param_table().apply(params, hand_set));
  DDGI_TRY(field()->set_params(params));
  hand_set_ = false;
  return ok_status();
}

void SessionScene::calibration_to_proto(v1::FieldCalibration* out) const {
  using State = v1::FieldCalibration;
  out->set_budget_ms(budget_ms_);
  if (!calibration_off_.empty()) {
    out->set_state(State::STATE_OFF);
    out->set_message(calibration_off_);
  } else if (!calibration_error_.empty()) {
    out->set_state(State::STATE_FAILED);
    out->set_message(calibration_error_);
  } else if (calibration_) {
    out->set_state(State::STATE_DONE);
    out->set_candidates_done(static_cast<uint32_t>(calibration_->candidates.size()));
    out->set_candidates(static_cast<uint32_t>(calibration_->candidates.size()));
    out->set_from_cache(calibration_from_cache_);
    out->set_seconds(switched_after_s_);
    out->set_switched(choice_.has_value());
    if (hand_set_) out->set_message("parameters set by hand: set budget_ms to follow the choice");
  } else if (job_) {
    const bool running = job_->state() == CalibrationJob::State::kRunning;
    out->set_state(running ? State::STATE_RUNNING : State::STATE_QUEUED);
    out->set_candidates_done(static_cast<uint32_t>(job_->done()));
    out->set_candidates(static_cast<uint32_t>(job_->total()));
    out->set_seconds(job_->seconds());
  } else {
    out->set_state(State::STATE_OFF);
    out->set_message("the session has no irradiance field");
  }
}

uint64_t SessionScene::gpu_bytes() const {
  return gpu_scene().gpu_bytes() + (field() ? field()->gpu_bytes() : 0) +
         (shadow_field() ? shadow_field()->gpu_bytes() : 0) +
         (world_cache() ? world_cache()->gpu_bytes() : 0);
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
