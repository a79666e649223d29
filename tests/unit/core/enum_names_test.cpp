// The enum name tables (core/enum_names.h) and the names built on them: log levels both ways,
// error codes, and the gRPC status codes the server and the clients print.
#include <gtest/gtest.h>

#include "core/enum_names.h"
#include "core/log.h"
#include "core/result.h"
#include "rpc/status_code_name.h"

namespace ddgi {
namespace {

enum class Colour { kRed, kGreen, kBlue };
constexpr EnumName<Colour> kColours[] = {{Colour::kRed, "red"}, {Colour::kGreen, "green"}};

TEST(EnumNames, LooksUpBothWays) {
  EXPECT_STREQ(enum_name(kColours, Colour::kGreen, "?"), "green");
  EXPECT_STREQ(enum_name(kColours, Colour::kBlue, "?"), "?");
  EXPECT_EQ(enum_value(kColours, "red"), Colour::kRed);
  EXPECT_EQ(enum_value(kColours, "blue"), std::nullopt);
  EXPECT_EQ(enum_value(kColours, "Red"), std::nullopt);
}

TEST(EnumNames, ParsesEveryLogLevel) {
  const std::pair<const char*, LogLevel> levels[] = {{"debug", LogLevel::kDebug},
                                                     {"info", LogLevel::kInfo},
                                                     {"warning", LogLevel::kWarning},
                                                     {"error", LogLevel::kError},
                                                     {"off", LogLevel::kOff}};
  for (const auto& [text, expected] : levels) {
    LogLevel level = LogLevel::kInfo;
    ASSERT_TRUE(parse_log_level(text, &level)) << text;
    EXPECT_EQ(level, expected) << text;
  }
  LogLevel untouched = LogLevel::kError;
  EXPECT_FALSE(parse_log_level("WARN", &untouched));
  EXPECT_EQ(untouched, LogLevel::kError);
}

TEST(EnumNames, NamesErrorCodesAsGrpcDoes) {
  EXPECT_STREQ(error_code_name(ErrorCode::kInvalidArgument), "INVALID_ARGUMENT");
  EXPECT_STREQ(error_code_name(ErrorCode::kInternal), "INTERNAL");
  EXPECT_STREQ(error_code_name(ErrorCode::kResourceExhausted),
               status_code_name(grpc::StatusCode::RESOURCE_EXHAUSTED));
}

TEST(EnumNames, NamesEveryStatusCode) {
  EXPECT_STREQ(status_code_name(grpc::StatusCode::OK), "OK");
  EXPECT_STREQ(status_code_name(grpc::StatusCode::ABORTED), "ABORTED");
  EXPECT_STREQ(status_code_name(grpc::StatusCode::UNAUTHENTICATED), "UNAUTHENTICATED");
  // 17 is no status code yet a value the enum can hold (its range is [-32, 31]: UBSan showed
  // that 99 made the cast itself undefined).
  EXPECT_STREQ(status_code_name(static_cast<grpc::StatusCode>(17)), "UNKNOWN");
}

TEST(EnumNames, StatusCodesComeBackFromTheirNames) {
  for (int code = 0; code <= 16; ++code) {
    const auto status = static_cast<grpc::StatusCode>(code);
    EXPECT_EQ(status_code_from_name(status_code_name(status)), status) << code;
  }
  EXPECT_EQ(status_code_from_name("not_found"), grpc::StatusCode::UNKNOWN) << "names are exact";
  EXPECT_EQ(status_code_from_name(""), grpc::StatusCode::UNKNOWN);
}

}  // namespace
}  // namespace ddgi
