// The background calibrator (service/calibrator.h) with made-up measurements, no GPU: one
// measurement for the requests of one key, listeners told once (at once when they come late), a
// queued job nobody wants any more dropped unmeasured, a running one cancelled between its
// candidates, and a request on an idle worker always measured (its interest is taken before the
// worker can see the job: it once was not, and the job was dropped as unwanted).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "service/calibrator.h"

namespace ddgi::test {
namespace {

using service::CalibrationJob;
using service::Calibrator;
using State = CalibrationJob::State;

// A measurement of `candidates` steps that waits for `go` before each, honouring the hooks.
CalibrationJob::Measure made_up(size_t candidates, std::shared_future<void> go,
                                std::atomic<int>* runs) {
  return [=](tools::CalibrationOptions::Hooks hooks) -> Result<tools::Calibration> {
    runs->fetch_add(1);
    tools::Calibration calibration;
    for (size_t i = 0; i < candidates; ++i) {
      if (hooks.cancelled && hooks.cancelled()) return unavailable("cancelled");
      go.wait();
      calibration.candidates.emplace_back();
      if (hooks.progress) hooks.progress(i + 1, candidates);
    }
    return calibration;
  };
}

// The state a job's listener was told, once it was.
struct Told {
  std::promise<State> promise;
  std::future<State> future = promise.get_future();
  void listen(CalibrationJob& job) {
    job.listen([this](const CalibrationJob& done) { promise.set_value(done.state()); });
  }
  State wait() {
    EXPECT_EQ(future.wait_for(std::chrono::seconds(10)), std::future_status::ready);
    return future.get();
  }
};

std::shared_future<void> released() {
  std::promise<void> p;
  p.set_value();
  return p.get_future().share();
}

TEST(CalibratorTest, OneMeasurementPerKeyAndEveryListenerTold) {
  Calibrator calibrator(1.0);
  std::promise<void> go;
  std::atomic<int> runs{0};
  Calibrator::Ticket first =
      calibrator.request("scene", 3, made_up(3, go.get_future().share(), &runs));
  Calibrator::Ticket second = calibrator.request("scene", 3, made_up(3, released(), &runs));
  EXPECT_EQ(first.job, second.job);
  Told a, b;
  a.listen(*first.job);
  b.listen(*second.job);
  go.set_value();
  EXPECT_EQ(a.wait(), State::kDone);
  EXPECT_EQ(b.wait(), State::kDone);
  EXPECT_EQ(runs.load(), 1);
  ASSERT_NE(first.job->result(), nullptr);
  EXPECT_EQ(first.job->result()->candidates.size(), 3u);
  EXPECT_EQ(first.job->done(), 3u);
  Told late;  // a listener that comes after the end is told at once
  late.listen(*first.job);
  EXPECT_EQ(late.wait(), State::kDone);
}

TEST(CalibratorTest, JobsNobodyWantsAreDroppedQueuedOrBetweenCandidates) {
  Calibrator calibrator(1.0);
  std::promise<void> go;
  std::shared_future<void> gate = go.get_future().share();
  std::atomic<int> runs{0};
  Calibrator::Ticket running = calibrator.request("a", 4, made_up(4, gate, &runs));
  Calibrator::Ticket queued = calibrator.request("b", 2, made_up(2, released(), &runs));
  Told running_told, queued_told;
  running_told.listen(*running.job);
  queued_told.listen(*queued.job);
  // Wait until "a" runs (it is blocked on its first candidate), then let go of both.
  for (int i = 0; i < 1000 && running.job->state() != State::kRunning; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  ASSERT_EQ(running.job->state(), State::kRunning);
  running.interest.reset();
  queued.interest.reset();
  go.set_value();
  EXPECT_EQ(running_told.wait(), State::kDropped);
  EXPECT_LT(running.job->done(), 4u) << "cancelled between candidates";
  EXPECT_EQ(queued_told.wait(), State::kDropped);
  EXPECT_EQ(runs.load(), 1) << "the queued job was never measured";
  // A new request of a dropped job's key is a new job, measured.
  Calibrator::Ticket again = calibrator.request("a", 1, made_up(1, released(), &runs));
  EXPECT_NE(again.job, running.job);
  Told again_told;
  again_told.listen(*again.job);
  EXPECT_EQ(again_told.wait(), State::kDone);
}

TEST(CalibratorTest, ARequestOnAnIdleWorkerIsAlwaysMeasured) {
  Calibrator calibrator(1.0);
  std::atomic<int> runs{0};
  for (int i = 0; i < 200; ++i) {
    Calibrator::Ticket ticket =
        calibrator.request("scene " + std::to_string(i), 1, made_up(1, released(), &runs));
    Told told;
    told.listen(*ticket.job);
    ASSERT_EQ(told.wait(), State::kDone) << "request " << i;
  }
  EXPECT_EQ(runs.load(), 200);
}

}  // namespace
}  // namespace ddgi::test
