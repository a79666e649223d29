// The dynamic-response measure (ddgi-eval --dynamic, tools/dynamic_response.h): the settling
// rule on hand-made curves, the change's parsing and refusals, then the executable on the
// Cornell box with its light moved: a field with low hysteresis settles within a few frames, one
// with the default high hysteresis takes many more, both settle where a field warmed up on the
// moved light sits, and the path tracer restarted at the change is the baseline.
#include <unistd.h>

#include <filesystem>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "scene/gltf_loader.h"
#include "tests/gpu/cli_run.h"
#include "tools/dynamic_response.h"

namespace ddgi::test {
namespace {

TEST(DynamicResponse, SettlesAtTheFirstFrameFromWhichEveryLaterOneIsWithinTenPercent) {
  tools::ResponseCurve curve;
  curve.error = {1.0, 0.5, 0.3, 0.21, 0.2, 0.23, 0.19, 0.2, 0.2, 0.2};
  curve.ms = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  // Frame by frame: 0.23 at frame 5 is over 1.1 x 0.2, so settled from frame 6 on, not 3.
  EXPECT_EQ(curve.frames_until_within(0.2, 1.1, 1), 6);
  EXPECT_EQ(curve.frames_until_within(0.2, 1.2, 1), 3);
  EXPECT_EQ(curve.frames_until_within(0.1, 1.1, 1), -1);  // never
  // In means of two frames, (0.21 + 0.2) / 2 <= 0.22 from frame 3 on; (0.3 + 0.21) / 2 is not.
  EXPECT_EQ(curve.frames_until_within(0.2, 1.1, 2), 3);
  EXPECT_DOUBLE_EQ(curve.ms_until(6), 21.0);
  EXPECT_DOUBLE_EQ(tools::relative_l1({1, 2, 3, 9, 2, 2, 2, 9}, {1, 2, 3, 0, 1, 2, 4, 0}),
                   3.0 / 13);
}

TEST(DynamicResponse, ChangesAreParsedAndBadOnesRefusedByWhatIsWrong) {
  auto scene = load_scene(std::string(DDGI_SOURCE_DIR) + "/scenes/cornell_box.gltf");
  ASSERT_TRUE(scene.ok());
  auto light = tools::parse_scene_change("light:0:-0.5,0.25,1", *scene);
  ASSERT_TRUE(light.ok()) << light.error().message;
  const Scene moved = tools::changed_scene(*scene, *light);
  EXPECT_LT(glm::length(moved.lights[0].position - scene->lights[0].position -
                        glm::vec3(-0.5f, 0.25f, 1.0f)),
            1e-6f);
  auto object = tools::parse_scene_change("object:6:0,0,0.5", *scene);
  ASSERT_TRUE(object.ok()) << object.error().message;
  EXPECT_FLOAT_EQ(tools::changed_scene(*scene, *object).instances[6].transform[3].z,
                  scene->instances[6].transform[3].z + 0.5f);
  const std::pair<const char*, const char*> refused[] = {
      {"lamp:0:1,1,1", "kind 'lamp'"},      {"light:1:1,1,1", "has 1 light;"},
      {"object:7:1,1,1", "7 is not one"},   {"light:0:1,1", "three offsets"},
      {"light:0:1,1,1,1", "three offsets"}, {"light:0:1,nan,1", "finite"},
      {"light:0.5:1,1,1", "not one of"},    {"light", "light:INDEX"}};
  for (const auto& [text, message] : refused) {
    auto change = tools::parse_scene_change(text, *scene);
    ASSERT_FALSE(change.ok()) << text;
    EXPECT_NE(change.error().message.find(message), std::string::npos)
        << text << ": " << change.error().message;
  }
}

// One table row of ddgi-eval --dynamic: error at the first frame, steady error, frames.
struct Row {
  double first = 0, steady = 0;
  long frames = -2;
};

Row row(const std::string& out, const std::string& method) {
  const size_t at = out.find("| cornell_box | " + method + " |");
  if (at == std::string::npos) return {};
  std::istringstream line(out.substr(at, out.find('\n', at) - at));
  std::string cell;
  std::vector<std::string> cells;
  while (std::getline(line, cell, '|')) cells.push_back(cell);
  if (cells.size() < 6) return {};
  const std::string frames = cells[5];
  return {std::stod(cells[3]), std::stod(cells[4]),
          frames.find("never") != std::string::npos ? -1 : std::stol(frames)};
}

TEST(DynamicResponseCli, LowHysteresisSettlesSoonerAfterALightMove) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("ddgi-dynamic-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "out");
  const CliRun run = run_cli(DDGI_EVAL_EXE,
                             "scenes/cornell_box.gltf --width 32 --height 24 --spp 256 "
                             "--warmup 32 --response-frames 40 --dynamic light:0:-0.7,-0.3,0 "
                             "--field counts=4,4,4 --configs 'slow:hysteresis=0.97;"
                             "fast:hysteresis=0.6' --pareto '" +
                                 (dir / "out").string() + "'",
                             dir);
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const Row slow = row(run.out, "slow"), fast = row(run.out, "fast");
  const Row traced = row(run.out, "path tracing, 1 spp per frame");
  std::printf(
      "settled after: slow %ld frames, fast %ld, path tracing %ld (to the best field's "
      "%.3f); first-frame errors %.3f / %.3f / %.3f\n",
      slow.frames, fast.frames, traced.frames, traced.steady, slow.first, fast.first, traced.first);
  // Measured on lavapipe: slow 20, fast 0, path tracing 6 frames (10-frame means).
  EXPECT_GE(slow.frames, 10);
  EXPECT_GE(fast.frames, 0);
  EXPECT_LE(fast.frames, 4);
  EXPECT_GT(slow.first, 1.15 * slow.steady);  // the lag is there to measure
  EXPECT_NEAR(slow.steady, fast.steady, 0.2 * fast.steady);
  EXPECT_GT(traced.first, slow.first);  // one sample per pixel is noisier than any field
  EXPECT_GE(traced.frames, 1);
  const std::string csv = slurp(dir / "out" / "cornell_box.response.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 41);
  EXPECT_EQ(csv.rfind("frame,slow,slow rays,fast,fast rays,\"path tracing, 1 spp per frame\"\n", 0),
            0u)
      << csv.substr(0, 80);
  const std::string svg = slurp(dir / "out" / "cornell_box.response.svg");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("frames after the change"), std::string::npos);
  // Its PNG: the first configuration's curve, more than its legend marker.
  EXPECT_GT(plot_pixels_of_colour(dir / "out" / "cornell_box.response.png", 0x1f77b4), 45);
  std::filesystem::remove_all(dir);
}

// The response flags' ranges, refused by name before any GPU work.
TEST(DynamicResponseCli, BadResponseFlagsAreRefusedByName) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("ddgi-dynamic-bad-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const char* flag : {"--response-static -1", "--response-static 100001",
                           "--response-static many", "--response-frames 4"}) {
    const CliRun run =
        run_cli(DDGI_EVAL_EXE,
                std::string("scenes/cornell_box.gltf --dynamic light:0:0,0.1,0 ") + flag, dir);
    EXPECT_NE(run.exit_code, 0) << flag;
    const std::string name = std::string(flag).substr(2, std::string(flag).find(' ') - 2);
    EXPECT_NE(run.err.find(name), std::string::npos) << flag << ": " << run.err;
    EXPECT_EQ(run.out.find("| cornell_box |"), std::string::npos) << flag;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ddgi::test
