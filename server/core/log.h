// Structured, line-oriented logging to stderr: "time level [context] message key=value...".
// One global level; thread-safe (one line is written with one call).
#pragma once

#include <sstream>
#include <string>

namespace ddgi {

enum class LogLevel { kDebug = 0, kInfo = 1, kWarning = 2, kError = 3, kOff = 4 };

void set_log_level(LogLevel level);
LogLevel log_level();
// Parses "debug", "info", "warning", "error", "off"; returns false when unknown.
bool parse_log_level(const std::string& text, LogLevel* level);
void log_line(LogLevel level, const std::string& message);

namespace detail {
class LogStream {
 public:
  explicit LogStream(LogLevel level) : level_(level) {}
  ~LogStream() { log_line(level_, stream_.str()); }
  template <typename T>
  LogStream& operator<<(const T& value) {
    stream_ << value;
    return *this;
  }

 private:
  LogLevel level_;
  std::ostringstream stream_;
};
}  // namespace detail

}  // namespace ddgi

#define DDGI_LOG(level)                                \
  if (::ddgi::LogLevel::level < ::ddgi::log_level()) { \
  } else                                               \
    ::ddgi::detail::LogStream(::ddgi::LogLevel::level)
#define LOG_DEBUG DDGI_LOG(kDebug)
#define LOG_INFO DDGI_LOG(kInfo)
#define LOG_WARNING DDGI_LOG(kWarning)
#define LOG_ERROR DDGI_LOG(kError)
