#include "tests/gpu/gpu_test.h"

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

}  // namespace ddgi::test
