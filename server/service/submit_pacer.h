// When a session's loop submits its next frames, so that a camera command waits behind as
// little GPU work as possible without the GPU running dry (issue 13: latency towards GPU time
// plus one JPEG encode). Frames are pipelined (session_frames.cpp): an iteration submits its
// frames, then reads back the previous iteration's. Submitted at once, the next iteration's
// frames would queue behind a whole frame still to run, and a command applied to them would
// wait that frame out: about 2.5 frames of GPU time from command to image. Paced, the loop
// submits them `ahead` (plus the time their recording took last time) before the GPU is expected
// to finish the frames queued before them, so they run as soon as the GPU is free and a command
// waits for about 1.5 frames. The GPU time expected of a batch is the shorter of the last two
// finished batches' (their passes' timestamps, not the wall time between fences, which would
// count a GPU left idle by late submission and so grow itself); a wrong guess costs latency when
// too short, GPU idle time when too long, and never a frame.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "core/result.h"

namespace ddgi::service {

// The largest `ahead` a server takes (--submit-ahead-ms): a second of queued GPU work is no
// pacing at all; anything above a frame's GPU time submits as soon as the previous batch is read
// back, as the loop did before pacing.
inline constexpr double kMaxSubmitAheadMs = 1000.0;
// The `ahead` a server takes unless told (ServerOptions::submit_ahead_ms): the loop thread's
// wake-ups and a frame's submission take tens of microseconds on a GPU host, and the recording
// time is added to it anyway.
inline constexpr double kDefaultSubmitAheadMs = 0.5;

// INVALID_ARGUMENT naming --submit-ahead-ms and its range unless `ahead_ms` is in
// [0, kMaxSubmitAheadMs].
Status check_submit_ahead_ms(double ahead_ms);

class SubmitPacer {
 public:
  using Clock = std::chrono::steady_clock;
  using Millis = std::chrono::duration<double, std::milli>;

  // `ahead`: GPU work still queued when the next batch is submitted (kDefaultSubmitAheadMs
  // unless the server was told otherwise).
  explicit SubmitPacer(Millis ahead) : ahead_(ahead) {}

  // Batch `index` (increasing) was submitted; recording its frames took `recording`.
  void submitted(uint64_t index, Millis recording);
  // A frame of batch `index` (batches finish in submission order) was seen done by the GPU at
  // `done_at`, after `gpu` of GPU time; a batch's frames add up.
  void finished(uint64_t index, Clock::time_point done_at, Millis gpu);
  // The earliest time to submit the next batch: Clock's epoch (at once) while nothing is in
  // flight or no batch has finished yet.
  Clock::time_point next_submit() const;

 private:
  const Millis ahead_;
  uint64_t submitted_ = 0;  // the newest batch submitted (0: none)
  Millis recording_{0.0};   // how long recording it took
  uint64_t finished_ = 0;   // the newest batch seen done (0: none)
  Clock::time_point finished_at_{};
  Millis finished_gpu_{0.0};            // its GPU time, all its frames
  std::optional<Millis> previous_gpu_;  // the batch's before it, once there was one
};

}  // namespace ddgi::service
