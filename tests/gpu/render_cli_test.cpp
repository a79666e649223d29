// The ddgi-render executable, as a user runs it (the README's command without a server): the
// default scene to a PNG with GI, its per-pass table, and clear errors for bad input.
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "encode/png.h"
#include "tests/gpu/cli_run.h"

namespace ddgi::test {
namespace {

class RenderCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("ddgi-render-cli-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  CliRun render(const std::string& arguments) const {
    return run_cli(DDGI_RENDER_EXE, arguments, dir_);
  }

  std::filesystem::path dir_;
};

// The default scene (the Cornell box) with GI: a PNG of the asked size whose left wall is red,
// right wall green and middle lit, and the pass table on stdout.
TEST_F(RenderCliTest, RendersTheDefaultSceneToAPng) {
  const std::string png = (dir_ / "cornell.png").string();
  const CliRun run = render("--out '" + png + "' --width 64 --height 48 --warmup 8 --validation");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.out.find("field trace"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("indirect"), std::string::npos);
  EXPECT_NE(run.out.find("total"), std::string::npos);
  EXPECT_NE(run.out.find("Mrays/s"), std::string::npos);
  // Validation was on and said nothing.
  EXPECT_NE(run.err.find("validation on"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find("vulkan validation:"), std::string::npos) << run.err;

  const std::string bytes = slurp(png);
  auto image = encode::decode_png(
      std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
  ASSERT_TRUE(image.ok()) << image.error().message;
  ASSERT_EQ(image->width, 64u);
  ASSERT_EQ(image->height, 48u);
  // Mean RGB of a block of pixels (x0..x0+7, y 20..27).
  auto block = [&](uint32_t x0) {
    double sum[3] = {0, 0, 0};
    for (uint32_t y = 20; y < 28; ++y) {
      for (uint32_t x = x0; x < x0 + 8; ++x) {
        for (int c = 0; c < 3; ++c) sum[c] += image->pixels[(size_t(y) * 64 + x) * 4 + c];
      }
    }
    return std::array<double, 3>{sum[0] / 64, sum[1] / 64, sum[2] / 64};
  };
  const auto left = block(6), middle = block(28), right = block(52);
  EXPECT_GT(left[0], 1.5 * left[1]) << "left wall not red";
  EXPECT_GT(right[1], 1.5 * right[0]) << "right wall not green";
  EXPECT_GT(middle[0] + middle[1] + middle[2], 3 * 40.0) << "back wall dark";
}

// --field track_camera=true places the field around the camera before the warm-up: a 4x4x4
// field 0.3 m apart set far outside the Cornell box (origin 5,5,5) draws the indirect light of
// a camera inside the box (the volume moved there); left where it was set, its probes see only
// the black outside and the indirect view stays black. Measured on lavapipe: mean level 125.4
// of 255 tracking; planted (no track before the warm-up): 0.0.
TEST_F(RenderCliTest, TrackingFieldIsPlacedAroundTheCamera) {
  const std::string png = (dir_ / "tracked.png").string();
  const CliRun run =
      render("--out '" + png +
             "' --width 48 --height 36 --warmup 16 --view indirect --camera 0,1,0.6,0,1,-1,60 "
             "--field counts=4,4,4 --field spacing=0.3,0.3,0.3 --field origin=5,5,5 "
             "--field track_camera=true --field rays_per_probe=64");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string bytes = slurp(png);
  auto image = encode::decode_png(
      std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
  ASSERT_TRUE(image.ok()) << image.error().message;
  double sum = 0.0;
  for (size_t i = 0; i < image->pixels.size(); i += 4) {
    sum += (image->pixels[i] + image->pixels[i + 1] + image->pixels[i + 2]) / 3.0;
  }
  const double mean = sum / double(image->pixels.size() / 4);
  std::printf("indirect view of the tracked field: mean level %.1f of 255\n", mean);
  EXPECT_GT(mean, 10.0);
}

// The per-pass table's values, by row name (summed where a name repeats), and the number after
// `prefix` on its own line ("field update: 1.234 ms ...").
std::map<std::string, double> pass_rows(const std::string& out) {
  std::map<std::string, double> rows;
  std::istringstream lines(out);
  std::string line;
  while (std::getline(lines, line)) {
    const size_t last_space = line.find_last_of(' ');
    if (last_space == std::string::npos || line.find(':') != std::string::npos) continue;
    std::string name = line.substr(0, last_space);
    name.erase(name.find_last_not_of(' ') + 1);
    char* end = nullptr;
    const double value = std::strtod(line.c_str() + last_space + 1, &end);
    if (end && *end == '\0' && !name.empty()) rows[name] += value;
  }
  return rows;
}

double value_after(const std::string& out, const std::string& prefix) {
  const size_t at = out.find(prefix);
  return at == std::string::npos ? -1.0 : std::strtod(out.c_str() + at + prefix.size(), nullptr);
}

// With a shadow field, its passes run first; the field update's time (and so its Mrays/s) must
// be the sum of the irradiance field's own passes, not of the first rows of the table.
TEST_F(RenderCliTest, FieldUpdateTimeIsTheSumOfTheFieldPassesOnly) {
  const CliRun run = render("--out '" + (dir_ / "x.png").string() +
                            "' --width 32 --height 24 --warmup 1 --direct shadow-field "
                            "--field counts=3,3,3 --shadow-field counts=3,3,3");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::map<std::string, double> rows = pass_rows(run.out);
  for (const char* name :
       {"shadow trace", "field trace", "field hit light", "field blend", "primary"}) {
    ASSERT_TRUE(rows.count(name)) << name << " missing from\n" << run.out;
  }
  const double field_sum =
      rows.at("field trace") + rows.at("field hit light") + rows.at("field blend");
  const double shadow_sum = rows.at("shadow trace") + rows.at("shadow rays") +
                            rows.at("shadow blend") + rows.at("shadow borders");
  const double field_ms = value_after(run.out, "field update: ");
  const double shadow_ms = value_after(run.out, "shadow field update: ");
  // The table prints 3 decimals: the sums agree to rounding of four rows (0.002) and its own
  // (0.0005).
  EXPECT_NEAR(field_ms, field_sum, 0.004) << run.out;
  EXPECT_NEAR(shadow_ms, shadow_sum, 0.004) << run.out;
  // Control: the passes took measurable time, so a mix-up of the two would show.
  EXPECT_GT(shadow_sum, 0.01) << run.out;
  EXPECT_GT(field_sum, 0.01) << run.out;
}

// Bad input: the exit code is non-zero and the message names what is wrong.
TEST_F(RenderCliTest, BadInputNamesTheProblem) {
  const std::string out = "--out '" + (dir_ / "x.png").string() + "'";
  const CliRun zero = render(out + " --width 0");
  EXPECT_NE(zero.exit_code, 0);
  EXPECT_NE(zero.err.find("--width must be in [1, 16384] (got 0)"), std::string::npos) << zero.err;
  const CliRun missing = render("no_such_scene.gltf " + out);
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("no_such_scene.gltf: no such file"), std::string::npos) << missing.err;
  const CliRun unknown = render(out + " --bogus 1");
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_NE(unknown.err.find("unknown flag --bogus"), std::string::npos) << unknown.err;
  const CliRun field = render(out + " --field hysteresis=2");
  EXPECT_NE(field.exit_code, 0);
  EXPECT_NE(field.err.find("hysteresis must be in [0, 0.999]"), std::string::npos) << field.err;
  const CliRun format = render("--out '" + (dir_ / "x.bmp").string() + "'");
  EXPECT_NE(format.exit_code, 0);
  EXPECT_NE(format.err.find("bmp"), std::string::npos) << format.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "x.png"));
}

}  // namespace
}  // namespace ddgi::test
