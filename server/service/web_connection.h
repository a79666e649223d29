// One browser's WebSocket (web.proto): each text message is a WebRequest, forwarded to the
// RenderService RPC it names over the in-process channel with this connection's token, and
// answered with a WebReply; frame streams run on their own threads (web_frame_stream.h). The
// requests of one connection are handled one at a time, in order, on civetweb's thread for it.
#pragma once

#include <grpcpp/grpcpp.h>

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>

#include "ddgi/v1/render_service.grpc.pb.h"
#include "ddgi/v1/web.pb.h"
#include "service/metrics.h"
#include "service/web_frame_stream.h"
#include "service/web_probe_stream.h"

namespace ddgi::service {

class WebConnection {
 public:
  // Writes one message to the browser (text or binary); false when the connection is gone.
  using Send = std::function<bool(bool binary, std::string_view bytes)>;

  WebConnection(v1::RenderService::Stub& stub, Send send, Metrics& metrics);
  // Ends the frame and probe streams (waits for their threads).
  ~WebConnection();

  // One text message from the browser: runs the call and sends its reply.
  void handle_text(std::string_view text);
  // A message the protocol does not allow (binary, fragmented, too large): refused with a
  // reply naming why; the connection stays open.
  void refuse(const std::string& why);

 private:
  v1::WebReply run(const v1::WebRequest& request);
  // Forwards one unary call with this connection's token.
  template <typename Request, typename Response>
  grpc::Status forward(grpc::Status (v1::RenderService::Stub::*method)(grpc::ClientContext*,
                                                                       const Request&, Response*),
                       const Request& request, Response* response);
  v1::WebReply start_stream(uint64_t id, const v1::StreamFramesRequest& request);
  v1::WebReply start_probe_stream(uint64_t id, const v1::StreamProbesRequest& request);
  void send_reply(const v1::WebReply& reply);

  v1::RenderService::Stub& stub_;
  Send send_;
  Metrics& metrics_;
  std::string token_;
  std::unique_ptr<WebFrameStream> stream_;
  std::unique_ptr<WebProbeStream> probe_stream_;
};

}  // namespace ddgi::service
