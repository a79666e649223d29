#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <numbers>

#include <gtest/gtest.h>

#include "metrics/color.h"
#include "metrics/colormap.h"
#include "metrics/flip.h"
#include "metrics/flip_csf.h"
#include "metrics/flip_features.h"
#include "test_images.h"

namespace ddgi::metrics {
namespace {

using test::constant_image;
using test::TestImage;

// Published CIELAB (D65) coordinates of the sRGB primaries and white, from any colour table;
// independent of our code, so they check the sRGB -> XYZ -> L*a*b* chain.
struct LabReference {
  Color3 linear_rgb;
  Color3 lab;
};
constexpr LabReference kLabReferences[] = {
    {{1.0, 1.0, 1.0}, {100.0, 0.0, 0.0}},
    {{1.0, 0.0, 0.0}, {53.2408, 80.0925, 67.2032}},
    {{0.0, 1.0, 0.0}, {87.7347, -86.1827, 83.1793}},
    {{0.0, 0.0, 1.0}, {32.2970, 79.1875, -107.8602}},
};

// The paper's colour-error re-mapping, written out again from the published Lab values above:
// cmax = HyAB(Hunt(green), Hunt(blue))^0.7, then linear to 0.95 at 0.4 cmax, linear beyond.
double expected_flat_error(double hyab_distance) {
  const auto hunt = [](const Color3& lab) {
    return Color3{lab.c0, lab.c1 * lab.c0 / 100.0, lab.c2 * lab.c0 / 100.0};
  };
  const Color3 green = hunt(kLabReferences[2].lab);
  const Color3 blue = hunt(kLabReferences[3].lab);
  const double cmax = std::pow(
      std::abs(green.c0 - blue.c0) + std::hypot(green.c1 - blue.c1, green.c2 - blue.c2), 0.7);
  const double d = std::pow(hyab_distance, 0.7);
  const double knee = 0.4 * cmax;
  return d < knee ? 0.95 * d / knee : 0.95 + 0.05 * (d - knee) / (cmax - knee);
}

TEST(FlipColor, SrgbPrimariesHaveTheirPublishedLabValues) {
  for (const LabReference& reference : kLabReferences) {
    const Color3 lab = xyz_to_lab(linear_rgb_to_xyz(reference.linear_rgb));
    EXPECT_NEAR(lab.c0, reference.lab.c0, 0.01);
    EXPECT_NEAR(lab.c1, reference.lab.c1, 0.01);
    EXPECT_NEAR(lab.c2, reference.lab.c2, 0.01);
  }
}

TEST(FlipColor, YcxczRoundTripsAndIsZeroChromaForGrey) {
  const Color3 xyz = linear_rgb_to_xyz({0.3, 0.6, 0.1});
  const Color3 back = ycxcz_to_xyz(xyz_to_ycxcz(xyz));
  EXPECT_NEAR(back.c0, xyz.c0, 1e-12);
  EXPECT_NEAR(back.c1, xyz.c1, 1e-12);
  EXPECT_NEAR(back.c2, xyz.c2, 1e-12);
  const Color3 grey = xyz_to_ycxcz(linear_rgb_to_xyz({0.2, 0.2, 0.2}));
  EXPECT_NEAR(grey.c1, 0.0, 1e-12);
  EXPECT_NEAR(grey.c2, 0.0, 1e-12);
  const Color3 rgb = xyz_to_linear_rgb(xyz);
  EXPECT_NEAR(rgb.c1, 0.6, 1e-12);
}

TEST(Flip, IdenticalImagesGiveExactlyZero) {
  const TestImage a = test::add_noise(test::gradient_image(40, 24), 0.3f);
  Result<FlipResult> result = flip(a.view(), a.view());
  ASSERT_TRUE(result.ok()) << result.error().message;
  EXPECT_EQ(result->mean, 0.0);
  for (float e : result->error_map) ASSERT_EQ(e, 0.0f);
}

TEST(Flip, BlackVersusWhiteMatchesTheAnalyticValue) {
  // Flat images: the CSF filters (normalised) leave them flat and the feature detectors see
  // nothing, so every pixel's error is the re-mapped colour error of HyAB(black, white) = 100
  // (L* 0 vs 100, no chroma): 100^0.7 = 25.1 is above the knee 0.4 * cmax = 16.5, giving
  // 0.95 + 0.05 * (25.1 - 16.5) / (41.3 - 16.5) = 0.9674. Not 1, because green vs blue is the
  // largest difference FLIP scales to.
  const TestImage black = constant_image(24, 20, 0.0f, 0.0f, 0.0f);
  const TestImage white = constant_image(24, 20, 1.0f, 1.0f, 1.0f);
  Result<FlipResult> result = flip(black.view(), white.view());
  ASSERT_TRUE(result.ok());
  const double expected = expected_flat_error(100.0);
  EXPECT_NEAR(expected, 0.9674, 1e-4);
  EXPECT_NEAR(result->mean, expected, 1e-4);
  for (float e : result->error_map) ASSERT_NEAR(e, expected, 1e-4);
}

TEST(Flip, MidGreyVersusBlackUsesTheLowerBranchOfTheRemap) {
  // sRGB 0.5 -> linear 0.2140 -> L* 53.389; 53.389^0.7 = 16.18 is just under the knee, so the
  // error is 0.95 * 16.18 / 16.51 = 0.9315.
  const TestImage black = constant_image(16, 16, 0.0f, 0.0f, 0.0f);
  const TestImage grey = constant_image(16, 16, 0.5f, 0.5f, 0.5f);
  const double lightness = 116.0 * std::cbrt(std::pow((0.5 + 0.055) / 1.055, 2.4)) - 16.0;
  EXPECT_NEAR(lightness, 53.389, 1e-3);
  const double expected = expected_flat_error(lightness);
  EXPECT_NEAR(expected, 0.9315, 1e-4);
  EXPECT_NEAR(flip(grey.view(), black.view())->mean, expected, 1e-4);
}

// One pixel's FLIP error recomposed from the public stages and the paper's formulas: colour =
// remap(HyAB(Hunt(Lab(clamp(RGB(CSF(YCxCz)))))) ), feature = (max(|d edge|, |d point|) / sqrt
// 2)^0.5, error = colour^(1 - feature). Also reports how far out of gamut the filtered reference
// got.
struct PixelBreakdown {
  double color = 0.0;
  double feature = 0.0;
  double error = 0.0;
  double most_out_of_gamut = 0.0;  // largest distance of a filtered linear RGB value outside [0,1]
};

PixelBreakdown recompose(const TestImage& reference, const TestImage& test, uint32_t x, uint32_t y,
                         double ppd) {
  const auto opponent = [](const TestImage& image) {
    std::array<Plane, 3> planes{Plane(image.width, image.height), Plane(image.width, image.height),
                                Plane(image.width, image.height)};
    for (size_t i = 0; i < planes[0].values.size(); ++i) {
      const Color3 ycxcz = xyz_to_ycxcz(
          linear_rgb_to_xyz({srgb_to_linear(image.rgb[i * 3]), srgb_to_linear(image.rgb[i * 3 + 1]),
                             srgb_to_linear(image.rgb[i * 3 + 2])}));
      planes[0].values[i] = ycxcz.c0;
      planes[1].values[i] = ycxcz.c1;
      planes[2].values[i] = ycxcz.c2;
    }
    return planes;
  };
  PixelBreakdown out;
  const auto filtered_lab = [&](const std::array<Plane, 3>& planes) {
    const Color3 ycxcz{csf_filter(planes[0], OpponentChannel::kAchromatic, ppd).at(x, y),
                       csf_filter(planes[1], OpponentChannel::kRedGreen, ppd).at(x, y),
                       csf_filter(planes[2], OpponentChannel::kBlueYellow, ppd).at(x, y)};
    Color3 rgb = xyz_to_linear_rgb(ycxcz_to_xyz(ycxcz));
    for (double* c : {&rgb.c0, &rgb.c1, &rgb.c2}) {
      out.most_out_of_gamut = std::max({out.most_out_of_gamut, -*c, *c - 1.0});
      *c = std::clamp(*c, 0.0, 1.0);
    }
    return hunt_adjust(xyz_to_lab(linear_rgb_to_xyz(rgb)));
  };
  const auto features = [&](const std::array<Plane, 3>& planes) {
    Plane luminance = planes[0];
    for (double& v : luminance.values) v = (v + 16.0) / 116.0;
    return detect_features(luminance, ppd);
  };
  const std::array<Plane, 3> ref_planes = opponent(reference);
  const std::array<Plane, 3> test_planes = opponent(test);
  const double out_of_gamut_test_only = out.most_out_of_gamut;
  out.color = expected_flat_error(hyab(filtered_lab(ref_planes), filtered_lab(test_planes)));
  out.most_out_of_gamut = std::max(out.most_out_of_gamut, out_of_gamut_test_only);
  const Features ref_features = features(ref_planes);
  const Features test_features = features(test_planes);
  const double edge = std::abs(ref_features.edges.at(x, y) - test_features.edges.at(x, y));
  const double point = std::abs(ref_features.points.at(x, y) - test_features.points.at(x, y));
  out.feature = std::sqrt(std::max(edge, point) / std::numbers::sqrt2);
  out.error = std::pow(out.color, 1.0 - out.feature);
  return out;
}

TEST(Flip, VanishingLineIsAmplifiedByTheFeatureTerm) {
  // A faint one-pixel line removed: the CSF blurs most of its colour difference away, but the
  // point detector sees it vanish, and the feature term raises the error well above the colour
  // term alone.
  TestImage with_line = constant_image(33, 33, 0.5f, 0.5f, 0.5f);
  for (uint32_t y = 0; y < 33; ++y) {
    for (uint32_t c = 0; c < 3; ++c) with_line.at(16, y, c) = 0.7f;
  }
  const TestImage without_line = constant_image(33, 33, 0.5f, 0.5f, 0.5f);
  const PixelBreakdown expected = recompose(with_line, without_line, 16, 16, 67.0);
  EXPECT_GT(expected.feature, 0.2);
  EXPECT_GT(expected.error, expected.color + 0.05);
  Result<FlipResult> result = flip(with_line.view(), without_line.view());
  ASSERT_TRUE(result.ok());
  EXPECT_NEAR(result->error_map[16 * 33 + 16], expected.error, 1e-5);
  // Beside the line the point detector answers with the opposite sign: check one pixel over too.
  EXPECT_NEAR(result->error_map[16 * 33 + 18],
              recompose(with_line, without_line, 18, 16, 67.0).error, 1e-5);
}

TEST(Flip, FilteredColoursAreClampedToTheDisplayGamut) {
  // A yellow line on blue: luminance is filtered narrowly and blue-yellow widely, so at the line
  // the filtered colour leaves the RGB cube and must be clamped before L*a*b*.
  TestImage line = constant_image(33, 33, 0.0f, 0.0f, 1.0f);
  for (uint32_t y = 0; y < 33; ++y) {
    line.at(16, y, 0) = 1.0f;
    line.at(16, y, 1) = 1.0f;
    line.at(16, y, 2) = 0.0f;
  }
  const TestImage plain = constant_image(33, 33, 0.0f, 0.0f, 1.0f);
  const PixelBreakdown expected = recompose(line, plain, 16, 16, 67.0);
  EXPECT_GT(expected.most_out_of_gamut, 0.05);
  EXPECT_NEAR(flip(line.view(), plain.view())->error_map[16 * 33 + 16], expected.error, 1e-5);
}

TEST(Flip, MapMatchesImageSizeAndStaysInUnitRange) {
  const TestImage a = test::gradient_image(33, 17);
  const TestImage b = test::add_noise(a, 0.5f);
  Result<FlipResult> result = flip(a.view(), b.view());
  ASSERT_TRUE(result.ok());
  EXPECT_EQ(result->width, 33u);
  EXPECT_EQ(result->height, 17u);
  ASSERT_EQ(result->error_map.size(), 33u * 17u);
  for (float e : result->error_map) {
    ASSERT_GE(e, 0.0f);
    ASSERT_LE(e, 1.0f);
  }
}

TEST(Flip, ErrorGrowsMonotonicallyWithNoiseAmplitude) {
  const TestImage base = test::gradient_image(48, 32);
  double previous = 0.0;
  for (float amplitude : {0.005f, 0.02f, 0.05f, 0.1f, 0.2f, 0.4f}) {
    const double mean = flip(base.view(), test::add_noise(base, amplitude).view())->mean;
    EXPECT_GT(mean, previous) << amplitude;
    previous = mean;
  }
}

TEST(Flip, IsSymmetric) {
  const TestImage a = test::gradient_image(30, 20);
  const TestImage b = test::add_noise(a, 0.2f);
  Result<FlipResult> ab = flip(a.view(), b.view());
  Result<FlipResult> ba = flip(b.view(), a.view());
  ASSERT_TRUE(ab.ok() && ba.ok());
  EXPECT_EQ(ab->error_map, ba->error_map);
}

TEST(Flip, DistantViewerSeesLessFineNoise) {
  // Same pixel noise, more pixels per degree: the CSF blurs more of it away.
  const TestImage base = constant_image(48, 48, 0.5f, 0.5f, 0.5f);
  const TestImage noisy = test::add_noise(base, 0.2f);
  double previous = 1.0;
  for (double ppd : {10.0, 30.0, 67.0, 150.0}) {
    const double mean = flip(base.view(), noisy.view(), {.pixels_per_degree = ppd})->mean;
    EXPECT_LT(mean, previous) << ppd;
    previous = mean;
  }
}

TEST(Flip, ErrorStaysLocalToTheChange) {
  // One pixel changed: beyond the widest filter reach (CSF 10 px, features 9 px at 67 ppd, so
  // 20 px counting both images' filters) nothing differs and the error is exactly 0.
  const TestImage a = constant_image(64, 64, 0.4f, 0.5f, 0.6f);
  TestImage b = a;
  for (uint32_t c = 0; c < 3; ++c) b.at(32, 32, c) = 1.0f;
  Result<FlipResult> result = flip(a.view(), b.view());
  ASSERT_TRUE(result.ok());
  EXPECT_GT(result->error_map[32 * 64 + 32], 0.1f);
  EXPECT_EQ(result->error_map[32 * 64 + 5], 0.0f);
  EXPECT_EQ(result->error_map[5 * 64 + 32], 0.0f);
  EXPECT_EQ(result->error_map[60 * 64 + 60], 0.0f);
  // And the peak is at the changed pixel.
  const auto peak = std::max_element(result->error_map.begin(), result->error_map.end());
  EXPECT_EQ(peak - result->error_map.begin(), 32 * 64 + 32);
}

TEST(Flip, RejectsMismatchedSizesAndBadPpd) {
  const TestImage a = constant_image(64, 48, 0.5f, 0.5f, 0.5f);
  const TestImage b = constant_image(32, 32, 0.5f, 0.5f, 0.5f);
  Result<FlipResult> mismatch = flip(a.view(), b.view());
  ASSERT_FALSE(mismatch.ok());
  EXPECT_NE(mismatch.error().message.find("64x48 vs 32x32"), std::string::npos);
  for (double ppd : {0.0, -1.0, 5000.0, std::nan("")}) {
    EXPECT_FALSE(flip(a.view(), a.view(), {.pixels_per_degree = ppd}).ok()) << ppd;
  }
}

TEST(Flip, PixelsPerDegreeOfThePaperSetup) {
  EXPECT_NEAR(pixels_per_degree(0.7, 3840.0, 0.7), 3840.0 * std::numbers::pi / 180.0, 1e-9);
  EXPECT_NEAR(pixels_per_degree(0.7, 3840.0, 0.7), 67.02, 0.01);
}

// Golden values from an independent implementation of LDR-FLIP (numpy, written from the paper's
// formulas and the choices in docs/metrics.md, sharing no code with server/metrics/), for three
// small image pairs built from integer codes / 256 (exact in float and double) by the same
// formulas here and in the script. The expectations of the tests above come partly from the
// library's own stages; these do not. Regenerate with
//   /usr/bin/python3 tests/data/flip/make_flip_golden.py
// Tolerance 1e-6. Measured: the means agree to 5e-10 (the printed digits), the pixels to 3e-8 (the
// map is stored as float); the two sides convolve in a different order (separable vs 2-D), which
// only moves rounding. Swapping the b1 of the achromatic and red-green CSFs moves the means by
// 1.2e-4 to 1.1e-3.
constexpr double kGoldenTolerance = 1e-6;

template <typename Code>
TestImage coded_image(uint32_t width, uint32_t height, Code code) {
  TestImage image = constant_image(width, height, 0.0f, 0.0f, 0.0f);
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      for (uint32_t c = 0; c < 3; ++c) image.at(x, y, c) = float(code(x, y, c)) / 256.0f;
    }
  }
  return image;
}

