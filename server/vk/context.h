// The Vulkan instance, one physical device, one queue: everything GPU work needs to start.
// Works headless (no surface, no window system) on lavapipe and on NVIDIA GPUs.
#pragma once

#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/result.h"
#include "vk/shader_statistics.h"

namespace ddgi::vk {

class CommandSlot;

// Where a test build may make a Vulkan call fail (Context::set_test_fault_hook): the queue
// submission and the fence wait every frame and update go through, and every memory allocation.
enum class FaultSite { kQueueSubmit, kFenceWait, kAllocateMemory };
// Returns the result the call at `site` reports instead of its own; VK_SUCCESS: no fault. Runs
// on whichever thread makes the call, holding no lock of the context's.
using FaultHook = std::function<VkResult(FaultSite site)>;

// How rays are traced: inline ray queries in compute shaders, or ray-tracing pipelines.
enum class TraceBackend { kRayQuery, kPipeline };
const char* backend_name(TraceBackend backend);
// Parses "query" / "pipeline"; "auto" returns nullopt (choose from the device).
Result<std::optional<TraceBackend>> parse_backend(const std::string& text);

struct DeviceCapabilities {
  std::string device_name;
  std::string driver_name;
  uint32_t vendor_id = 0;
  // VK_PHYSICAL_DEVICE_TYPE_CPU: a software implementation (lavapipe), where work that takes a
  // GPU a second takes a minute.
  bool cpu = false;
  uint32_t api_version = 0;
  bool acceleration_structure = false;
  bool ray_query = false;
  bool ray_tracing_pipeline = false;
  bool buffer_device_address = false;
  float timestamp_period_ns = 1.0f;
  bool timestamps = false;
  uint64_t device_local_bytes = 0;
  uint32_t min_scratch_alignment = 256;
  uint32_t shader_group_handle_size = 0;
  uint32_t shader_group_base_alignment = 0;
  uint32_t shader_group_handle_alignment = 0;
  uint32_t max_ray_recursion_depth = 0;
  uint32_t max_compute_workgroup_count_x = 65535;
  // VK_KHR_pipeline_executable_properties: the driver reports what it compiled (registers...).
  bool pipeline_executable_info = false;
};

// The pure part of device and backend selection, kept free of Vulkan calls so that unit tests
// can cover devices this machine does not have.
// Names what a device lacks to trace rays at all ("" when it can trace one way or another).
std::string missing_for_tracing(const DeviceCapabilities& caps);
// Errors when a device with `caps` cannot run `backend`, naming the missing extension.
Status backend_supported(const DeviceCapabilities& caps, TraceBackend backend);
// The backend a device with `caps` runs: `forced` when given (an error when the device lacks
// it), else ray queries when present, else ray-tracing pipelines. A device with neither is an
// error naming what is missing.
Result<TraceBackend> choose_backend(const DeviceCapabilities& caps,
                                    std::optional<TraceBackend> forced);

struct ContextOptions {
  bool validation = false;              // VK_LAYER_KHRONOS_validation; always on in tests
  std::string device_filter;            // substring of the device name; empty: best device
  std::optional<TraceBackend> backend;  // forced backend; nullopt: ray queries when present
  uint64_t memory_budget_bytes = 0;     // 0: no budget beyond the device's own limit
  // Keep what the driver reports of every pipeline it compiles (ddgi-bench --shader-stats),
  // where it has VK_KHR_pipeline_executable_properties; a diagnostic, off in the service.
  bool shader_statistics = false;
};

// Extension entry points that the loader does not export.
struct DeviceFunctions {
  PFN_vkCreateAccelerationStructureKHR vkCreateAccelerationStructureKHR = nullptr;
  PFN_vkDestroyAccelerationStructureKHR vkDestroyAccelerationStructureKHR = nullptr;
  PFN_vkGetAccelerationStructureBuildSizesKHR vkGetAccelerationStructureBuildSizesKHR = nullptr;
  PFN_vkCmdBuildAccelerationStructuresKHR vkCmdBuildAccelerationStructuresKHR = nullptr;
  PFN_vkGetAccelerationStructureDeviceAddressKHR vkGetAccelerationStructureDeviceAddressKHR =
      nullptr;
  PFN_vkCreateRayTracingPipelinesKHR vkCreateRayTracingPipelinesKHR = nullptr;
  PFN_vkGetPipelineExecutablePropertiesKHR vkGetPipelineExecutablePropertiesKHR = nullptr;
  PFN_vkGetPipelineExecutableStatisticsKHR vkGetPipelineExecutableStatisticsKHR = nullptr;
  PFN_vkGetRayTracingShaderGroupHandlesKHR vkGetRayTracingShaderGroupHandlesKHR = nullptr;
  PFN_vkCmdTraceRaysKHR vkCmdTraceRaysKHR = nullptr;
  PFN_vkSetDebugUtilsObjectNameEXT vkSetDebugUtilsObjectNameEXT = nullptr;
  PFN_vkCmdBeginDebugUtilsLabelEXT vkCmdBeginDebugUtilsLabelEXT = nullptr;
  PFN_vkCmdEndDebugUtilsLabelEXT vkCmdEndDebugUtilsLabelEXT = nullptr;
};

class Context {
 public:
  static Result<std::unique_ptr<Context>> create(const ContextOptions& options);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_device_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  uint32_t queue_family() const { return queue_family_; }
  const DeviceCapabilities& caps() const { return caps_; }
  const DeviceFunctions& fn() const { return fn_; }
  TraceBackend default_backend() const { return default_backend_; }
  // Errors when the device cannot run `backend`, naming the missing feature.
  Status check_backend(TraceBackend backend) const;

