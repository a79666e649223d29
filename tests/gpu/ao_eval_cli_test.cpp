// ddgi-ao-eval end to end on a tiny box_on_floor (tools/ao_eval_main.cpp): a row per AO mode with
// the cache's error below one traced ray's; bad flags refused by name before any GPU work.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "tests/gpu/cli_run.h"

namespace ddgi::test {
namespace {

class AoEvalCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("ddgi-ao-eval-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  CliRun eval(const std::string& arguments) { return run_cli(DDGI_AO_EVAL_EXE, arguments, dir_); }
  std::filesystem::path dir_;
};

// The mean error column of the row that starts with `row` (-1 when there is none).
double mean_error(const std::string& table, const std::string& row) {
  const size_t at = table.find(row);
  if (at == std::string::npos) return -1.0;
  std::istringstream line(table.substr(at + row.size()));
  double ms = 0.0, error = -1.0;
  char bar = 0;
  line >> ms >> bar >> error;
  return error;
}

TEST_F(AoEvalCliTest, PrintsARowPerModeAndTheCacheBeatsOneRay) {
  const CliRun run = eval(
      "scenes/box_on_floor.gltf --width 48 --height 36 --reference-spp 256 --warmup 8 "
      "--frames 1");
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  for (const char* mode :
       {"| box_on_floor | ao-traced 1 ray |", "| box_on_floor | ao-traced 4 rays |",
        "| box_on_floor | ao-traced 16 rays |", "| box_on_floor | ao (shadow field) |",
        "| box_on_floor | ao-cache |"}) {
    EXPECT_NE(run.out.find(mode), std::string::npos) << mode << "\n" << run.out;
  }
  const double one_ray = mean_error(run.out, "| box_on_floor | ao-traced 1 ray |");
  const double cache = mean_error(run.out, "| box_on_floor | ao-cache |");
  std::printf("mean error: one ray %.4f, cache %.4f\n", one_ray, cache);
  EXPECT_GT(one_ray, 0.0);
  EXPECT_GT(cache, 0.0);
  EXPECT_LT(cache, one_ray);
}

TEST_F(AoEvalCliTest, BadFlagsAreRefusedByName) {
  const CliRun no_scene = eval("--width 8");
  EXPECT_EQ(no_scene.exit_code, 2);
  EXPECT_NE(no_scene.err.find("name at least one SCENE"), std::string::npos) << no_scene.err;
  const CliRun entries = eval("scenes/box_on_floor.gltf --world-cache entries=3000");
  EXPECT_EQ(entries.exit_code, 2);
  EXPECT_NE(entries.err.find("world cache entries must be a power of two"), std::string::npos)
      << entries.err;
  const CliRun spp = eval("scenes/box_on_floor.gltf --reference-spp 0");
  EXPECT_EQ(spp.exit_code, 2);
  EXPECT_NE(spp.err.find("reference-spp"), std::string::npos) << spp.err;
}

}  // namespace
}  // namespace ddgi::test
