#include "service/web_probe_stream.h"

#include "rpc/status_code_name.h"

namespace ddgi::service {

WebProbeStream::WebProbeStream(v1::RenderService::Stub& stub, const std::string& token,
                               const v1::StreamProbesRequest& request, uint64_t id, Send send)
    : id_(id), send_(std::move(send)) {
  if (!token.empty()) call_.AddMetadata("authorization", "Bearer " + token);
  thread_ = std::thread([this, &stub, request] { run(stub, request); });
}

WebProbeStream::~WebProbeStream() {
  stopped_ = true;
  call_.TryCancel();
  thread_.join();
}

void WebProbeStream::run(v1::RenderService::Stub& stub, v1::StreamProbesRequest request) {
  auto reader = stub.StreamProbes(&call_, request);
  v1::WebReply reply;
  reply.set_id(id_);
  while (reader->Read(reply.mutable_probe_update())) {
    if (!send_(reply)) {
      call_.TryCancel();  // the browser is gone: end the call, report nothing
      (void)reader->Finish();
      return;
    }
  }
  const grpc::Status status = reader->Finish();
  v1::WebReply ended;
  ended.set_id(id_);
  // Our own cancel is how a viewer ends its stream: not an error to report.
  const grpc::Status reported = stopped_ ? grpc::Status::OK : status;
  ended.mutable_stream_ended()->set_code(status_code_name(reported.error_code()));
  ended.mutable_stream_ended()->set_message(reported.error_message());
  (void)send_(ended);
}

}  // namespace ddgi::service
