// Which tracing backend a device gets, decided from its capabilities alone: automatic choice,
// forced backends the device lacks, and devices that cannot trace at all. No Vulkan device is
// needed, so devices unlike lavapipe (ray queries only, pipelines only, neither) are covered.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "vk/context.h"

namespace ddgi::vk {
namespace {

using ::testing::HasSubstr;

DeviceCapabilities device(bool ray_query, bool pipeline) {
  DeviceCapabilities caps;
  caps.device_name = "Test GPU";
  caps.buffer_device_address = true;
  caps.acceleration_structure = true;
  caps.ray_query = ray_query;
  caps.ray_tracing_pipeline = pipeline;
  return caps;
}

std::string error_of(const DeviceCapabilities& caps, std::optional<TraceBackend> forced) {
  const Result<TraceBackend> chosen = choose_backend(caps, forced);
  return chosen.ok() ? "" : chosen.error().message;
}

TEST(BackendChoice, AutoPrefersRayQueriesWhenPresent) {
  auto both = choose_backend(device(true, true), std::nullopt);
  ASSERT_TRUE(both.ok()) << both.error().message;
  EXPECT_EQ(*both, TraceBackend::kRayQuery);
  auto query_only = choose_backend(device(true, false), std::nullopt);
  ASSERT_TRUE(query_only.ok()) << query_only.error().message;
  EXPECT_EQ(*query_only, TraceBackend::kRayQuery);
}

TEST(BackendChoice, AutoFallsBackToPipelinesWithoutRayQueries) {
  auto chosen = choose_backend(device(false, true), std::nullopt);
  ASSERT_TRUE(chosen.ok()) << chosen.error().message;
  EXPECT_EQ(*chosen, TraceBackend::kPipeline);
}

TEST(BackendChoice, ForcedBackendIsKeptWhenPresent) {
  auto pipeline = choose_backend(device(true, true), TraceBackend::kPipeline);
  ASSERT_TRUE(pipeline.ok()) << pipeline.error().message;
  EXPECT_EQ(*pipeline, TraceBackend::kPipeline);
  auto query = choose_backend(device(true, true), TraceBackend::kRayQuery);
  ASSERT_TRUE(query.ok()) << query.error().message;
  EXPECT_EQ(*query, TraceBackend::kRayQuery);
}

TEST(BackendChoice, ForcingAnAbsentBackendNamesItAndTheAlternative) {
  const std::string no_query = error_of(device(false, true), TraceBackend::kRayQuery);
  EXPECT_THAT(no_query, HasSubstr("backend 'query' needs VK_KHR_ray_query"));
  EXPECT_THAT(no_query, HasSubstr("Test GPU does not support"));
  EXPECT_THAT(no_query, HasSubstr("use --backend pipeline"));

  const std::string no_pipeline = error_of(device(true, false), TraceBackend::kPipeline);
  EXPECT_THAT(no_pipeline, HasSubstr("backend 'pipeline' needs VK_KHR_ray_tracing_pipeline"));
  EXPECT_THAT(no_pipeline, HasSubstr("use --backend query"));

  // The same check serves Context::check_backend for kernels created later.
  EXPECT_TRUE(backend_supported(device(false, true), TraceBackend::kPipeline).ok());
  EXPECT_FALSE(backend_supported(device(false, true), TraceBackend::kRayQuery).ok());
}

TEST(BackendChoice, DeviceWithNeitherNamesBothExtensions) {
  for (std::optional<TraceBackend> forced :
       {std::optional<TraceBackend>{}, std::optional<TraceBackend>{TraceBackend::kRayQuery},
        std::optional<TraceBackend>{TraceBackend::kPipeline}}) {
    const std::string message = error_of(device(false, false), forced);
    EXPECT_THAT(message, HasSubstr("Test GPU cannot trace rays"));
    EXPECT_THAT(message, HasSubstr("VK_KHR_ray_query (rayQuery)"));
    EXPECT_THAT(message, HasSubstr("VK_KHR_ray_tracing_pipeline (rayTracingPipeline)"));
    // No advice to switch to a backend the device does not have either.
    EXPECT_THAT(message, ::testing::Not(HasSubstr("use --backend")));
  }
}

TEST(BackendChoice, MissingFoundationsAreNamedFirst) {
  DeviceCapabilities no_address = device(true, true);
  no_address.buffer_device_address = false;
  EXPECT_THAT(error_of(no_address, std::nullopt), HasSubstr("bufferDeviceAddress"));

  DeviceCapabilities no_structures = device(true, true);
  no_structures.acceleration_structure = false;
  EXPECT_THAT(error_of(no_structures, std::nullopt), HasSubstr("VK_KHR_acceleration_structure"));

  EXPECT_EQ(missing_for_tracing(device(true, false)), "");
  EXPECT_EQ(missing_for_tracing(device(false, true)), "");
}

}  // namespace
}  // namespace ddgi::vk
