// The Pareto harness (ddgi-eval --pareto, tools/pareto.h): the front and the equal-time lookup
// on hand-made points, then the executable end to end on the Cornell box: the JSON holds every
// configuration, the path tracer's curve and a front that is one, and the SVG plot is written
// with all three series.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/gpu/cli_run.h"
#include "tools/pareto.h"

namespace ddgi::test {
namespace {

tools::ConfigPoint point(const char* name, double ms, double flip) {
  tools::ConfigPoint p;
  p.name = name;
  p.field_ms = ms / 2;
  p.frame_ms = ms / 2;
  p.full.flip = flip;
  return p;
}

// Four configurations: "slow and bad" is beaten by "fast" on both axes, so it is not on the
// front; the rest are, by ascending time.
TEST(Pareto, FrontHoldsThePointsNoOtherBeatsOnBothAxes) {
  const std::vector<tools::ConfigPoint> configs = {
      point("slow and bad", 4.0, 0.3), point("fast", 1.0, 0.2), point("best", 8.0, 0.05),
      point("middle", 2.0, 0.1)};
  EXPECT_EQ(tools::pareto_front(configs), (std::vector<size_t>{1, 3, 2}));
}

// Interpolation in log(ms): at the geometric mean of two measured times the FLIP is the mean
// of theirs; outside the measured range there is no value.
TEST(Pareto, PathTraceFlipAtEqualTime) {
  std::vector<tools::PathTracePoint> curve(3);
  curve[0] = {1, 1, 1.0, {0, 0, 0.4, 0}};
  curve[1] = {2, 1, 4.0, {0, 0, 0.2, 0}};
  curve[2] = {4, 1, 16.0, {0, 0, 0.1, 0}};
  EXPECT_NEAR(*tools::path_trace_flip_at(curve, 2.0), 0.3, 1e-12);
  EXPECT_NEAR(*tools::path_trace_flip_at(curve, 8.0), 0.15, 1e-12);
  EXPECT_NEAR(*tools::path_trace_flip_at(curve, 16.0), 0.1, 1e-12);
  EXPECT_FALSE(tools::path_trace_flip_at(curve, 0.5).has_value());
  EXPECT_FALSE(tools::path_trace_flip_at(curve, 17.0).has_value());
  // And the other way: the ms for a FLIP, at the geometric mean where the FLIP is the mean.
  EXPECT_NEAR(*tools::path_trace_ms_for(curve, 0.3), 2.0, 1e-9);
  EXPECT_NEAR(*tools::path_trace_ms_for(curve, 0.15), 8.0, 1e-9);
  EXPECT_FALSE(tools::path_trace_ms_for(curve, 0.05).has_value());
}

// The best configuration within a time: the lowest FLIP among those whose total ms fits, not the
// fastest nor the last; nothing when none fits.
TEST(Pareto, BestFlipWithinATime) {
  const std::vector<tools::ConfigPoint> configs = {
      point("slow and bad", 4.0, 0.3), point("fast", 1.0, 0.2), point("best", 8.0, 0.05),
      point("middle", 2.0, 0.1)};
  EXPECT_FALSE(tools::best_flip_within(configs, 0.9).has_value());
  EXPECT_DOUBLE_EQ(*tools::best_flip_within(configs, 1.0), 0.2);
  EXPECT_DOUBLE_EQ(*tools::best_flip_within(configs, 5.0), 0.1);
  EXPECT_DOUBLE_EQ(*tools::best_flip_within(configs, 8.0), 0.05);
}

// A sweep of more than eight configurations names only the front's points on the plot (their
// names overlapped into a block on the H200's 16-candidate plots); four are all named (below).
// Planted: names kept on every point fails the absence checks.
TEST(Pareto, PlotNamesOnlyTheFrontPastEightConfigurations) {
  tools::SceneTrade trade;
  trade.scene = "many";
  trade.width = 64;
  trade.height = 36;
  trade.reference_spp = 16;
  for (int i = 0; i < 10; ++i) {
    // Two points on the front ("fast 0", "best 9"); the rest slower and worse than "fast 0".
    const std::string name = i == 0 ? "fast 0" : i == 9 ? "best 9" : "beaten " + std::to_string(i);
    trade.configs.push_back(
        point(name.c_str(), i == 0 ? 1.0 : 2.0 + i, i == 9 ? 0.05 : 0.2 + 0.01 * i));
  }
  trade.path_tracing = {{1, 1, 4.0, {0, 0, 0.4, 0}}, {2, 1, 8.0, {0, 0, 0.3, 0}}};
  const auto dir =
      std::filesystem::temp_directory_path() / ("ddgi-plot-names-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  ASSERT_TRUE(tools::write_scene_trade(trade, dir.string()).ok());
  const std::string svg = slurp(dir / "many.svg");
  EXPECT_NE(svg.find(">fast 0<"), std::string::npos);
  EXPECT_NE(svg.find(">best 9<"), std::string::npos);
  for (int i = 1; i < 9; ++i) {
    EXPECT_EQ(svg.find(">beaten " + std::to_string(i) + "<"), std::string::npos) << i;
  }
  std::filesystem::remove_all(dir);
}

class ParetoCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("ddgi-pareto-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_ / "out");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  CliRun eval(const std::string& arguments) { return run_cli(DDGI_EVAL_EXE, arguments, dir_); }
  std::filesystem::path dir_;
};

// Three configurations of different cost, the path tracer at 1/4, 1, 2, 4 spp. Measured on
// lavapipe: path-traced FLIP 0.41 / 0.27 / 0.22 / 0.17 at 1/4 / 1 / 2 / 4 spp; the default's
// mean 0.96 of the reference's.
TEST_F(ParetoCliTest, WritesConfigurationsCurveFrontAndPlot) {
  const CliRun run = eval(
      "scenes/cornell_box.gltf --width 40 --height 30 --spp 16 --warmup 4 --frames 1 "
      "--pt-max-spp 4 --pareto '" +
      (dir_ / "out").string() +
      "' --configs 'default:;16 rays:rays_per_probe=16;small maps:counts=4,4,4,"
      "irradiance_texels=4,distance_texels=8,rays_per_probe=32;sh probes:basis=sh'");
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  EXPECT_NE(run.out.find("| scene | front point |"), std::string::npos) << run.out;
  const nlohmann::json doc = nlohmann::json::parse(slurp(dir_ / "out" / "cornell_box.json"));
  // The probe basis is an axis like any parameter (docs/sh-probes.md).
  ASSERT_EQ(doc["configs"].size(), 4u);
  EXPECT_EQ(doc["configs"][3]["assignments"][0], "basis=sh");
  const double sh_ratio = doc["configs"][3]["full"]["mean_ratio"];
  EXPECT_GT(sh_ratio, 0.5);
  EXPECT_LT(sh_ratio, 2.0);
  EXPECT_EQ(doc["configs"][1]["assignments"][0], "rays_per_probe=16");
  // A vector value keeps its commas (counts=4,4,4 is one assignment, not three pieces).
  ASSERT_EQ(doc["configs"][2]["assignments"].size(), 4u);
  EXPECT_EQ(doc["configs"][2]["assignments"][0], "counts=4,4,4");
  const double mean_ratio = doc["configs"][0]["full"]["mean_ratio"];
  EXPECT_GT(mean_ratio, 0.5);
  EXPECT_LT(mean_ratio, 2.0);

  // 1/4 sample per pixel (one at 20x15, upscaled; 40x30 does not divide by 4), then 1, 2, 4.
  const nlohmann::json& curve = doc["path_tracing"];
  ASSERT_EQ(curve.size(), 4u);
  EXPECT_EQ(curve[0]["spp"], 1u);
  EXPECT_EQ(curve[0]["downscale"], 2u);
  EXPECT_EQ(curve[0]["samples_per_pixel"], 0.25);
  for (size_t i = 0; i < curve.size(); ++i) {
    if (i > 0) {
      EXPECT_EQ(curve[i]["spp"], 1u << (i - 1));
      EXPECT_EQ(curve[i]["downscale"], 1u);
    }
    EXPECT_GT(curve[i]["ms"].get<double>(), 0.0);
    std::printf("path tracing %.2f spp: FLIP %.3f\n", curve[i]["samples_per_pixel"].get<double>(),
                curve[i]["full"]["flip"].get<double>());
  }
  // More samples, less error: the curve is a measurement, not a constant.
  EXPECT_LT(curve[3]["full"]["flip"].get<double>(), curve[1]["full"]["flip"].get<double>());
  EXPECT_LT(curve[3]["full"]["flip"].get<double>(), curve[0]["full"]["flip"].get<double>());

  // The front is one: ascending time, descending FLIP, and every configuration off it is
  // beaten on both axes by a point on it.
  const nlohmann::json& front = doc["front"];
  ASSERT_FALSE(front.empty());
  std::vector<bool> on_front(4, false);
  for (size_t i = 0; i < front.size(); ++i) {
    on_front[front[i]["config"].get<size_t>()] = true;
    if (i > 0) {
      EXPECT_GE(front[i]["total_ms"].get<double>(), front[i - 1]["total_ms"].get<double>());
      EXPECT_LT(front[i]["flip"].get<double>(), front[i - 1]["flip"].get<double>());
    }
  }
  for (size_t c = 0; c < 4; ++c) {
    if (on_front[c]) continue;
    const double ms = doc["configs"][c]["total_ms"], flip = doc["configs"][c]["full"]["flip"];
    bool beaten = false;
    for (const auto& f : front) beaten |= f["total_ms"] <= ms && f["flip"] <= flip;
    EXPECT_TRUE(beaten) << doc["configs"][c]["name"];
  }

  // The equal-time figure at 1, 2 and 5 ms, recomputed here from the points: the best
  // configuration within each time over the path tracer's FLIP there (lavapipe's times put some
  // or all of them outside the measured range: then null, never a made-up value).
  ASSERT_EQ(doc["equal_time"].size(), 3u);
  EXPECT_NE(run.out.find("| scene | ms | best DDGI FLIP within |"), std::string::npos) << run.out;
  for (const nlohmann::json& at : doc["equal_time"]) {
    const double ms = at["ms"];
    std::optional<double> best;
    for (const auto& c : doc["configs"]) {
      const double flip = c["full"]["flip"];
      if (c["total_ms"].get<double>() <= ms && (!best || flip < *best)) best = flip;
    }
    EXPECT_EQ(at["best_flip_within"].is_null(), !best.has_value()) << ms;
    if (best) {
      EXPECT_DOUBLE_EQ(at["best_flip_within"].get<double>(), *best) << ms;
    }
    if (!at["flip_over_path_trace"].is_null()) {
      EXPECT_DOUBLE_EQ(at["flip_over_path_trace"].get<double>(),
                       *best / at["path_trace_flip"].get<double>());
    }
  }

  const std::string svg = slurp(dir_ / "out" / "cornell_box.svg");
  EXPECT_EQ(svg.rfind("<svg", 0), 0u) << svg.substr(0, 80);
  for (const char* text :
       {"Pareto front", "path tracing (spp)", "16 rays", "small maps", "sh probes", ">1/4<"}) {
    EXPECT_NE(svg.find(text), std::string::npos) << text;
  }
  // The PNG beside it draws the three series in their colours (first, second, third of
  // plot_drawing.cpp's): more of each than the legend's marker alone (~40 pixels).
  const std::filesystem::path png = dir_ / "out" / "cornell_box.png";
  const int64_t configs = plot_pixels_of_colour(png, 0x1f77b4);
  const int64_t front_line = plot_pixels_of_colour(png, 0xd62728);
  const int64_t traced = plot_pixels_of_colour(png, 0x2ca02c);
  EXPECT_GT(configs, 60) << "DDGI configurations";  // measured 96, 289 and 145
  EXPECT_GT(front_line, 45) << "Pareto front";
  EXPECT_GT(traced, 45) << "path tracing";
}

TEST_F(ParetoCliTest, BadFlagsAreRefusedByName) {
  CliRun run = eval("scenes/cornell_box.gltf --pt-max-spp 0 --pareto '" + dir_.string() + "'");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("pt-max-spp"), std::string::npos) << run.err;
  run = eval(
      "scenes/cornell_box.gltf --width 16 --height 12 --spp 1 --warmup 1 --frames 1 "
      "--pt-max-spp 1 --pareto /nonexistent/ddgi-pareto");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("/nonexistent/ddgi-pareto"), std::string::npos) << run.err;
  run = eval("scenes/cornell_box.gltf --configs 'dense:4,4,4'");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("'4' is not NAME=VALUE"), std::string::npos) << run.err;
  // The frame's own choices are checked by name too, before any GPU work.
  run = eval("scenes/cornell_box.gltf --width 40 --height 30 --configs 'odd:frame_downscale=3'");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("'odd': frame_downscale=3 must divide --width 40 and --height 30"),
            std::string::npos)
      << run.err;
  run = eval("scenes/cornell_box.gltf --configs 'big:frame_downscale=9'");
  EXPECT_NE(run.err.find("frame_downscale must be a whole number in [1, 8] (got '9')"),
            std::string::npos)
      << run.err;
  run = eval("scenes/cornell_box.gltf --configs 'aside:direct=sideways'");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("'aside': direct mode must be one of"), std::string::npos) << run.err;
  run = eval(
      "scenes/cornell_box.gltf --width 16 --height 12 --spp 1 --warmup 1 --frames 1 "
      "--configs 'coarse:direct=shadow-field,shadow.texels=2'");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_NE(run.err.find("texels"), std::string::npos) << run.err;
}

