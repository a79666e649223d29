// A session's frames: what its loop calls (SessionLoop::Owner), rendering every view someone
// waits for and the one-off frames, one field update per iteration shared by all of them, and
// handing the images to the encoder (service/session.h).
#include <chrono>

#include "core/log.h"
#include "service/session.h"

namespace ddgi::service {

bool Session::wants_frame() {
  return state_.views.wants_frame() || !state_.one_offs.empty();
}

void Session::produce_frame(uint64_t index, const CommandStamp& last_applied) {
  FrameBatch batch;
  batch.index = index;
  batch.last_applied = last_applied;
  batch.field_due = field() != nullptr || shadow_field() != nullptr;
  render_views(batch);
  render_one_offs(batch);
}

void Session::after_iteration() {
  {
    std::lock_guard<std::mutex> lock(summary_mutex_);
    to_proto(state_, loop_.frames(), &summary_);
  }
  env_.context->collect_garbage();
}

void Session::tear_down() {
  const Error closed = unavailable("session " + state_.id + " was closed");
  state_.views.close_all(closed);
  state_.one_offs.close_all(closed);
  state_.scene.reset();
  env_.context->collect_garbage();
  env_.metrics->sessions.fetch_sub(1);
  LOG_INFO << "session closed session=" << state_.id << " frames=" << loop_.frames();
}

void Session::render_views(FrameBatch& batch) {
  std::vector<std::string> failed;
  for (auto& [view_id, view] : state_.views.all()) {
    view.drop_ended_streams();
    if (view.streams.empty() && view.waiters.empty()) continue;
    Result<std::unique_ptr<EncodeJob>> job = [&]() -> Result<std::unique_ptr<EncodeJob>> {
      DDGI_ASSIGN_OR_RETURN(FrameTarget * target, view.sized_target(*env_.context));
      return render_job(batch, view_id, view.config, view.camera, *target);
    }();
    if (!job.ok()) {
      LOG_WARNING << "render failed session=" << state_.id << " view=" << view_id << ": "
                  << job.error().message;
      view.fail(job.error());
      if (view.owned_by_stream) failed.push_back(view_id);
      continue;
    }
    (*job)->view_key = state_.id + "/" + view_id;
    (*job)->streams = view.streams;
    (*job)->waiters = std::move(view.waiters);
    view.waiters.clear();
    env_.encoder->submit(std::move(*job));
  }
  for (const std::string& view_id : failed) state_.views.erase(view_id);
}

void Session::render_one_offs(FrameBatch& batch) {
  for (OneOffFrame& one_off : state_.one_offs.take()) {
    Result<std::unique_ptr<EncodeJob>> job = [&]() -> Result<std::unique_ptr<EncodeJob>> {
      DDGI_ASSIGN_OR_RETURN(
          FrameTarget * target,
          state_.one_offs.target(*env_.context, one_off.config.width, one_off.config.height));
      return render_job(batch, "", one_off.config, one_off.camera, *target);
    }();
    if (!job.ok()) {
      LOG_WARNING << "render failed session=" << state_.id << " one-off frame " << one_off.number
                  << ": " << job.error().message;
      one_off.waiter(job.error());
      continue;
    }
    (*job)->view_key = state_.id + "/one-off " + std::to_string(one_off.number);
    (*job)->waiters.push_back(std::move(one_off.waiter));
    env_.encoder->submit(std::move(*job));
  }
}

Result<std::unique_ptr<EncodeJob>> Session::render_job(FrameBatch& batch,
                                                       const std::string& view_id,
                                                       const ViewConfig& config,
                                                       const Camera& camera, FrameTarget& target) {
  FrameRecord record;
  DDGI_ASSIGN_OR_RETURN(FrameResult frame, render(batch, config, camera, target, record));
  record.session_id = state_.id;
  record.view_id = view_id;
  record.index = batch.index;
  record.width = frame.width;
  record.height = frame.height;
  record.camera = camera;
  record.gi_passes = batch.gi_passes;
  record.gi_ms = batch.gi_ms;
  record.last_applied = batch.last_applied;
  record.rendered_unix_us = unix_micros();
  record.field_updates = field()          ? field()->updates()
                         : shadow_field() ? shadow_field()->updates()
                                          : 0;
  auto job = std::make_unique<EncodeJob>();
  job->image = encode::ImageRgba8{frame.width, frame.height, std::move(frame.ldr)};
  job->quality = config.jpeg_quality;
  job->max_frame_bytes = env_.limits->max_message_bytes;
  to_proto(record, &job->frame);
  return job;
}

Result<FrameResult> Session::render(FrameBatch& batch, const ViewConfig& config,
                                    const Camera& camera, FrameTarget& target,
                                    FrameRecord& record) {
  const FrameSettings settings = frame_settings(config, camera, state_.options.direct_mode);
  const auto start = std::chrono::steady_clock::now();
  DDGI_ASSIGN_OR_RETURN(FrameResult frame, state_.scene->render(settings, target, batch.field_due));
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const vk::PassTime& pass : frame.pass_times) {
    const bool gi_pass =
        pass.group == vk::PassGroup::kIrradianceField || pass.group == vk::PassGroup::kShadowField;
    if (gi_pass) {
      batch.gi_passes.push_back(pass);
      batch.gi_ms += pass.milliseconds;
    } else {
      record.view_passes.push_back(pass);
    }
  }
  if (batch.field_due) {
    batch.field_due = false;
    env_.metrics->field_updates.fetch_add(1);
    env_.metrics->gi_update_seconds.observe(batch.gi_ms * 1e-3);
  }
  env_.metrics->frames_rendered.fetch_add(1);
  env_.metrics->frame_seconds.observe(seconds);
  return frame;
}

}  // namespace ddgi::service
