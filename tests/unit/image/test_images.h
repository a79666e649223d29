// Deterministic synthetic images shared by the image tests.
#pragma once

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "metrics/image_view.h"

namespace ddgi::test {

// An owning RGB float image that hands out metric views.
struct TestImage {
  uint32_t width = 0;
  uint32_t height = 0;
  std::vector<float> rgb;

  metrics::RgbImageView view() const { return {width, height, rgb}; }
  float& at(uint32_t x, uint32_t y, uint32_t c) { return rgb[(size_t{y} * width + x) * 3 + c]; }
};

inline TestImage constant_image(uint32_t width, uint32_t height, float r, float g, float b) {
  TestImage image{width, height, {}};
  for (size_t i = 0; i < size_t{width} * height; ++i) image.rgb.insert(image.rgb.end(), {r, g, b});
  return image;
}

// Smooth colour gradient in [0.1, 0.9]: no features beyond the gentle ramps.
inline TestImage gradient_image(uint32_t width, uint32_t height) {
  TestImage image = constant_image(width, height, 0.0f, 0.0f, 0.0f);
  for (uint32_t y = 0; y < height; ++y) {
    for (uint32_t x = 0; x < width; ++x) {
      image.at(x, y, 0) = 0.1f + 0.8f * float(x) / float(width - 1);
      image.at(x, y, 1) = 0.1f + 0.8f * float(y) / float(height - 1);
      image.at(x, y, 2) = 0.5f;
    }
  }
  return image;
}

// Fixed pseudo-random numbers in [-1, 1] (a 32-bit LCG), the same on every platform.
inline std::vector<float> noise_pattern(size_t count, uint32_t seed = 12345) {
  std::vector<float> out(count);
  uint32_t state = seed;
  for (float& value : out) {
    state = state * 1664525u + 1013904223u;
    value = float(state >> 8) / float(1u << 23) - 1.0f;
  }
  return out;
}

// base + amplitude * noise, clamped to [0,1].
inline TestImage add_noise(const TestImage& base, float amplitude, uint32_t seed = 12345) {
  TestImage out = base;
  const std::vector<float> noise = noise_pattern(out.rgb.size(), seed);
  for (size_t i = 0; i < out.rgb.size(); ++i) {
    out.rgb[i] = std::min(1.0f, std::max(0.0f, out.rgb[i] + amplitude * noise[i]));
  }
  return out;
}

// A fresh directory per test (named after it and the process, so parallel ctest runs never
// share files), removed again when the test ends.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            ("ddgi_image_tests_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
             std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

}  // namespace ddgi::test
