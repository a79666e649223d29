// ddgi-shadow-eval end to end on a tiny Cornell box (tools/shadow_eval_main.cpp): the table rows
// of every direct mode, and the plot written as SVG and PNG; a --svg that does not end in .svg
// is refused by name before any GPU work.
#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tests/gpu/cli_run.h"

namespace ddgi::test {
namespace {

class ShadowEvalCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() / ("ddgi-shadow-eval-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  CliRun eval(const std::string& arguments) {
    return run_cli(DDGI_SHADOW_EVAL_EXE, arguments, dir_);
  }
  std::filesystem::path dir_;
};

TEST_F(ShadowEvalCliTest, WritesTheModesTableAndThePlotAsSvgAndPng) {
  const CliRun run = eval(
      "scenes/cornell_box.gltf --width 32 --height 24 --spp 4 --warmup 2 "
      "--frames 1 --resolutions 64:8 --svg '" +
      (dir_ / "direct.svg").string() + "'");
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  for (const char* mode : {"| cornell_box | shadow-rays |", "| cornell_box | unshadowed |",
                           "| cornell_box | shadow-field |"}) {
    EXPECT_NE(run.out.find(mode), std::string::npos) << mode << "\n" << run.out;
  }
  const std::string svg = slurp(dir_ / "direct.svg");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u) << svg.substr(0, 80);
  EXPECT_NE(svg.find("mean FLIP of the direct image"), std::string::npos);
  // One series (the scene): its legend marker and a marker per mode (five).
  const int64_t markers = plot_pixels_of_colour(dir_ / "direct.png", 0x1f77b4);
  EXPECT_GT(markers, 4 * 30);  // measured 224 (~38 a marker; two modes' markers overlap)
}

TEST_F(ShadowEvalCliTest, ASvgPathNotEndingInSvgIsRefusedByName) {
  const CliRun run = eval("scenes/cornell_box.gltf --svg '" + (dir_ / "direct.txt").string() + "'");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("--svg must name a file ending in .svg"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "direct.txt"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "direct.png"));
}

}  // namespace
}  // namespace ddgi::test
