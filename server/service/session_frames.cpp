// A session's frames: what its loop calls (SessionLoop::Owner). Each iteration submits a frame
// of every view someone waits for (the first carries the iteration's one field update, shared
// by all of them), then reads back the previous iteration's frames, which the GPU ran while
// these were recorded, and hands them to the encoder; one-off frames are drawn last, one at a
// time (service/session.h). Views alternate between two frame targets, so a view has at most
// two frames in flight and never draws into a target whose frame is not read back. The frames
// in flight pace the loop (next_submit_time): the next iteration starts when the GPU is about to
// finish them (service/submit_pacer.h), not as soon as the previous iteration's are read back.
#include <chrono>
#include <limits>

#include "core/log.h"
#include "service/grpc_status.h"
#include "service/session.h"

namespace ddgi::service {

bool Session::wants_frame() {
  return state_.views.wants_frame() || !state_.one_offs.empty() || !state_.probe_streams.empty();
}

void Session::produce_frame(uint64_t index, const CommandStamp& last_applied) {
  auto batch = std::make_shared<FrameBatch>();
  batch->index = index;
  batch->last_applied = last_applied;
  batch->field_due = field() != nullptr || shadow_field() != nullptr;
  const auto recording = std::chrono::steady_clock::now();
  render_views(batch);
  if (!in_flight_.empty() && in_flight_.back().batch->index == index) {
    pacer_.submitted(index, std::chrono::steady_clock::now() - recording);
  }
  // This iteration's frames are on the queue behind the previous one's: read those back now.
  // The loop was paced to come here as they end, when the older ones are long done.
  deliver_older_than(index, true);
  render_one_offs(batch);
  stream_probes(batch);
}

void Session::stream_probes(const std::shared_ptr<FrameBatch>& batch) {
  std::erase_if(state_.probe_streams, [](const auto& stream) { return stream->ended(); });
  if (state_.probe_streams.empty()) return;
  finish_frames();
  Result<std::shared_ptr<const ProbeSnapshot>> snapshot =
      [&]() -> Result<std::shared_ptr<const ProbeSnapshot>> {
    DDGI_TRY(require_field(v1::FIELD_KIND_IRRADIANCE));
    if (batch->field_due) {
      DDGI_TRY(state_.scene->update_fields());
      batch->field_due = false;
      env_.metrics->field_updates.fetch_add(1);
    }
    return take_probe_snapshot(*field());
  }();
  for (const auto& stream : state_.probe_streams) {
    if (snapshot.ok()) {
      stream->offer(*snapshot);
    } else {
      stream->finish(to_grpc(snapshot.error()));
    }
  }
  if (!snapshot.ok()) state_.probe_streams.clear();
}

void Session::finish_frames() {
  deliver_older_than(std::numeric_limits<uint64_t>::max(), false);
}

std::chrono::steady_clock::time_point Session::next_submit_time() {
  return pacer_.next_submit();
}

void Session::after_iteration() {
  {
    std::lock_guard<std::mutex> lock(summary_mutex_);
    to_proto(state_, loop_.frames(), &summary_);
  }
  env_.context->collect_garbage();
}

void Session::report_world_cache() {
  const WorldCache* cache = state_.scene ? state_.scene->world_cache() : nullptr;
  if (!cache) return;
  const WorldCacheCounters now = cache->counters();
  const WorldCacheCounters& was = world_cache_reported_;
  Metrics& m = *env_.metrics;
  // Differences of wrapping 32-bit counts; live entries may fall (evictions), so signed.
  m.world_cache_entries.fetch_add(int32_t(now.live() - was.live()));
  m.world_cache_inserted.fetch_add(now.inserted - was.inserted);
  m.world_cache_evicted.fetch_add(now.evicted - was.evicted);
  m.world_cache_dropped.fetch_add(now.dropped - was.dropped);
  m.world_cache_checksum_rejects.fetch_add(now.checksum_rejects - was.checksum_rejects);
  world_cache_reported_ = now;
}

void Session::forget_world_cache() {
  env_.metrics->world_cache_entries.fetch_sub(world_cache_reported_.live());
  world_cache_reported_ = {};
}

void Session::tear_down(const Error& why, bool failed) {
  finish_frames();  // their waiters get their frames before the rest learn of the close
  state_.views.close_all(why, failed);
  state_.one_offs.close_all(why);
  for (const auto& stream : state_.probe_streams) {
    stream->finish(failed ? to_grpc(why) : grpc::Status::OK);
  }
  state_.probe_streams.clear();
  forget_world_cache();
  state_.scene.reset();
  env_.context->collect_garbage();
  env_.metrics->sessions.fetch_sub(1);
  LOG_INFO << "session closed session=" << state_.id << " frames=" << loop_.frames();
}

void Session::render_views(const std::shared_ptr<FrameBatch>& batch) {
  std::vector<std::string> failed;
  for (auto& entry : state_.views.all()) {
    // Named references, not a structured binding: the lambda below captures them (C++20
    // allows capturing bindings, clang 14 does not).
    const std::string& view_id = entry.first;
    SessionView& view = entry.second;
    view.drop_ended_streams();
    if (view.streams.empty() && view.waiters.empty()) continue;
    if (view.resized()) finish_frames();  // its targets go: the budget then sees the new ones
    Result<InFlightFrame> frame = [&]() -> Result<InFlightFrame> {
      DDGI_ASSIGN_OR_RETURN(std::shared_ptr<FrameTarget> target, view.take_target(*env_.context));
      DDGI_ASSIGN_OR_RETURN(InFlightFrame submitted,
                            submit_frame(batch, view_id, view.config, view.camera, *target));
      submitted.target = std::move(target);
      return submitted;
    }();
    if (!frame.ok()) {
      LOG_WARNING << "render failed session=" << state_.id << " view=" << view_id << ": "
                  << frame.error().message;
      view.fail(frame.error());
      if (view.owned_by_stream) failed.push_back(view_id);
      continue;
    }
    EncodeJob& job = *frame->job;
    job.view_key = state_.id + "/" + view_id;
    job.streams = view.streams;
    job.waiters = std::move(view.waiters);
    view.waiters.clear();
    in_flight_.push_back(std::move(*frame));
  }
  for (const std::string& view_id : failed) state_.views.erase(view_id);
}

void Session::render_one_offs(const std::shared_ptr<FrameBatch>& batch) {
  std::vector<OneOffFrame> one_offs = state_.one_offs.take();
  if (one_offs.empty()) return;
  // After the views' frames: one of them may carry the field update these frames report.
  finish_frames();
  for (OneOffFrame& one_off : one_offs) {
    Result<InFlightFrame> frame = [&]() -> Result<InFlightFrame> {
      DDGI_ASSIGN_OR_RETURN(
          FrameTarget * target,
          state_.one_offs.target(*env_.context, one_off.config.width, one_off.config.height));
      return submit_frame(batch, "", one_off.config, one_off.camera, *target);
    }();
    if (!frame.ok()) {
      LOG_WARNING << "render failed session=" << state_.id << " one-off frame " << one_off.number
                  << ": " << frame.error().message;
      one_off.waiter(frame.error());
      continue;
    }
    frame->job->view_key = state_.id + "/one-off " + std::to_string(one_off.number);
    frame->job->waiters.push_back(std::move(one_off.waiter));
    deliver(*frame);  // the next one-off of this size reuses the target
  }
}

Status Session::wait_for_frames_on_gpu() {
  for (InFlightFrame& frame : in_flight_) DDGI_TRY(frame.pending.wait());
  return ok_status();
}

Result<Session::InFlightFrame> Session::submit_frame(const std::shared_ptr<FrameBatch>& batch,
                                                     const std::string& view_id,
                                                     const ViewConfig& config, const Camera& camera,
                                                     FrameTarget& target) {
  const FrameSettings settings = frame_settings(config, camera, state_.options.direct_mode);
  InFlightFrame frame;
  frame.start = std::chrono::steady_clock::now();
  // Building an irradiance-field update may rewrite its host-visible probe list, which the
  // previous update (in a frame still in flight) reads: that one must be done first. In a
  // steady field the list stays and frames overlap on the GPU.
  if (batch->field_due && field() && field()->next_update_rewrites_probe_list()) {
    DDGI_TRY(wait_for_frames_on_gpu());
  }
  // A tracking field follows the camera of the frame that carries the update: the first view
  // drawn in an iteration (docs/cascades.md). A scroll's work goes into that frame's command
  // buffer, after the frames in flight on the same queue: nothing to wait for.
  if (batch->field_due && field()) field()->track(camera.position);
  const bool behind_another = !in_flight_.empty();
  DDGI_ASSIGN_OR_RETURN(frame.pending, state_.scene->submit(settings, target, batch->field_due));
  if (batch->field_due) {
    batch->field_due = false;
    frame.carries_update = true;
    env_.metrics->field_updates.fetch_add(1);
  }
  if (behind_another) env_.metrics->frames_pipelined.fetch_add(1);
  frame.batch = batch;
  FrameRecord& record = frame.record;
  record.session_id = state_.id;
  record.view_id = view_id;
  record.index = batch->index;
  record.width = settings.width;
  record.height = settings.height;
  record.camera = camera;
  record.last_applied = batch->last_applied;
  record.field_updates = field()          ? field()->updates()
                         : shadow_field() ? shadow_field()->updates()
                                          : 0;
  frame.job = std::make_unique<EncodeJob>();
  frame.job->quality = config.jpeg_quality;
  frame.job->max_frame_bytes = env_.limits->max_message_bytes;
  return frame;
}

SubmitPacer::Millis Session::deliver(InFlightFrame& frame) {
  Result<FrameResult> result = frame.pending.finish();
  frame.target.reset();
  EncodeJob& job = *frame.job;
  if (!result.ok()) {
    LOG_WARNING << "render failed session=" << state_.id << " frame=" << job.view_key << ": "
                << result.error().message;
    for (auto& stream : job.streams) stream->finish(to_grpc(result.error()));
    for (auto& waiter : job.waiters) waiter(result.error());
    return SubmitPacer::Millis(0.0);
  }
  FrameBatch& batch = *frame.batch;
  FrameRecord& record = frame.record;
  SubmitPacer::Millis gpu{0.0};
  for (const vk::PassTime& pass : result->pass_times) {
    gpu += SubmitPacer::Millis(pass.milliseconds);
    const bool gi_pass =
        pass.group == vk::PassGroup::kIrradianceField || pass.group == vk::PassGroup::kShadowField;
    if (!gi_pass) {
      record.view_passes.push_back(pass);
    } else if (frame.carries_update) {
      batch.gi_passes.push_back(pass);
      batch.gi_ms += pass.milliseconds;
    }
  }
  if (frame.carries_update) env_.metrics->gi_update_seconds.observe(batch.gi_ms * 1e-3);
  record.gi_passes = batch.gi_passes;
  record.gi_ms = batch.gi_ms;
  record.rendered_unix_us = unix_micros();
  env_.metrics->frames_rendered.fetch_add(1);
  report_world_cache();
  env_.metrics->frame_seconds.observe(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - frame.start).count());
  const gpu::Yuv420Layout& planes = result->yuv420_layout;
  job.image = encode::ImageYuv420{
      planes.width,     planes.height,    planes.y_stride,          planes.chroma_stride,
      planes.cb_offset, planes.cr_offset, std::move(result->yuv420)};
  to_proto(record, &job.frame);
  env_.encoder->submit(std::move(frame.job));
  return gpu;
}

void Session::deliver_older_than(uint64_t index, bool newest_first) {
  size_t count = 0;
  while (count < in_flight_.size() && in_flight_[count].batch->index < index) ++count;
  if (count == 0) return;
  // The GPU runs frames in submission order: when the newest is done, it is done with them all
  // and starts the next batch, the time the pacer needs. Seen after the older frames' readback
  // copies, that time would come too late. A failed wait fails its finish() too.
  std::chrono::steady_clock::time_point done_at{};
  if (newest_first) {
    (void)in_flight_[count - 1].pending.wait();
    done_at = std::chrono::steady_clock::now();
  }
  for (; count > 0; --count) {
    InFlightFrame frame = std::move(in_flight_.front());
    in_flight_.pop_front();
    if (!newest_first) {
      (void)frame.pending.wait();
      done_at = std::chrono::steady_clock::now();
    }
    pacer_.finished(frame.batch->index, done_at, deliver(frame));
  }
}

}  // namespace ddgi::service
