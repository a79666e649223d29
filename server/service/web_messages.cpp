#include "service/web_messages.h"

#include <google/protobuf/util/json_util.h>

#include "rpc/status_code_name.h"

namespace ddgi::service {
namespace {

std::string to_json(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  std::string text;
  // Printing our own, well-formed messages cannot fail.
  (void)google::protobuf::util::MessageToJsonString(message, &text, options);
  return text;
}

}  // namespace

Result<v1::WebRequest> parse_web_request(std::string_view text) {
  v1::WebRequest request;
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = false;
  const auto status = google::protobuf::util::JsonStringToMessage(
      google::protobuf::StringPiece(text.data(), text.size()), &request, options);
  if (!status.ok()) {
    return invalid_argument("the message is not a WebRequest in JSON: " +
                            std::string(status.message()));
  }
  if (request.call_case() == v1::WebRequest::CALL_NOT_SET) {
    return invalid_argument("the WebRequest names no call (e.g. \"hello\", \"setCamera\")");
  }
  return request;
}

std::string web_reply_text(const v1::WebReply& reply) {
  return to_json(reply);
}

v1::WebReply web_error_reply(uint64_t id, const grpc::Status& status) {
  v1::WebReply reply;
  reply.set_id(id);
  reply.mutable_error()->set_code(status_code_name(status.error_code()));
  reply.mutable_error()->set_message(status.error_message());
  return reply;
}

}  // namespace ddgi::service
