// ddgi-eval --path (tools/path_eval.h) end to end on the Cornell box: a 1 s walk of 0.6 m along
// x inside the box, a static field and a tracking one of 0.22 m cells. Every scored view is where
// the path says, each configuration scores every view against its reference, and only the tracking
// field scrolls, at the frames where the camera crosses its cells.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/gpu/cli_run.h"

namespace ddgi::test {
namespace {

// The summary row (second table) of configuration `name`.
std::vector<std::string> summary_row(const std::string& out, const std::string& name) {
  const size_t summary = out.find("| configuration | probes |");
  std::stringstream in(out.substr(summary == std::string::npos ? out.size() : summary));
  std::string line;
  while (std::getline(in, line)) {
    const std::vector<std::string> c = markdown_cells(line);
    if (!c.empty() && c[0] == name) return c;
  }
  return {};
}

class PathEvalCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("ddgi-path-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_ / "out");
    std::ofstream(dir_ / "walk.path.json")
        << R"({"keyframes": [{"time": 0, "position": [-0.3, 1, 0.6], "target": [-0.3, 1, -1]},
                             {"time": 1, "position": [0.3, 1, 0.6], "target": [0.3, 1, -1]}]})";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

// 6 frames per second (x = -0.3, -0.2, ..., 0.3), views scored every 0.5 s (x = -0.3, 0, 0.3).
// The tracking field (4x4x4 probes 0.22 m apart, placed centred on the camera's start) scrolls
// a cell when the camera is a cell or more from its centre: at x = 0 (0.3 from -0.3; centre then
// -0.08) and at x = 0.2 (0.28 from it), at no frame within 0.06 m of a border. Measured on
// lavapipe at this tiny size (FLIP is high at 48x36): FLIP 0.40-0.46 / PSNR 14.9-17.3 dB
// (static), 0.35-0.54 / 15.1-15.3 dB (tracking); frames planted black: FLIP 0.95, 5.0-5.2 dB.
TEST_F(PathEvalCliTest, ScoresEveryViewAlongThePathAndOnlyTheTrackingFieldScrolls) {
  const CliRun run = run_cli(
      DDGI_EVAL_EXE,
      "scenes/cornell_box.gltf --width 48 --height 36 --spp 64 --warmup 8 --path '" +
          (dir_ / "walk.path.json").string() + "' --path-rate 6 --path-every 0.5 --out-dir '" +
          (dir_ / "out").string() +
          "' --configs 'static:counts=4,4,4,rays_per_probe=32;tracking:counts=4,4,4,"
          "spacing=0.22,0.22,0.22,origin=-0.63,0.67,0.27,track_camera=true,rays_per_probe=32'",
      dir_);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  // The views, where the path puts the camera, each scored for both configurations.
  std::stringstream csv(slurp(dir_ / "out" / "cornell_box.path.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "time,x,y,z,static FLIP,static PSNR,tracking FLIP,tracking PSNR");
  const double expected_x[] = {-0.3, 0.0, 0.3};
  for (int view = 0; view < 3; ++view) {
    ASSERT_TRUE(std::getline(csv, line)) << "view " << view << " missing";
    std::vector<double> v;
    std::stringstream fields(line);
    for (std::string f; std::getline(fields, f, ',');) v.push_back(std::stod(f));
    ASSERT_EQ(v.size(), 8u) << line;
    EXPECT_NEAR(v[0], 0.5 * view, 1e-9) << line;
    EXPECT_NEAR(v[1], expected_x[view], 1e-5) << line;
    EXPECT_NEAR(v[3], 0.6, 1e-5) << line;
    for (size_t flip : {4u, 6u}) {
      EXPECT_GT(v[flip], 0.0) << line;       // a frame equal to its reference: not scored
      EXPECT_LT(v[flip], 0.7) << line;       // planted black frames: 0.95
      EXPECT_GT(v[flip + 1], 10.0) << line;  // PSNR; black frames: 5.0-5.2 dB
    }
  }
  EXPECT_FALSE(std::getline(csv, line)) << "more views than scored: " << line;
  // Scroll frames (column 12): the frames at x = 0 and 0.2 for the tracking field, none for
  // the static one; 7 frames each (column 11).
  const std::vector<std::string> fixed = summary_row(run.out, "static");
  const std::vector<std::string> tracking = summary_row(run.out, "tracking");
  ASSERT_EQ(fixed.size(), 14u) << run.out;
  ASSERT_EQ(tracking.size(), 14u) << run.out;
  EXPECT_EQ(fixed[10], "7");
  EXPECT_EQ(fixed[11], "0");
  EXPECT_EQ(tracking[11], "2") << run.out;
  EXPECT_TRUE(std::filesystem::exists(dir_ / "out" / "cornell_box.path.svg"));
  EXPECT_GT(plot_pixels_of_colour(dir_ / "out" / "cornell_box.path.png", 0x1f77b4), 45);
  EXPECT_TRUE(std::filesystem::exists(dir_ / "out" / "cornell_box.path001.tracking.exr"));
}

TEST_F(PathEvalCliTest, BadPathsAreRefusedByName) {
  std::ofstream(dir_ / "bad.path.json") << R"({"keyframes": [{"time": 0}]})";
  const CliRun run = run_cli(
      DDGI_EVAL_EXE,
      "scenes/cornell_box.gltf --path '" + (dir_ / "bad.path.json").string() + "' --spp 1", dir_);
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("bad.path.json: keyframes: expected an array of 2 to 100000 keyframes"),
            std::string::npos)
      << run.err;
  const CliRun two = run_cli(DDGI_EVAL_EXE,
                             "scenes/cornell_box.gltf scenes/white_box.gltf --path '" +
                                 (dir_ / "bad.path.json").string() + "'",
                             dir_);
  EXPECT_NE(two.err.find("--path takes one scene"), std::string::npos) << two.err;
}

}  // namespace
}  // namespace ddgi::test
