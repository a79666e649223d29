#include "core/log.h"

#include <atomic>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <optional>

#include "core/enum_names.h"

namespace ddgi {
namespace {
std::atomic<LogLevel> g_level{LogLevel::kInfo};

// What a log line shows.
constexpr EnumName<LogLevel> kLevelLabels[] = {{LogLevel::kDebug, "DEBUG"},
                                               {LogLevel::kInfo, "INFO"},
                                               {LogLevel::kWarning, "WARN"},
                                               {LogLevel::kError, "ERROR"},
                                               {LogLevel::kOff, "OFF"}};
// What --log-level takes.
constexpr EnumName<LogLevel> kLevelFlags[] = {{LogLevel::kDebug, "debug"},
                                              {LogLevel::kInfo, "info"},
                                              {LogLevel::kWarning, "warning"},
                                              {LogLevel::kError, "error"},
                                              {LogLevel::kOff, "off"}};
}  // namespace

void set_log_level(LogLevel level) {
  g_level = level;
}
LogLevel log_level() {
  return g_level;
}

bool parse_log_level(const std::string& text, LogLevel* level) {
  const std::optional<LogLevel> parsed = enum_value(kLevelFlags, text);
  if (!parsed) return false;
  *level = *parsed;
  return true;
}

void log_line(LogLevel level, const std::string& message) {
  if (level < g_level.load()) return;
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  const int millis = static_cast<int>(
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y-%m-%dT%H:%M:%S", &utc);
  // One fprintf per line keeps lines whole when several threads log.
  std::fprintf(stderr, "%s.%03dZ %-5s %s\n", stamp, millis, enum_name(kLevelLabels, level, "?"),
               message.c_str());
}

}  // namespace ddgi
