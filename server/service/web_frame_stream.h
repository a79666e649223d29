// One browser's frame stream: a StreamFrames call (on the in-process channel) whose frames go
// to the browser's WebSocket. A reader thread takes frames from the call as fast as the
// session makes them and puts each in a one-frame slot, where a newer frame replaces an unsent
// one (dropped, counted); a writer thread sends the slot's frame. A browser that reads slowly,
// or not at all, holds back only its writer (until civetweb's write timeout ends the
// connection): it costs at most the slot's frame and the one being written, and the session
// and other viewers never wait for it. Latest frame wins, as on the gRPC stream itself.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "ddgi/v1/render_service.grpc.pb.h"
#include "service/metrics.h"

namespace ddgi::service {

class WebFrameStream {
 public:
  // Writes one binary message to the browser; false when it could not (connection gone or
  // write timed out), which ends the stream.
  using SendFrame = std::function<bool(const std::string& message)>;
  // Called once, on the writer thread, after the last frame was sent: how the stream ended
  // (OK when the session closed or stop() ended it). Not called when SendFrame failed.
  using Ended = std::function<void(const grpc::Status& status)>;

  // Starts the call with `token` as its bearer token (none when empty).
  WebFrameStream(v1::RenderService::Stub& stub, const std::string& token,
                 const v1::StreamFramesRequest& request, SendFrame send, Ended ended,
                 Metrics& metrics);
  // stop(), then waits for both threads.
  ~WebFrameStream();
  WebFrameStream(const WebFrameStream&) = delete;
  WebFrameStream& operator=(const WebFrameStream&) = delete;

  // Cancels the call; the stream ends with OK.
  void stop();
  uint64_t dropped() const;

 private:
  void read_frames(v1::RenderService::Stub& stub, v1::StreamFramesRequest request);
  void write_frames();

  SendFrame send_;
  Ended ended_;
  Metrics& metrics_;
  grpc::ClientContext call_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::shared_ptr<const v1::Frame> slot_;
  bool reading_done_ = false;
  bool stopped_ = false;
  grpc::Status status_;
  uint64_t dropped_ = 0;
  std::thread reader_;
  std::thread writer_;
};

}  // namespace ddgi::service
