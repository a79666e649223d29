#include "service/limits.h"

#include <algorithm>
#include <string>

namespace ddgi::service {
namespace {

template <typename T>
Status check_range(const char* flag, T value, T min, T max) {
  if (value < min || value > max) {
    return invalid_argument(std::string("--") + flag + " must be in [" + std::to_string(min) +
                            ", " + std::to_string(max) + "] (got " + std::to_string(value) + ")");
  }
  return ok_status();
}

}  // namespace

Status validate(const ServiceLimits& l) {
  DDGI_TRY(check_range<uint32_t>("max-sessions", l.max_sessions, 1, 1024));
  DDGI_TRY(check_range<uint32_t>("max-views-per-session", l.max_views_per_session, 1, 256));
  DDGI_TRY(check_range<uint32_t>("max-one-off-frames", l.max_one_off_frames, 1, 256));
  DDGI_TRY(check_range<uint32_t>("max-width", l.max_width, 1, 16384));
  DDGI_TRY(check_range<uint32_t>("max-height", l.max_height, 1, 16384));
  DDGI_TRY(
      check_range<uint64_t>("max-message-bytes", l.max_message_bytes, 64ull << 10, 1ull << 30));
  DDGI_TRY(check_range<uint64_t>("max-upload-bytes", l.max_upload_bytes, 1ull << 10, 1ull << 30));
  DDGI_TRY(check_range<uint32_t>("max-query-points", l.max_query_points, 1, 1u << 20));
  DDGI_TRY(check_range<uint32_t>("max-lights", l.max_lights, 1, 65536));
  DDGI_TRY(check_range<double>("max-fps", l.max_fps, 1.0, 1000.0));
  DDGI_TRY(check_range<uint32_t>("max-warmup-updates", l.max_warmup_updates, 0, 65536));
  return ok_status();
}

uint64_t max_receive_bytes(const ServiceLimits& limits) {
  // An upload travels in one message beside a few small fields.
  return std::max<uint64_t>(limits.max_message_bytes, limits.max_upload_bytes + (64ull << 10));
}

}  // namespace ddgi::service
