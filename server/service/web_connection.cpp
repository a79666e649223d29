#include "service/web_connection.h"

#include <chrono>

#include "core/log.h"
#include "rpc/status_code_name.h"
#include "service/web_messages.h"

namespace ddgi::service {
namespace {

// Long enough for CreateSession (scene load, GPU build, warm-up) on a loaded server.
constexpr auto kCallDeadline = std::chrono::seconds(300);

}  // namespace

WebConnection::WebConnection(v1::RenderService::Stub& stub, Send send, Metrics& metrics)
    : stub_(stub), send_(std::move(send)), metrics_(metrics) {}

WebConnection::~WebConnection() {
  stream_.reset();
  probe_stream_.reset();
}

void WebConnection::handle_text(std::string_view text) {
  Result<v1::WebRequest> request = parse_web_request(text);
  if (!request.ok()) {
    ++metrics_.web_messages_refused;
    send_reply(web_error_reply(
        0, grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, request.error().message)));
    return;
  }
  send_reply(run(*request));
}

void WebConnection::refuse(const std::string& why) {
  ++metrics_.web_messages_refused;
  send_reply(web_error_reply(0, grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, why)));
}

template <typename Request, typename Response>
grpc::Status WebConnection::forward(grpc::Status (v1::RenderService::Stub::*method)(
                                        grpc::ClientContext*, const Request&, Response*),
                                    const Request& request, Response* response) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + kCallDeadline);
  if (!token_.empty()) context.AddMetadata("authorization", "Bearer " + token_);
  return (stub_.*method)(&context, request, response);
}

v1::WebReply WebConnection::run(const v1::WebRequest& request) {
  using Stub = v1::RenderService::Stub;
  v1::WebReply reply;
  reply.set_id(request.id());
  grpc::Status status;
  switch (request.call_case()) {
    case v1::WebRequest::kHello:
      token_ = request.hello().token();
      status =
          forward(&Stub::GetServerInfo, v1::GetServerInfoRequest(), reply.mutable_server_info());
      break;
    case v1::WebRequest::kListSessions:
      status = forward(&Stub::ListSessions, request.list_sessions(), reply.mutable_sessions());
      break;
    case v1::WebRequest::kCreateSession:
      status = forward(&Stub::CreateSession, request.create_session(), reply.mutable_session());
      break;
    case v1::WebRequest::kGetSession:
      status = forward(&Stub::GetSession, request.get_session(), reply.mutable_session());
      break;
    case v1::WebRequest::kCloseSession:
      status = forward(&Stub::CloseSession, request.close_session(), reply.mutable_closed());
      break;
    case v1::WebRequest::kSetCamera:
      status = forward(&Stub::SetCamera, request.set_camera(), reply.mutable_view());
      break;
    case v1::WebRequest::kUpdateView:
      status = forward(&Stub::UpdateView, request.update_view(), reply.mutable_view());
      break;
    case v1::WebRequest::kAddLight:
      status = forward(&Stub::AddLight, request.add_light(), reply.mutable_light());
      break;
    case v1::WebRequest::kUpdateLight:
      status = forward(&Stub::UpdateLight, request.update_light(), reply.mutable_light());
      break;
    case v1::WebRequest::kRemoveLight:
      status = forward(&Stub::RemoveLight, request.remove_light(), reply.mutable_light());
      break;
    case v1::WebRequest::kSetInstanceTransform:
      status = forward(&Stub::SetInstanceTransform, request.set_instance_transform(),
                       reply.mutable_instance());
      break;
    case v1::WebRequest::kGetFieldParams:
      status =
          forward(&Stub::GetFieldParams, request.get_field_params(), reply.mutable_field_params());
      break;
    case v1::WebRequest::kSetFieldParams:
      status =
          forward(&Stub::SetFieldParams, request.set_field_params(), reply.mutable_field_params());
      break;
    case v1::WebRequest::kStreamFrames:
      return start_stream(request.id(), request.stream_frames());
    case v1::WebRequest::kStopFrames:
      stream_.reset();
      reply.mutable_stream_ended()->set_code("OK");
      return reply;
    case v1::WebRequest::kQueryIrradiance:
      status =
          forward(&Stub::QueryIrradiance, request.query_irradiance(), reply.mutable_irradiance());
      break;
    case v1::WebRequest::kStreamProbes:
      return start_probe_stream(request.id(), request.stream_probes());
    case v1::WebRequest::kStopProbes:
      probe_stream_.reset();
      reply.mutable_stream_ended()->set_code("OK");
      return reply;
    case v1::WebRequest::CALL_NOT_SET:
      break;  // parse_web_request refuses these
  }
  return status.ok() ? reply : web_error_reply(request.id(), status);
}

v1::WebReply WebConnection::start_stream(uint64_t id, const v1::StreamFramesRequest& request) {
  stream_.reset();  // one stream per connection: the new one replaces it
  auto send_frame = [this](const std::string& message) { return send_(true, message); };
  auto ended = [this, id](const grpc::Status& status) {
    v1::WebReply reply;
    reply.set_id(id);
    reply.mutable_stream_ended()->set_code(status_code_name(status.error_code()));
    reply.mutable_stream_ended()->set_message(status.error_message());
    send_reply(reply);
  };
  stream_ = std::make_unique<WebFrameStream>(stub_, token_, request, std::move(send_frame),
                                             std::move(ended), metrics_);
  v1::WebReply reply;
  reply.set_id(id);
  reply.mutable_stream_started();
  return reply;
}

v1::WebReply WebConnection::start_probe_stream(uint64_t id,
                                               const v1::StreamProbesRequest& request) {
  probe_stream_.reset();  // one probe stream per connection: the new one replaces it
  auto send = [this](const v1::WebReply& reply) { return send_(false, web_reply_text(reply)); };
  probe_stream_ = std::make_unique<WebProbeStream>(stub_, token_, request, id, std::move(send));
  v1::WebReply reply;
  reply.set_id(id);
  reply.mutable_stream_started();
  return reply;
}

void WebConnection::send_reply(const v1::WebReply& reply) {
  if (!send_(false, web_reply_text(reply))) {
    LOG_DEBUG << "web: a reply could not be sent (connection gone)";
  }
}

}  // namespace ddgi::service
