#include "service/web_frame_stream.h"

#include "rpc/web_frame.h"

namespace ddgi::service {

WebFrameStream::WebFrameStream(v1::RenderService::Stub& stub, const std::string& token,
                               const v1::StreamFramesRequest& request, SendFrame send, Ended ended,
                               Metrics& metrics)
    : send_(std::move(send)), ended_(std::move(ended)), metrics_(metrics) {
  if (!token.empty()) call_.AddMetadata("authorization", "Bearer " + token);
  reader_ = std::thread([this, &stub, request] { read_frames(stub, request); });
  writer_ = std::thread([this] { write_frames(); });
}

WebFrameStream::~WebFrameStream() {
  stop();
  reader_.join();
  writer_.join();
}

void WebFrameStream::stop() {
  {
    std::lock_guard lock(mutex_);
    stopped_ = true;
  }
  call_.TryCancel();
}

uint64_t WebFrameStream::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

void WebFrameStream::read_frames(v1::RenderService::Stub& stub, v1::StreamFramesRequest request) {
  auto reader = stub.StreamFrames(&call_, request);
  auto frame = std::make_shared<v1::Frame>();
  while (reader->Read(frame.get())) {
    std::lock_guard lock(mutex_);
    if (slot_) {
      ++dropped_;
      ++metrics_.web_frames_dropped;
    }
    slot_ = std::move(frame);
    frame = std::make_shared<v1::Frame>();
    changed_.notify_one();
  }
  const grpc::Status status = reader->Finish();
  std::lock_guard lock(mutex_);
  // Our own cancel (stop()) is how a viewer ends its stream: not an error to report.
  status_ = stopped_ ? grpc::Status::OK : status;
  reading_done_ = true;
  changed_.notify_one();
}

void WebFrameStream::write_frames() {
  std::unique_lock lock(mutex_);
  while (true) {
    changed_.wait(lock, [this] { return slot_ != nullptr || reading_done_; });
    if (slot_ == nullptr) break;  // reading is done and every frame went out
    const std::shared_ptr<const v1::Frame> frame = std::move(slot_);
    const uint64_t dropped = dropped_;
    lock.unlock();
    const bool sent = send_(encode_web_frame(*frame, dropped));
    lock.lock();
    if (!sent) {
      stopped_ = true;  // the browser is gone: end the call, report nothing
      lock.unlock();
      call_.TryCancel();
      return;
    }
    ++metrics_.web_frames_sent;
  }
  const grpc::Status status = status_;
  lock.unlock();
  ended_(status);
}

}  // namespace ddgi::service