struct GoldenPixel {
  uint32_t x, y;
  double error;
};

void expect_golden(const TestImage& reference, const TestImage& test, double ppd, double mean,
                   std::initializer_list<GoldenPixel> pixels) {
  Result<FlipResult> result = flip(reference.view(), test.view(), {.pixels_per_degree = ppd});
  ASSERT_TRUE(result.ok()) << result.error().message;
  EXPECT_NEAR(result->mean, mean, kGoldenTolerance);
  for (const GoldenPixel& p : pixels) {
    EXPECT_NEAR(result->error_map[size_t{p.y} * reference.width + p.x], p.error, kGoldenTolerance)
        << "pixel " << p.x << "," << p.y;
  }
}

// A gradient and the same with a saturated orange square: colour and edge terms inside, at the
// square's corner and far from it.
TEST(FlipGolden, SquareOnAGradient) {
  const auto gradient = [](uint32_t x, uint32_t y, uint32_t c) {
    return std::array<uint32_t, 3>{16 + 8 * x, 16 + 10 * y, 128}[c];
  };
  const TestImage reference = coded_image(24, 18, gradient);
  const TestImage test = coded_image(24, 18, [&](uint32_t x, uint32_t y, uint32_t c) {
    const bool in_square = x >= 9 && x <= 14 && y >= 6 && y <= 11;
    return in_square ? std::array<uint32_t, 3>{240, 64, 32}[c] : gradient(x, y, c);
  });
  expect_golden(reference, test, 67.0, 0.138058533,
                {{11, 8, 0.841289069}, {9, 6, 0.631190432}, {4, 4, 0.029127380}});
}

