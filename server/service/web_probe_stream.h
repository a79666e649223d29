// One browser's probe stream (docs/probe-stream.md): a StreamProbes call (on the in-process
// channel) whose messages go to the browser's WebSocket as WebReplies (JSON). One thread reads
// a message and sends it before reading the next, so a browser that reads slowly holds back
// the call itself: gRPC's flow control then stops the server's writes, and the server folds the
// updates the browser has no time for into its next message (nothing is dropped, which a
// delta stream could not afford, and nothing queues here).
#pragma once

#include <grpcpp/grpcpp.h>

#include <functional>
#include <string>
#include <thread>

#include "ddgi/v1/render_service.grpc.pb.h"
#include "ddgi/v1/web.pb.h"

namespace ddgi::service {

class WebProbeStream {
 public:
  // Sends one reply to the browser; false when it could not (which ends the stream).
  using Send = std::function<bool(const v1::WebReply& reply)>;

  // Starts the call with `token` as its bearer token (none when empty). Every message and the
  // stream's end (WebStreamEnded: OK when stopped or the session closed) carry `id`.
  WebProbeStream(v1::RenderService::Stub& stub, const std::string& token,
                 const v1::StreamProbesRequest& request, uint64_t id, Send send);
  // Cancels the call and waits for the thread.
  ~WebProbeStream();
  WebProbeStream(const WebProbeStream&) = delete;
  WebProbeStream& operator=(const WebProbeStream&) = delete;

 private:
  void run(v1::RenderService::Stub& stub, v1::StreamProbesRequest request);

  const uint64_t id_;
  Send send_;
  grpc::ClientContext call_;
  std::atomic<bool> stopped_{false};
  std::thread thread_;
};

}  // namespace ddgi::service
