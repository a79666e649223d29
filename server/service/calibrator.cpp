// The service's background calibrations (service/calibrator.h).
#include "service/calibrator.h"

#include <algorithm>

#include "core/log.h"
#include "vk/gpu_share.h"

namespace ddgi::service {

const char* state_name(CalibrationJob::State state) {
  switch (state) {
    case CalibrationJob::State::kQueued:
      return "queued";
    case CalibrationJob::State::kRunning:
      return "running";
    case CalibrationJob::State::kDone:
      return "done";
    case CalibrationJob::State::kFailed:
      return "failed";
    case CalibrationJob::State::kDropped:
      return "dropped";
  }
  return "?";
}

CalibrationJob::CalibrationJob(std::string key, size_t candidates, Measure measure)
    : key_(std::move(key)), total_(candidates), measure_(std::move(measure)) {}

double CalibrationJob::seconds() const {
  std::lock_guard lock(mutex_);
  const Clock::time_point end = finished_.value_or(Clock::now());
  return std::chrono::duration<double>(end - queued_).count();
}

std::shared_ptr<const tools::Calibration> CalibrationJob::result() const {
  std::lock_guard lock(mutex_);
  return result_;
}

std::string CalibrationJob::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

void CalibrationJob::listen(Listener listener) {
  {
    std::lock_guard lock(mutex_);
    if (!finished_) {
      listeners_.push_back(std::move(listener));
      return;
    }
  }
  listener(*this);  // done already: told at once
}

std::shared_ptr<void> CalibrationJob::join() {
  std::lock_guard lock(mutex_);
  if (dropping_) return nullptr;
  auto token = std::make_shared<int>(0);
  wanted_by_.push_back(token);
  return token;
}

bool CalibrationJob::still_wanted() {
  std::lock_guard lock(mutex_);
  dropping_ = dropping_ || std::all_of(wanted_by_.begin(), wanted_by_.end(),
                                       [](const std::weak_ptr<void>& w) { return w.expired(); });
  return !dropping_;
}

void CalibrationJob::run(double gpu_share, const std::atomic<bool>& stopping) {
  if (!still_wanted()) return finish(State::kDropped);
  state_ = State::kRunning;
  tools::CalibrationOptions::Hooks hooks;
  hooks.progress = [this](size_t done, size_t) { done_ = done; };
  hooks.cancelled = [this, &stopping] { return stopping.load() || !still_wanted(); };
  Result<tools::Calibration> measured = [&] {
    vk::GpuShareScope share(gpu_share);
    return measure_(hooks);
  }();
  if (measured.ok()) {
    std::lock_guard lock(mutex_);
    result_ = std::make_shared<const tools::Calibration>(std::move(*measured));
  } else {
    std::lock_guard lock(mutex_);
    error_ = measured.error().message;
  }
  const bool dropped = [this] {
    std::lock_guard lock(mutex_);
    return dropping_;
  }();
  finish(measured.ok() ? State::kDone : (dropped ? State::kDropped : State::kFailed));
}

void CalibrationJob::finish(State state) {
  std::vector<Listener> listeners;
  {
    std::lock_guard lock(mutex_);
    state_ = state;
    finished_ = Clock::now();
    listeners.swap(listeners_);
  }
  measure_ = nullptr;  // what it captured (the scene's copy) goes now
  LOG_INFO << "calibration " << state_name(state) << " candidates=" << done_.load() << "/" << total_
           << " seconds=" << seconds() << (error_.empty() ? "" : " error=" + error_);
  for (const Listener& listener : listeners) listener(*this);
}

Calibrator::Calibrator(double gpu_share) : gpu_share_(gpu_share), worker_([this] { work(); }) {}

Calibrator::~Calibrator() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    queue_.clear();
  }
  wake_.notify_all();
  worker_.join();
}

Calibrator::Ticket Calibrator::request(const std::string& key, size_t candidates,
                                       CalibrationJob::Measure measure) {
  std::lock_guard lock(mutex_);
  if (running_ && running_->key() == key) {
    if (std::shared_ptr<void> interest = running_->join()) return {running_, interest};
  }
  for (const auto& job : queue_) {
    if (job->key() != key) continue;
    if (std::shared_ptr<void> interest = job->join()) return {job, interest};
  }
  auto job = std::make_shared<CalibrationJob>(key, candidates, std::move(measure));
  std::shared_ptr<void> interest = job->join();  // before the worker can see the job
  queue_.push_back(job);
  wake_.notify_all();
  return {job, interest};
}

void Calibrator::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (stopping_) return;
    running_ = queue_.front();
    queue_.pop_front();
    lock.unlock();
    running_->run(gpu_share_, stopping_);
    lock.lock();
    running_.reset();
  }
}

}  // namespace ddgi::service