  // Debug names show up in validation messages and GPU debuggers.
  void set_name(uint64_t handle, VkObjectType type, const std::string& name) const;

  // Records `record` into a one-shot command buffer, submits it and waits for it. Only the
  // submission holds the queue lock: recording and waiting do not, so several threads (sessions)
  // may have work in flight at once.
  Status submit_and_wait(const std::function<void(VkCommandBuffer)>& record);
  // Submits recorded work (`info`: its command buffers, and any semaphores) that signals
  // `fence`, and returns at once. The queue lock covers this vkQueueSubmit only (the queue must
  // be externally synchronized). Returns the submission's serial, for wait().
  Result<uint64_t> submit(const VkSubmitInfo& info, VkFence fence);
  // Waits, holding no lock, for `fence`, the fence of submission `serial`; from then on the
  // submission counts as completed (deferred destruction). Every submission must be waited for.
  Status wait(uint64_t serial, VkFence fence);
  // The newest submission's serial, and whether submission `serial` (and every one before it)
  // has completed: waited for by whoever made it.
  uint64_t submitted_serial() const;
  bool completed(uint64_t serial) const { return completed_serial() >= serial; }

  // Device loss. The first VK_ERROR_DEVICE_LOST from a submission or a fence wait marks the
  // device lost for good: every later submit() fails at once with the same UNAVAILABLE error,
  // and `on_lost` (set once, by the server) runs on the thread that saw it. A lost device does
  // not come back; its owner ends what uses it and the process is restarted.
  bool device_lost() const { return device_lost_.load(); }
  void set_device_lost_handler(std::function<void(const Error& why)> on_lost);

  // Test-only fault injection: `hook` is asked before every call at a FaultSite (after the
  // real wait, at kFenceWait, so the injected result leaves no submission pending). An empty
  // hook turns injection off. Production code never sets one.
  void set_test_fault_hook(FaultHook hook);
  // The injected result for a call at `site` (VK_SUCCESS when none is injected).
  VkResult injected_fault(FaultSite site) const;

  // Deferred destruction: `destroy` runs once the GPU has finished every submission made
  // before this call. Objects can be dropped at any time without waiting for the GPU.
  void defer_destroy(std::function<void()> destroy);
  // Runs the deferred destructions whose submissions have completed.
  void collect_garbage();

