// End-to-end checks of the ddgi-compare executable: exit codes, JSON fields, agreement with the
// library, and HDR handling. Skipped when the client is not built (DDGI_BUILD_CLIENT=OFF).
#include <sys/wait.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "encode/exr.h"
#include "encode/file_io.h"
#include "encode/png.h"
#include "encode/write_image.h"
#include "metrics/flip.h"
#include "metrics/pixel_error.h"
#include "test_images.h"

#ifdef DDGI_COMPARE_EXE
#include "compare_args.h"
#endif

namespace ddgi {
namespace {

#ifdef DDGI_COMPARE_EXE

struct CliRun {
  int exit_code = -1;
  std::string out;
  std::string err;
};

std::string slurp(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

CliRun run_compare(const test::TempDir& dir, const std::string& arguments) {
  const std::filesystem::path out = dir / "stdout.txt";
  const std::filesystem::path err = dir / "stderr.txt";
  const std::string command = std::string("'") + DDGI_COMPARE_EXE + "' " + arguments + " >'" +
                              out.string() + "' 2>'" + err.string() + "'";
  const int status = std::system(command.c_str());
  CliRun run;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = slurp(out);
  run.err = slurp(err);
  return run;
}

// An 8-bit test image and the [0,1] float values the tool will see for it.
struct EightBit {
  encode::ImageRgba8 image;
  test::TestImage values;
};

EightBit eight_bit(const test::TestImage& source) {
  EightBit out{{source.width, source.height, {}}, source};
  for (size_t i = 0; i < source.rgb.size(); ++i) {
    const uint8_t code = uint8_t(std::lround(source.rgb[i] * 255.0f));
    out.image.pixels.push_back(code);
    if (i % 3 == 2) out.image.pixels.push_back(255);
    out.values.rgb[i] = float(code) / 255.0f;
  }
  return out;
}

TEST(CompareCli, JsonAgreesWithTheLibrary) {
  const test::TempDir dir;
  const EightBit a = eight_bit(test::gradient_image(40, 30));
  const EightBit b = eight_bit(test::add_noise(test::gradient_image(40, 30), 0.1f));
  ASSERT_TRUE(encode::write_image((dir / "a.png").string(), a.image).ok());
  ASSERT_TRUE(encode::write_image((dir / "b.png").string(), b.image).ok());

  const CliRun run = run_compare(dir, (dir / "a.png").string() + " " + (dir / "b.png").string() +
                                          " --json --flip-map " + (dir / "map.png").string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json report = nlohmann::json::parse(run.out);
  EXPECT_EQ(report["width"], 40);
  EXPECT_EQ(report["height"], 30);
  EXPECT_EQ(report["identical"], false);
  EXPECT_NEAR(report["rmse"].get<double>(), *metrics::rmse(a.values.view(), b.values.view()), 1e-6);
  EXPECT_NEAR(report["psnr_db"].get<double>(), *metrics::psnr(a.values.view(), b.values.view()),
              1e-4);
  EXPECT_NEAR(report["flip_mean"].get<double>(),
              metrics::flip(a.values.view(), b.values.view())->mean, 1e-5);
  EXPECT_GT(report["ssim"].get<double>(), 0.0);
  EXPECT_LT(report["ssim"].get<double>(), 1.0);
  EXPECT_EQ(report["reference"]["hdr"], false);

  Result<encode::ImageRgba8> map =
      encode::decode_png(*encode::read_file((dir / "map.png").string()));
  ASSERT_TRUE(map.ok());
  EXPECT_EQ(map->width, 40u);
  EXPECT_EQ(map->height, 30u);
}

TEST(CompareCli, IdenticalImagesReportZeroErrorAndNullPsnr) {
  const test::TempDir dir;
  const EightBit a = eight_bit(test::gradient_image(16, 16));
  ASSERT_TRUE(encode::write_image((dir / "a.png").string(), a.image).ok());
  const CliRun run =
      run_compare(dir, (dir / "a.png").string() + " " + (dir / "a.png").string() + " --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json report = nlohmann::json::parse(run.out);
  EXPECT_TRUE(report["psnr_db"].is_null());
  EXPECT_EQ(report["identical"], true);
  EXPECT_EQ(report["rmse"], 0.0);
  EXPECT_EQ(report["ssim"], 1.0);
  EXPECT_EQ(report["flip_mean"], 0.0);
}

TEST(CompareCli, HdrInputIsExposedClippedAndEncoded) {
  // Linear 0.5 at +1 EV becomes exactly 1.0 (white, not clipped); at 0 EV it is sRGB 0.7354.
  // The one value of 8.0 clips either way: 1 of 768 values.
  const test::TempDir dir;
  encode::ImageRgbF hdr{16, 16, std::vector<float>(16 * 16 * 3, 0.5f)};
  hdr.rgb[0] = 8.0f;  // one clipped value of 768
  ASSERT_TRUE(encode::write_exr((dir / "hdr.exr").string(), hdr).ok());
  encode::ImageRgba8 white{16, 16, std::vector<uint8_t>(16 * 16 * 4, 255)};
  ASSERT_TRUE(encode::write_image((dir / "white.png").string(), white).ok());

  const CliRun exposed =
      run_compare(dir, (dir / "hdr.exr").string() + " " + (dir / "white.png").string() +
                           " --json --exposure 1");
  ASSERT_EQ(exposed.exit_code, 0) << exposed.err;
  const nlohmann::json report = nlohmann::json::parse(exposed.out);
  EXPECT_EQ(report["reference"]["hdr"], true);
  EXPECT_EQ(report["rmse"], 0.0);
  EXPECT_NEAR(report["reference"]["clipped_fraction"].get<double>(), 1.0 / 768.0, 1e-12);

  const CliRun plain =
      run_compare(dir, (dir / "hdr.exr").string() + " " + (dir / "white.png").string() + " --json");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const nlohmann::json unexposed = nlohmann::json::parse(plain.out);
  EXPECT_NEAR(unexposed["reference"]["clipped_fraction"].get<double>(), 1.0 / 768.0, 1e-12);
  // Every value but the clipped one differs by 1 - 0.7354 (sRGB of linear 0.5).
  EXPECT_NEAR(unexposed["rmse"].get<double>(), (1.0 - 0.735357) * std::sqrt(767.0 / 768.0), 1e-4);
}

TEST(CompareCli, ErrorsExitWithTwoAndSayWhy) {
  const test::TempDir dir;
  const EightBit a = eight_bit(test::gradient_image(16, 12));
  const EightBit b = eight_bit(test::gradient_image(12, 16));
  ASSERT_TRUE(encode::write_image((dir / "a.png").string(), a.image).ok());
  ASSERT_TRUE(encode::write_image((dir / "b.png").string(), b.image).ok());

  const CliRun missing =
      run_compare(dir, (dir / "a.png").string() + " " + (dir / "nope.png").string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("nope.png"), std::string::npos) << missing.err;

  const CliRun mismatch =
      run_compare(dir, (dir / "a.png").string() + " " + (dir / "b.png").string());
  EXPECT_EQ(mismatch.exit_code, 2);
  EXPECT_NE(mismatch.err.find("16x12"), std::string::npos) << mismatch.err;
  EXPECT_NE(mismatch.err.find("12x16"), std::string::npos) << mismatch.err;

  // Argument errors take the same exit path; the parser itself is tested in-process below.
  EXPECT_EQ(run_compare(dir, (dir / "a.png").string()).exit_code, 2);
  const CliRun bad_map = run_compare(
      dir, (dir / "a.png").string() + " " + (dir / "a.png").string() + " --flip-map out.bmp");
  EXPECT_EQ(bad_map.exit_code, 2);
  EXPECT_NE(bad_map.err.find("out.bmp"), std::string::npos) << bad_map.err;
}

TEST(CompareArgs, ParsesOptionsAndRejectsBadOnes) {
  using client::parse_compare_args;
  Result<client::CompareArgs> args = parse_compare_args(
      {"a.exr", "--ppd", "30.5", "b.png", "--json", "--exposure", "-1.5", "--flip-map", "m.png"});
  ASSERT_TRUE(args.ok()) << args.error().message;
  EXPECT_EQ(args->reference, "a.exr");
  EXPECT_EQ(args->test, "b.png");
  EXPECT_EQ(args->ppd, 30.5);
  EXPECT_EQ(args->exposure, -1.5);
  EXPECT_TRUE(args->json);
  EXPECT_EQ(args->flip_map, "m.png");

  const Result<client::CompareArgs> defaults = parse_compare_args({"a.png", "b.png"});
  ASSERT_TRUE(defaults.ok());
  EXPECT_EQ(defaults->ppd, 67.0);
  EXPECT_EQ(defaults->exposure, 0.0);
  EXPECT_FALSE(defaults->json);
  EXPECT_FALSE(defaults->flip_map.has_value());

  EXPECT_TRUE(parse_compare_args({"--help"})->help);
  EXPECT_NE(client::compare_usage().find("--exposure"), std::string::npos);
  for (const std::vector<std::string>& bad :
       std::vector<std::vector<std::string>>{{"a.png"},
                                             {"a.png", "b.png", "c.png"},
                                             {"a.png", "b.png", "--ppd", "banana"},
                                             {"a.png", "b.png", "--ppd", "0"},
                                             {"a.png", "b.png", "--ppd", "2000"},
                                             {"a.png", "b.png", "--ppd"},
                                             {"a.png", "b.png", "--exposure", "1e999"},
                                             {"a.png", "b.png", "--frobnicate"}}) {
    EXPECT_FALSE(parse_compare_args(bad).ok()) << bad.back();
  }
}

#else

TEST(CompareCli, SkippedWithoutClient) {
  GTEST_SKIP() << "ddgi-compare is not built";
}

#endif

}  // namespace
}  // namespace ddgi