// The sweep's frame axes (issue 14: direct modes, shadow field resolutions, frame size) on the
// Cornell box, lit by a point light: each is recorded in the JSON and changes the image the
// way it must. Measured on lavapipe beside the tolerances below.
TEST_F(ParetoCliTest, SweepsDirectModesShadowFieldAndFrameSize) {
  const CliRun run = eval(
      "scenes/cornell_box.gltf --width 48 --height 32 --spp 64 --warmup 16 --frames 1 "
      "--pt-max-spp 1 --pareto '" +
      (dir_ / "out").string() +
      "' --configs 'default:;unshadowed:direct=unshadowed;"
      "shadow field:direct=shadow-field,shadow.texels=8;half size:frame_downscale=2'");
  ASSERT_EQ(run.exit_code, 0) << run.out << run.err;
  const nlohmann::json doc = nlohmann::json::parse(slurp(dir_ / "out" / "cornell_box.json"));
  ASSERT_EQ(doc["configs"].size(), 4u);
  const nlohmann::json &shadowed = doc["configs"][0], &unshadowed = doc["configs"][1],
                       &field = doc["configs"][2], &half = doc["configs"][3];
  EXPECT_EQ(unshadowed["assignments"], nlohmann::json({"direct=unshadowed"}));
  EXPECT_EQ(field["assignments"], nlohmann::json({"shadow.texels=8", "direct=shadow-field"}));
  EXPECT_EQ(half["assignments"], nlohmann::json({"frame_downscale=2"}));
  auto full = [](const nlohmann::json& c, const char* score) {
    return c["full"][score].get<double>();
  };
  std::printf(
      "mean/ref, FLIP: default %.3f %.4f, unshadowed %.3f %.4f, shadow field %.3f %.4f, "
      "half size %.3f %.4f\n",
      full(shadowed, "mean_ratio"), full(shadowed, "flip"), full(unshadowed, "mean_ratio"),
      full(unshadowed, "flip"), full(field, "mean_ratio"), full(field, "flip"),
      full(half, "mean_ratio"), full(half, "flip"));
  // Not trivial: the default is close to the reference.
  EXPECT_NEAR(full(shadowed, "mean_ratio"), 1.0, 0.1);
  // Without shadows the light the boxes block arrives: a brighter, worse image (measured mean
  // 1.026 against 1.002, FLIP 0.131 against 0.095; with the frame's own direct light left
  // shadowed and only the probe-ray hits unshadowed, 1.014 and 0.113).
  EXPECT_GT(full(unshadowed, "mean_ratio"), full(shadowed, "mean_ratio") + 0.018);
  EXPECT_GT(full(unshadowed, "flip"), full(shadowed, "flip") + 0.025);
  // The shadow field approximates the traced shadows: about as much light, another image.
  EXPECT_NEAR(full(field, "mean_ratio"), full(shadowed, "mean_ratio"), 0.05);
  EXPECT_NE(full(field, "flip"), full(shadowed, "flip"));
  // Half the size each way, stretched: the same light on the surfaces (the indirect view's mean:
  // measured 1.012 against 1.004; the full frame's moves with how many pixel centres hit the
  // small bright lamp, 1.345 here), blurred edges (FLIP 0.164 against 0.095).
  EXPECT_NEAR(half["indirect"]["mean_ratio"].get<double>(),
              shadowed["indirect"]["mean_ratio"].get<double>(), 0.03);
  EXPECT_GT(full(half, "flip"), full(shadowed, "flip") + 0.02);
}

}  // namespace
}  // namespace ddgi::test
