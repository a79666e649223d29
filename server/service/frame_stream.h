// One StreamFrames call: a gRPC ServerWriteReactor with one write in flight and a latest-frame
// slot. The session's frame loop (through the encoder) offers frames from its own threads; a
// newer frame overwrites an unsent one in the slot (counted as dropped), so a slow reader costs
// at most two frames of memory and never stalls the loop. Nothing here blocks.
#pragma once

#include <grpcpp/grpcpp.h>

#include <chrono>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>

#include "ddgi/v1/render_service.pb.h"
#include "service/metrics.h"

namespace ddgi::service {

class FrameStreamReactor;

// The part of a stream that producers hold: outlives the reactor, ignores frames once the
// stream has ended.
class FrameStreamState {
 public:
  FrameStreamState(Metrics& metrics, double max_fps) : metrics_(metrics), max_fps_(max_fps) {}

  // A frame with this index is on its way to offer() (called in index order, when the frame
  // is handed to the encoder). An expected index older than an offered frame was dropped on
  // the way (replaced in the encoder's queue, or finished after a newer one), and the offered
  // frame is the first to count it: so frames_dropped grows by exactly the indices a client
  // sees skipped, whatever order the encoder threads finish in.
  void expect(uint64_t frame_index);
  // A new frame for this stream (any thread).
  void offer(const std::shared_ptr<const v1::Frame>& frame);
  // Ends the stream with `status` once the write in flight (if any) is done. Only the first
  // call counts.
  void finish(const grpc::Status& status);
  bool ended() const;
  uint64_t dropped() const;

 private:
  friend class FrameStreamReactor;
  enum class Action { kNone, kWrite, kFinish };
  Action next_action_locked();  // decides what to do after a state change
  void act(Action action);      // performs it, without the lock
  void write_done(bool ok);
  void reactor_done();

  Metrics& metrics_;
  const double max_fps_;
  mutable std::mutex mutex_;
  FrameStreamReactor* reactor_ = nullptr;  // null once gRPC is done with the call
  bool in_flight_ = false;
  bool finish_requested_ = false;
  bool finished_ = false;
  grpc::Status finish_status_;
  std::shared_ptr<const v1::Frame> slot_;
  v1::Frame writing_;  // the message in flight: the frame plus this stream's drop count
  uint64_t dropped_ = 0;
  std::deque<uint64_t> expected_;  // ascending indices handed to the encoder, not yet offered
  uint64_t last_index_ = 0;        // frame indices start at 1
  std::chrono::steady_clock::time_point last_write_{};
};

class FrameStreamReactor : public grpc::ServerWriteReactor<v1::Frame> {
 public:
  FrameStreamReactor(Metrics& metrics, double max_fps);
  const std::shared_ptr<FrameStreamState>& state() const { return state_; }
  // Runs once gRPC is done with the call (client gone, finished, or cancelled).
  void set_on_done(std::function<void()> on_done) { on_done_ = std::move(on_done); }

  void OnWriteDone(bool ok) override;
  void OnCancel() override;
  void OnDone() override;

 private:
  std::shared_ptr<FrameStreamState> state_;
  std::function<void()> on_done_;
  Metrics& metrics_;
};

}  // namespace ddgi::service
