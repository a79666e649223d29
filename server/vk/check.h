// Two error paths for Vulkan calls (DESIGN.md): at run time a failed call becomes an Error
// value naming the call; VK_CHECK_FATAL is only for start-up paths with no caller to tell.
#pragma once

#include <vulkan/vulkan.h>

#include <string>

#include "core/result.h"

namespace ddgi::vk {

const char* result_name(VkResult result);

// Out-of-memory results become RESOURCE_EXHAUSTED, a lost device UNAVAILABLE, everything else
// INTERNAL.
Error vk_error(VkResult result, const std::string& what);

[[noreturn]] void fatal(const std::string& message);

}  // namespace ddgi::vk

#define VK_TRY(call)                                                                      \
  do {                                                                                    \
    VkResult vk_try_result_ = (call);                                                     \
    if (vk_try_result_ != VK_SUCCESS) return ::ddgi::vk::vk_error(vk_try_result_, #call); \
  } while (0)

// VK_TRY for a call that a test build may make fail (vk::FaultSite, Context::injected_fault):
// the injected result is reported as the call's own.
#define VK_TRY_AT(context, site, call)                                                    \
  do {                                                                                    \
    VkResult vk_try_result_ = (context).injected_fault(site);                             \
    if (vk_try_result_ == VK_SUCCESS) vk_try_result_ = (call);                            \
    if (vk_try_result_ != VK_SUCCESS) return ::ddgi::vk::vk_error(vk_try_result_, #call); \
  } while (0)

#define VK_CHECK_FATAL(call)                                                      \
  do {                                                                            \
    VkResult vk_check_result_ = (call);                                           \
    if (vk_check_result_ != VK_SUCCESS)                                           \
      ::ddgi::vk::fatal(std::string(#call) +                                      \
                        " failed: " + ::ddgi::vk::result_name(vk_check_result_)); \
  } while (0)