// Reddish/greenish bars against yellowish/bluish bars, two pixels wide, at 20 ppd (small
// filters, so the chroma differences survive the CSF).
TEST(FlipGolden, ColouredBars) {
  const TestImage reference = coded_image(16, 12, [](uint32_t x, uint32_t, uint32_t c) {
    return (x / 2) % 2 == 0 ? std::array<uint32_t, 3>{160, 96, 96}[c]
                            : std::array<uint32_t, 3>{96, 160, 96}[c];
  });
  const TestImage test = coded_image(16, 12, [](uint32_t x, uint32_t, uint32_t c) {
    return (x / 2) % 2 == 0 ? std::array<uint32_t, 3>{160, 160, 96}[c]
                            : std::array<uint32_t, 3>{96, 96, 160}[c];
  });
  expect_golden(reference, test, 20.0, 0.836616545,
                {{0, 0, 0.785558524}, {5, 7, 0.748412861}, {15, 11, 0.957083914}});
}

// Integer-hash noise and a perturbed copy, each with one pixel outside [0,1] (clamped on input).
TEST(FlipGolden, NoiseWithOutOfRangePixels) {
  TestImage reference = coded_image(
      20, 16, [](uint32_t x, uint32_t y, uint32_t c) { return (x * 37 + y * 101 + c * 59) % 256; });
  TestImage test = coded_image(20, 16, [](uint32_t x, uint32_t y, uint32_t c) {
    return (x * 37 + y * 101 + c * 59 + 11 * ((x + 2 * y) % 5)) % 256;
  });
  reference.at(3, 4, 0) = 1.25f;
  reference.at(3, 4, 1) = -0.25f;
  reference.at(3, 4, 2) = 0.5f;
  test.at(15, 9, 0) = -0.5f;
  test.at(15, 9, 1) = 1.5f;
  test.at(15, 9, 2) = 2.0f;
  expect_golden(reference, test, 67.0, 0.337437402,
                {{3, 4, 0.227287255}, {15, 9, 0.349124339}, {10, 10, 0.333380311}});
}

TEST(ErrorColormap, LightnessRisesMonotonicallyFromDarkToBright) {
  double previous = -1.0;
  for (int i = 0; i <= 100; ++i) {
    const auto color = error_color(float(i) / 100.0f);
    const double luma = 0.2126 * color[0] + 0.7152 * color[1] + 0.0722 * color[2];
    EXPECT_GT(luma, previous) << i;
    previous = luma;
  }
  EXPECT_LT(0.2126 * error_color(0.0f)[0] + 0.7152 * error_color(0.0f)[1], 5.0);
  EXPECT_GT(error_color(1.0f)[1], 240);
  EXPECT_EQ(error_color(-3.0f), error_color(0.0f));
  EXPECT_EQ(error_color(7.0f), error_color(1.0f));
  EXPECT_EQ(error_color(std::nanf("")), error_color(0.0f));
  const float errors[] = {0.0f, 0.5f, 1.0f};
  const std::vector<uint8_t> pixels = colorize_errors(errors);
  ASSERT_EQ(pixels.size(), 12u);
  EXPECT_EQ(pixels[7], 255);
}

}  // namespace
}  // namespace ddgi::metrics
