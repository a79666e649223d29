#include "rpc/web_frame.h"

#include <google/protobuf/util/json_util.h>

namespace ddgi {

std::string encode_web_frame(const v1::Frame& frame, uint64_t more_dropped) {
  v1::Frame header = frame;
  header.clear_jpeg();
  header.set_frames_dropped(frame.frames_dropped() + more_dropped);
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  std::string header_text;
  (void)google::protobuf::util::MessageToJsonString(header, &header_text, options);
  const uint32_t length = static_cast<uint32_t>(header_text.size());
  std::string message;
  message.reserve(4 + header_text.size() + frame.jpeg().size());
  for (int byte = 0; byte < 4; ++byte) message.push_back(char((length >> (8 * byte)) & 0xff));
  message += header_text;
  message += frame.jpeg();
  return message;
}

Result<v1::Frame> decode_web_frame(std::string_view message) {
  if (message.size() < 4) return invalid_argument("a frame message is shorter than 4 bytes");
  uint32_t length = 0;
  for (int byte = 0; byte < 4; ++byte) length |= uint32_t(uint8_t(message[byte])) << (8 * byte);
  if (length > message.size() - 4) {
    return invalid_argument("a frame message's header length " + std::to_string(length) +
                            " is past its end");
  }
  v1::Frame frame;
  const auto status = google::protobuf::util::JsonStringToMessage(
      google::protobuf::StringPiece(message.data() + 4, length), &frame);
  if (!status.ok()) {
    return invalid_argument("a frame message's header is not a Frame: " +
                            std::string(status.message()));
  }
  frame.set_jpeg(std::string(message.substr(4 + length)));
  return frame;
}

}  // namespace ddgi
