// The session's command queue, sequencing, frame pacing and teardown (service/session_loop.h).
#include "service/session_loop.h"

#include <algorithm>
#include <thread>

#include "core/log.h"

namespace ddgi::service {

int64_t unix_micros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

SessionLoop::SessionLoop(std::string session_id, double max_fps, Owner& owner)
    : session_id_(std::move(session_id)),
      interval_(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(1.0 / max_fps))),
      owner_(owner) {}

void SessionLoop::start(std::shared_ptr<void> keep_alive, std::function<void()> on_exit) {
  std::thread([this, keep_alive = std::move(keep_alive), on_exit = std::move(on_exit)] {
    run(keep_alive, on_exit);
  }).detach();
}

void SessionLoop::enqueue(bool changes_state, Run run, Completion done) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!stopping_) {
      queue_.push_back(
          Command{std::move(run), std::move(done), next_seq_++, unix_micros(), changes_state});
      wake_.notify_one();
      return;
    }
  }
  done(unavailable("session " + session_id_ + " is closing"));
}

void SessionLoop::enqueue_sync(bool changes_state, std::function<Status()> run, Completion done) {
  enqueue(
      changes_state, [run = std::move(run)](Completion finish) { finish(run()); }, std::move(done));
}

void SessionLoop::stop(std::function<void()> on_stopped, std::optional<Error> reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  stopping_ = true;
  if (reason && !stop_reason_) stop_reason_ = std::move(reason);
  if (on_stopped) on_stopped_.push_back(std::move(on_stopped));
  wake_.notify_one();
}

void SessionLoop::run(const std::shared_ptr<void>&, const std::function<void()>& on_exit) {
  LOG_INFO << "session loop started session=" << session_id_;
  std::deque<Command> batch;
  while (wait_for_work(batch)) {
    apply(batch);
    if (frame_due()) {
      last_frame_start_ = std::chrono::steady_clock::now();
      owner_.produce_frame(++frames_, last_applied_);
    }
    owner_.after_iteration();
  }
  finish();
  if (on_exit) on_exit();
}

bool SessionLoop::wait_for_work(std::deque<Command>& batch) {
  std::unique_lock<std::mutex> lock(mutex_);
  bool finished = false;
  while (!stopping_ && queue_.empty()) {
    const bool wanted = owner_.wants_frame();
    const auto next = last_frame_start_ + interval_;
    const auto paced = wanted ? owner_.next_submit_time() : std::chrono::steady_clock::time_point{};
    if (wanted && std::chrono::steady_clock::now() >= std::max(next, paced)) break;
    if (wanted && paced >= next) {
      // The frames in flight, not the frame rate, hold the next one back: they stay in flight
      // (the GPU is running them), and a command arriving wakes the loop to apply it.
      wake_.wait_until(lock, paced);
      continue;
    }
    if (!finished) {  // about to sleep: what is in flight is delivered now, not a frame later
      lock.unlock();
      owner_.finish_frames();
      lock.lock();
      finished = true;
      continue;
    }
    if (wanted) {
      wake_.wait_until(lock, next);
    } else {
      wake_.wait(lock);
    }
  }
  if (stopping_) return false;
  batch.swap(queue_);
  return true;
}

void SessionLoop::apply(std::deque<Command>& batch) {
  for (Command& command : batch) {
    applying_seq_ = command.seq;
    if (command.changes_state) last_applied_ = {command.seq, command.arrival_unix_us};
    command.run(std::move(command.done));
  }
  batch.clear();
}

bool SessionLoop::frame_due() const {
  const auto next = std::max(last_frame_start_ + interval_, owner_.next_submit_time());
  return owner_.wants_frame() && std::chrono::steady_clock::now() >= next;
}

void SessionLoop::finish() {
  std::deque<Command> rest;
  std::optional<Error> reason;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    rest.swap(queue_);
    reason = stop_reason_;
  }
  const Error closed = reason ? *reason : unavailable("session " + session_id_ + " was closed");
  for (Command& command : rest) command.done(closed);
  owner_.tear_down(closed, reason.has_value());
  std::vector<std::function<void()>> on_stopped;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    on_stopped.swap(on_stopped_);
  }
  for (auto& callback : on_stopped) callback();
}

}  // namespace ddgi::service
