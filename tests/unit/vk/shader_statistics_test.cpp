// The shader-statistics table of ddgi-bench --shader-stats: statistics in, markdown out.
#include "vk/shader_statistics.h"

#include <gtest/gtest.h>

namespace ddgi::vk {
namespace {

// Two kernels whose executables report different statistics (as NVIDIA's and Mesa's do): one
// row per kernel and executable in the order first seen, one column per statistic name, the
// values under their own names, empty cells where an executable has no such statistic.
TEST(ShaderStatisticsTable, PivotsStatisticsIntoRowsAndColumns) {
  const std::vector<ShaderStatistic> statistics = {
      {"field_blend", "Compute Shader", "Register Count", "40"},
      {"field_blend", "Compute Shader", "Shared Memory Size", "4096"},
      {"field_trace", "Ray Generation", "Register Count", "96"},
      {"field_trace", "Ray Generation", "Stack Size", "128"},
      {"field_trace", "Closest Hit", "Register Count", "64"},
  };
  EXPECT_EQ(shader_statistics_table(statistics),
            "| kernel | executable | Register Count | Shared Memory Size | Stack Size |\n"
            "|---|---|---|---|---|\n"
            "| field_blend | Compute Shader | 40 | 4096 | |\n"
            "| field_trace | Ray Generation | 96 | | 128 |\n"
            "| field_trace | Closest Hit | 64 | | |\n");
}

// A driver that reports nothing (lavapipe here) gets a line saying so, not an empty table.
TEST(ShaderStatisticsTable, SaysWhenTheDriverReportedNone) {
  EXPECT_EQ(shader_statistics_table({}), "(the driver reported none)\n");
}

}  // namespace
}  // namespace ddgi::vk
