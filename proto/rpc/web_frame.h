// A frame as the web front sends it to browsers (proto/ddgi/v1/web.proto): a 4-byte
// little-endian length N, N bytes of the Frame's JSON without its jpeg, then the JPEG bytes.
// The server writes it, the C++ web client (web_link.h) reads it; web/socket.js reads it too.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"

namespace ddgi {

// `frame` as a binary WebSocket message, its frames_dropped raised by `more_dropped` (the
// frames the WebSocket side skipped).
std::string encode_web_frame(const v1::Frame& frame, uint64_t more_dropped);
// The Frame (jpeg included) of such a message; INVALID_ARGUMENT when it is not one.
Result<v1::Frame> decode_web_frame(std::string_view message);

}  // namespace ddgi
