// The web client's messages (proto/ddgi/v1/web.proto) to and from the bytes of WebSocket
// messages: requests and replies as proto3 JSON (protobuf's own parser and printer, no
// hand-written JSON). Frames are rpc/web_frame.h's.
#pragma once

#include <grpcpp/grpcpp.h>

#include <cstdint>
#include <string>
#include <string_view>

#include "core/result.h"
#include "ddgi/v1/web.pb.h"

namespace ddgi::service {

// A text message from a browser: one WebRequest in proto3 JSON. Unknown fields, wrong types
// and a request without a call are INVALID_ARGUMENT naming what is wrong.
Result<v1::WebRequest> parse_web_request(std::string_view text);

// The JSON text of a reply (fields at their defaults included, so the page sees every value).
std::string web_reply_text(const v1::WebReply& reply);
// A reply that refuses request `id` with `status`.
v1::WebReply web_error_reply(uint64_t id, const grpc::Status& status);

}  // namespace ddgi::service