  // Device memory accounting against the budget (RESOURCE_EXHAUSTED beyond it).
  Status reserve_memory(uint64_t bytes, const std::string& what);
  // Whether `bytes` more would fit the budget once `replaced_bytes` of what is allocated now are
  // freed: checked before an object frees its old resources to make new ones, so a refusal
  // leaves it as it was. The error names `what`, the bytes and what the budget leaves free.
  Status check_fits(uint64_t bytes, uint64_t replaced_bytes, const std::string& what) const;
  void release_memory(uint64_t bytes);
  uint64_t allocated_bytes() const { return allocated_bytes_.load(); }
  uint64_t memory_budget() const { return memory_budget_; }
  Result<uint32_t> find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags required,
                                    VkMemoryPropertyFlags preferred = 0) const;

  // Shader statistics (ContextOptions::shader_statistics): whether pipelines are created to
  // report them, keeping what the driver reports of `pipeline` (named `name`), and all kept.
  bool captures_shader_statistics() const { return shader_statistics_enabled_; }
  void keep_shader_statistics(VkPipeline pipeline, const std::string& name);
  std::vector<ShaderStatistic> shader_statistics() const;

  // Validation messages (warnings and errors) seen since creation; tests require zero.
  uint32_t validation_message_count() const { return validation_messages_.load(); }
  // INTERNAL naming the count when any validation message was reported (how tools and the
  // server end a run that drew one); OK otherwise.
  Status no_validation_messages() const;
  // True when the validation layer is on and its messages reach the counter above.
  bool validation_enabled() const { return validation_enabled_; }

 private:
  Context();
  // init() in the order it runs: each step fills the members the next ones read.
  Status init(const ContextOptions& options);
  Status create_instance(const std::vector<const char*>& layers, bool debug_utils, bool validation);
  // The first device (discrete GPUs first) that matches `device_filter` and can trace rays.
  Status pick_physical_device(const std::string& device_filter);
  // A compute queue family, the universal (graphics + compute) one when there is one.
  Status pick_queue_family();
  // The logical device with every tracing feature the device has, so either backend can run
  // (and the shader statistics, where shader_statistics_enabled_ asks).
  Status create_device();
  void load_device_functions(bool debug_utils);
  // A one-shot command slot for submit_and_wait (an idle one, or a new one), and its return.
  Result<std::unique_ptr<CommandSlot>> take_one_shot();
  void return_one_shot(std::unique_ptr<CommandSlot> slot);
  static VKAPI_ATTR VkBool32 VKAPI_CALL debug_callback(
      VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
      const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  DeviceCapabilities caps_;
  DeviceFunctions fn_;
  TraceBackend default_backend_ = TraceBackend::kRayQuery;
  bool validation_enabled_ = false;
  std::atomic<uint32_t> validation_messages_{0};
  bool shader_statistics_enabled_ = false;
  mutable std::mutex shader_statistics_mutex_;
  std::vector<ShaderStatistic> shader_statistics_;

  // Held for vkQueueSubmit only (and the serial it assigns, so serials follow queue order).
  std::mutex queue_mutex_;
  // Guards the serials: the newest submitted, and those submitted and not yet waited for. A
  // submission counts as completed once it and every one before it were waited for.
  mutable std::mutex serial_mutex_;
  uint64_t submitted_serial_ = 0;
  std::set<uint64_t> pending_serials_;
  uint64_t completed_serial() const;
  std::mutex one_shot_mutex_;
  std::vector<std::unique_ptr<CommandSlot>> idle_one_shots_;
  std::mutex garbage_mutex_;
  std::deque<std::pair<uint64_t, std::function<void()>>> garbage_;

  std::atomic<uint64_t> allocated_bytes_{0};
  uint64_t memory_budget_ = 0;

  // The error every submission after a device loss gets; records the loss once.
  Error lose_device(VkResult result, const char* call);
  std::atomic<bool> device_lost_{false};
  mutable std::mutex fault_mutex_;  // guards the two below
  std::function<void(const Error&)> on_device_lost_;
  std::optional<Error> device_lost_error_;
  FaultHook fault_hook_;
};

}  // namespace ddgi::vk
