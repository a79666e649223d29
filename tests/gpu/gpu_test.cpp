#include "tests/gpu/gpu_test.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

namespace ddgi::test {

vk::Context& gpu_context() {
  static std::unique_ptr<vk::Context> context = [] {
    vk::ContextOptions options;
    options.validation = true;
    auto created = vk::Context::create(options);
    if (!created.ok()) {
      std::fprintf(stderr, "cannot create a Vulkan context: %s\n", created.error().message.c_str());
      std::abort();
    }
    // The tests' "no validation messages" check means nothing unless messages are counted.
    if (!(*created)->validation_enabled()) {
      std::fprintf(stderr, "the test context was created without validation\n");
      std::abort();
    }
    return std::move(created).value();
  }();
  return *context;
}

ValueSpread value_spread(const std::vector<float>& values, size_t stride, size_t channels) {
  ValueSpread spread;
  double sum = 0.0;
  for (size_t i = 0; i + channels <= values.size(); i += stride) {
    for (size_t c = 0; c < channels; ++c) {
      const double v = values[i + c];
      spread.min = spread.count == 0 ? v : std::min(spread.min, v);
      spread.max = spread.count == 0 ? v : std::max(spread.max, v);
      sum += v;
      ++spread.count;
    }
  }
  spread.mean = spread.count > 0 ? sum / double(spread.count) : 0.0;
  return spread;
}

::testing::AssertionResult is_nontrivial(const std::vector<float>& values, double min_mean,
                                         double min_range, size_t stride, size_t channels) {
  const ValueSpread s = value_spread(values, stride, channels);
  const bool finite = std::isfinite(s.mean) && std::isfinite(s.min) && std::isfinite(s.max);
  if (s.count > 0 && finite && s.mean >= min_mean && s.max - s.min >= min_range) {
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure()
         << "trivial result: " << s.count << " values, mean " << s.mean << " (at least " << min_mean
         << " required), range " << s.min << " .. " << s.max << " = " << s.max - s.min
         << " (at least " << min_range << " required)";
}

}  // namespace ddgi::test
