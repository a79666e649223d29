// One StreamFrames call's state and reactor (service/frame_stream.h).
#include "service/frame_stream.h"

namespace ddgi::service {

void FrameStreamState::expect(uint64_t frame_index) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!finish_requested_ && !finished_) expected_.push_back(frame_index);
}

void FrameStreamState::offer(const std::shared_ptr<const v1::Frame>& frame) {
  Action action;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finish_requested_ || finished_) return;
    // Encoder threads may finish frames out of order: never send an older one.
    if (frame->frame_index() <= last_index_) return;
    last_index_ = frame->frame_index();
    // Older frames still expected will never be sent: dropped before this one.
    while (!expected_.empty() && expected_.front() <= last_index_) {
      if (expected_.front() < last_index_) {
        ++dropped_;
        metrics_.frames_dropped.fetch_add(1);
      }
      expected_.pop_front();
    }
    if (slot_ && in_flight_) {  // the client has not taken the previous one: it is stale
      ++dropped_;
      metrics_.frames_dropped.fetch_add(1);
    }
    slot_ = frame;
    action = next_action_locked();
  }
  act(action);
}

void FrameStreamState::finish(const grpc::Status& status) {
  Action action;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finish_requested_ || finished_) return;
    finish_requested_ = true;
    finish_status_ = status;
    action = next_action_locked();
  }
  act(action);
}

bool FrameStreamState::ended() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return finish_requested_ || finished_;
}

uint64_t FrameStreamState::dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

FrameStreamState::Action FrameStreamState::next_action_locked() {
  if (in_flight_ || finished_ || reactor_ == nullptr) return Action::kNone;
  if (finish_requested_) {
    finished_ = true;
    slot_.reset();
    return Action::kFinish;
  }
  if (!slot_) return Action::kNone;
  if (max_fps_ > 0.0) {
    // Rate cap: hold the frame; a later offer or write completion sends the newest one.
    const auto interval = std::chrono::duration<double>(1.0 / max_fps_);
    if (std::chrono::steady_clock::now() - last_write_ < interval) return Action::kNone;
  }
  writing_ = *slot_;
  slot_.reset();
  writing_.set_frames_dropped(dropped_);
  in_flight_ = true;
  last_write_ = std::chrono::steady_clock::now();
  return Action::kWrite;
}

void FrameStreamState::act(Action action) {
  // Safe without the lock: while a write is in flight or Finish is pending, gRPC cannot call
  // OnDone, so the reactor is alive; only this path calls StartWrite/Finish.
  switch (action) {
    case Action::kNone:
      break;
    case Action::kWrite:
      reactor_->StartWrite(&writing_);
      break;
    case Action::kFinish:
      reactor_->Finish(finish_status_);
      break;
  }
}

void FrameStreamState::write_done(bool ok) {
  Action action;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    in_flight_ = false;
    if (ok) {
      metrics_.frames_sent.fetch_add(1);
    } else if (!finish_requested_) {
      // The client is gone; the call ends whatever status we give.
      finish_requested_ = true;
      finish_status_ = grpc::Status(grpc::StatusCode::CANCELLED, "the client went away");
    }
    action = next_action_locked();
  }
  act(action);
}

void FrameStreamState::reactor_done() {
  std::lock_guard<std::mutex> lock(mutex_);
  reactor_ = nullptr;
  finished_ = true;
  slot_.reset();
}

FrameStreamReactor::FrameStreamReactor(Metrics& metrics, double max_fps)
    : state_(std::make_shared<FrameStreamState>(metrics, max_fps)), metrics_(metrics) {
  state_->reactor_ = this;
  metrics_.streams.fetch_add(1);
}

void FrameStreamReactor::OnWriteDone(bool ok) {
  state_->write_done(ok);
}

void FrameStreamReactor::OnCancel() {
  state_->finish(grpc::Status(grpc::StatusCode::CANCELLED, "the stream was cancelled"));
}

void FrameStreamReactor::OnDone() {
  state_->reactor_done();
  if (on_done_) on_done_();
  metrics_.streams.fetch_sub(1);  // after on_done_ queued the detach: "0 streams" means gone
  delete this;
}

}  // namespace ddgi::service
