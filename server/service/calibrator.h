// The service's background calibrations (issue 45, "no wait at load"): a session streams at once
// with the static default while the calibration of its scene (tools/field_budget.h) runs on one
// worker thread of the server, on the same GPU, taking at most a share of the GPU's time
// (vk/gpu_share.h) so that the other sessions' streams go on; then the session switches to the
// rule's choice (tools/field_choice.h). Requests of one key (one scene, device, frame and base)
// share one measurement; requests wait in arrival order; a job nobody wants any more (its
// sessions closed or loaded another scene) is dropped before it starts or between its candidates.
// The result lands in the BudgetCache (on disk by default), so a restarted server does not
// calibrate again.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "core/result.h"
#include "tools/field_budget.h"

namespace ddgi::service {

// One calibration as its sessions see it. Thread-safe: the worker writes, sessions read.
class CalibrationJob {
 public:
  enum class State { kQueued, kRunning, kDone, kFailed, kDropped };
  using Clock = std::chrono::steady_clock;
  // `measure` runs the calibration with the given progress and cancellation hooks set.
  using Measure = std::function<Result<tools::Calibration>(tools::CalibrationOptions::Hooks)>;
  using Listener = std::function<void(const CalibrationJob&)>;

  CalibrationJob(std::string key, size_t candidates, Measure measure);

  const std::string& key() const { return key_; }
  State state() const { return state_.load(); }
  size_t done() const { return done_.load(); }
  size_t total() const { return total_; }
  // Seconds since it was queued (while it runs), or that it took from queued to done.
  double seconds() const;
  // Once kDone: the calibration; once kFailed: why.
  std::shared_ptr<const tools::Calibration> result() const;
  std::string error() const;

  // Called once, on the worker thread, when it is done, failed or dropped (at once, on the
  // caller's thread, where it is already).
  void listen(Listener listener);

 private:
  friend class Calibrator;
  // An interest in the job, held as long as it lasts (a session's scene holds it); nothing once
  // the job is being dropped. Decided under the job's lock, as still_wanted() is, so that an
  // interest is never added to a job that has just decided nobody wants it.
  std::shared_ptr<void> join();
  // Whether any interest is alive; the first time none is, the job is dropping for good.
  bool still_wanted();
  // Runs the measurement unless nobody wants it; `stopping`: the server is going.
  void run(double gpu_share, const std::atomic<bool>& stopping);
  void finish(State state);

  const std::string key_;
  const size_t total_;
  Measure measure_;
  std::atomic<State> state_{State::kQueued};
  std::atomic<size_t> done_{0};
  const Clock::time_point queued_ = Clock::now();
  mutable std::mutex mutex_;
  std::optional<Clock::time_point> finished_;
  std::shared_ptr<const tools::Calibration> result_;
  std::string error_;
  std::vector<Listener> listeners_;
  std::vector<std::weak_ptr<void>> wanted_by_;
  bool dropping_ = false;
};

const char* state_name(CalibrationJob::State state);

class Calibrator {
 public:
  // Calibrations take at most `gpu_share` of the GPU's time, (0, 1].
  explicit Calibrator(double gpu_share);
  ~Calibrator();  // drops queued jobs, cancels the running one between candidates, joins
  Calibrator(const Calibrator&) = delete;
  Calibrator& operator=(const Calibrator&) = delete;

  // A job and the caller's interest in it: the job ends early (dropped) once every interest is
  // gone.
  struct Ticket {
    std::shared_ptr<CalibrationJob> job;
    std::shared_ptr<void> interest;
  };
  // The job of `key` (the one queued or running already, unless it is being dropped, else a new
  // one of `measure`), with an interest taken before the worker can see it.
  Ticket request(const std::string& key, size_t candidates, CalibrationJob::Measure measure);

 private:
  void work();

  const double gpu_share_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::shared_ptr<CalibrationJob>> queue_;
  std::shared_ptr<CalibrationJob> running_;
  std::atomic<bool> stopping_{false};
  std::thread worker_;  // last: started once the rest exists
};

}  // namespace ddgi::service
