#include "vk/context.h"

#include <algorithm>
#include <cstring>
#include <vector>

#include "core/log.h"
#include "vk/check.h"
#include "vk/command_slot.h"
#include "vk/gpu_share.h"

namespace ddgi::vk {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

bool has_extension(const std::vector<VkExtensionProperties>& list, const char* name) {
  return std::any_of(list.begin(), list.end(), [&](const VkExtensionProperties& e) {
    return std::strcmp(e.extensionName, name) == 0;
  });
}

std::vector<VkExtensionProperties> device_extensions(VkPhysicalDevice device) {
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> list(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, list.data());
  return list;
}

// Reads the ray-tracing related features and properties of one device.
DeviceCapabilities query_capabilities(VkPhysicalDevice device) {
  DeviceCapabilities caps;
  const auto extensions = device_extensions(device);

  VkPhysicalDeviceRayTracingPipelineFeaturesKHR rt_features{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR};
  VkPhysicalDeviceRayQueryFeaturesKHR rq_features{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as_features{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  VkPhysicalDeviceVulkan12Features features12{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR executable_features{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
  VkPhysicalDeviceFeatures2 features2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  void** chain = &features2.pNext;
  auto link = [&chain](auto* s) {
    *chain = s;
    chain = &s->pNext;
  };
  link(&features12);
  const bool has_as = has_extension(extensions, VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME) &&
                      has_extension(extensions, VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME);
  const bool has_rq = has_extension(extensions, VK_KHR_RAY_QUERY_EXTENSION_NAME);
  const bool has_rt = has_extension(extensions, VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME);
  if (has_as) link(&as_features);
  if (has_rq) link(&rq_features);
  if (has_rt) link(&rt_features);
  const bool has_executables =
      has_extension(extensions, VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
  if (has_executables) link(&executable_features);
  vkGetPhysicalDeviceFeatures2(device, &features2);
  caps.pipeline_executable_info = has_executables && executable_features.pipelineExecutableInfo;

  VkPhysicalDeviceRayTracingPipelinePropertiesKHR rt_props{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_PROPERTIES_KHR};
  VkPhysicalDeviceAccelerationStructurePropertiesKHR as_props{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR};
  VkPhysicalDeviceDriverProperties driver_props{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props2.pNext = &driver_props;
  if (has_as) {
    as_props.pNext = props2.pNext;
    props2.pNext = &as_props;
  }
  if (has_rt) {
    rt_props.pNext = props2.pNext;
    props2.pNext = &rt_props;
  }
  vkGetPhysicalDeviceProperties2(device, &props2);

  caps.device_name = props2.properties.deviceName;
  caps.driver_name = std::string(driver_props.driverName) + " " + driver_props.driverInfo;
  caps.vendor_id = props2.properties.vendorID;
  caps.cpu = props2.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
  caps.api_version = props2.properties.apiVersion;
  caps.buffer_device_address = features12.bufferDeviceAddress == VK_TRUE;
  caps.acceleration_structure = has_as && as_features.accelerationStructure == VK_TRUE;
  caps.ray_query = caps.acceleration_structure && has_rq && rq_features.rayQuery == VK_TRUE;
  caps.ray_tracing_pipeline =
      caps.acceleration_structure && has_rt && rt_features.rayTracingPipeline == VK_TRUE;
  caps.timestamp_period_ns = props2.properties.limits.timestampPeriod;
  caps.timestamps = props2.properties.limits.timestampComputeAndGraphics == VK_TRUE;
  caps.max_compute_workgroup_count_x = props2.properties.limits.maxComputeWorkGroupCount[0];
  if (has_as) {
    caps.min_scratch_alignment =
        std::max<uint32_t>(1, as_props.minAccelerationStructureScratchOffsetAlignment);
  }
  if (has_rt) {
    caps.shader_group_handle_size = rt_props.shaderGroupHandleSize;
    caps.shader_group_base_alignment = rt_props.shaderGroupBaseAlignment;
    caps.shader_group_handle_alignment = rt_props.shaderGroupHandleAlignment;
    caps.max_ray_recursion_depth = rt_props.maxRayRecursionDepth;
  }
  VkPhysicalDeviceMemoryProperties memory{};
  vkGetPhysicalDeviceMemoryProperties(device, &memory);
  for (uint32_t i = 0; i < memory.memoryHeapCount; ++i) {
    if (memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) {
      caps.device_local_bytes = std::max(caps.device_local_bytes, memory.memoryHeaps[i].size);
    }
  }
  return caps;
}

// The instance layers to enable: the validation layer when asked for (an error when absent).
Result<std::vector<const char*>> instance_layers(bool validation) {
  if (!validation) return std::vector<const char*>{};
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  const bool present = std::any_of(layers.begin(), layers.end(), [](const VkLayerProperties& l) {
    return std::strcmp(l.layerName, kValidationLayer) == 0;
  });
  if (!present) {
    return failed_precondition(
        "validation requested but VK_LAYER_KHRONOS_validation is not installed "
        "(Debian package vulkan-validationlayers)");
  }
  return std::vector<const char*>{kValidationLayer};
}

std::vector<VkExtensionProperties> instance_extensions(const char* layer) {
  uint32_t count = 0;
  vkEnumerateInstanceExtensionProperties(layer, &count, nullptr);
  std::vector<VkExtensionProperties> list(count);
  vkEnumerateInstanceExtensionProperties(layer, &count, list.data());
  return list;
}

// Whether VK_EXT_debug_utils can be enabled; with validation on it must be, or the layer's
// findings would reach no counter and a "no validation messages" check would pass whatever
// happens.
Result<bool> debug_utils_available(bool validation) {
  bool available = has_extension(instance_extensions(nullptr), VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  if (validation && !available) {
    // The validation layer may be the one providing the extension.
    available =
        has_extension(instance_extensions(kValidationLayer), VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  }
  if (validation && !available) {
    return failed_precondition(
        "validation requested but VK_EXT_debug_utils is not available, so validation messages "
        "could not be counted");
  }
  return available;
}

// Discrete GPUs first, then integrated ones, then the rest (lavapipe), each in the driver's order.
void sort_by_device_type(std::vector<VkPhysicalDevice>& devices) {
  std::stable_sort(devices.begin(), devices.end(), [](VkPhysicalDevice a, VkPhysicalDevice b) {
    VkPhysicalDeviceProperties pa, pb;
    vkGetPhysicalDeviceProperties(a, &pa);
    vkGetPhysicalDeviceProperties(b, &pb);
    auto rank = [](VkPhysicalDeviceType t) {
      return t == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU     ? 0
             : t == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU ? 1
                                                           : 2;
    };
    return rank(pa.deviceType) < rank(pb.deviceType);
  });
}

}  // namespace

std::string missing_for_tracing(const DeviceCapabilities& caps) {
  if (!caps.buffer_device_address) return "bufferDeviceAddress (Vulkan 1.2)";
  if (!caps.acceleration_structure)
    return "VK_KHR_acceleration_structure (accelerationStructure feature)";
  if (!caps.ray_query && !caps.ray_tracing_pipeline)
    return "both VK_KHR_ray_query (rayQuery) and VK_KHR_ray_tracing_pipeline "
           "(rayTracingPipeline)";
  return "";
}

Status backend_supported(const DeviceCapabilities& caps, TraceBackend backend) {
  if (backend == TraceBackend::kRayQuery && !caps.ray_query) {
    return failed_precondition("backend 'query' needs VK_KHR_ray_query, which " + caps.device_name +
                               " does not support; use --backend pipeline");
  }
  if (backend == TraceBackend::kPipeline && !caps.ray_tracing_pipeline) {
    return failed_precondition("backend 'pipeline' needs VK_KHR_ray_tracing_pipeline, which " +
                               caps.device_name + " does not support; use --backend query");
  }
  return ok_status();
}

Result<TraceBackend> choose_backend(const DeviceCapabilities& caps,
                                    std::optional<TraceBackend> forced) {
  // A device that cannot trace at all gets the one message that names everything it lacks,
  // not advice to switch to another backend it does not have either.
  const std::string missing = missing_for_tracing(caps);
  if (!missing.empty()) {
    return failed_precondition(caps.device_name + " cannot trace rays: it lacks " + missing);
  }
  if (forced) {
    DDGI_TRY(backend_supported(caps, *forced));
    return *forced;
  }
  return caps.ray_query ? TraceBackend::kRayQuery : TraceBackend::kPipeline;
}

const char* backend_name(TraceBackend backend) {
  return backend == TraceBackend::kRayQuery ? "query" : "pipeline";
}

Result<std::optional<TraceBackend>> parse_backend(const std::string& text) {
  if (text == "auto") return std::optional<TraceBackend>{};
  if (text == "query") return std::optional<TraceBackend>{TraceBackend::kRayQuery};
  if (text == "pipeline") return std::optional<TraceBackend>{TraceBackend::kPipeline};
  return invalid_argument("backend must be one of auto, query, pipeline (got '" + text + "')");
}

Result<std::unique_ptr<Context>> Context::create(const ContextOptions& options) {
  std::unique_ptr<Context> context(new Context());
  DDGI_TRY(context->init(options));
  return context;
}

VKAPI_ATTR VkBool32 VKAPI_CALL Context::debug_callback(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT,
    const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* self = static_cast<Context*>(user);
  if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
    self->validation_messages_.fetch_add(1);
    LOG_ERROR << "vulkan validation: " << (data->pMessage ? data->pMessage : "(no message)");
  }
  return VK_FALSE;
}

Status Context::init(const ContextOptions& options) {
  DDGI_ASSIGN_OR_RETURN(const std::vector<const char*> layers, instance_layers(options.validation));
  DDGI_ASSIGN_OR_RETURN(const bool debug_utils, debug_utils_available(options.validation));
  DDGI_TRY(create_instance(layers, debug_utils, options.validation));
  DDGI_TRY(pick_physical_device(options.device_filter));
  DDGI_ASSIGN_OR_RETURN(default_backend_, choose_backend(caps_, options.backend));
  DDGI_TRY(pick_queue_family());
  shader_statistics_enabled_ = options.shader_statistics && caps_.pipeline_executable_info;
  if (options.shader_statistics && !shader_statistics_enabled_) {
    LOG_WARNING << caps_.device_name
                << " reports no shader statistics (no VK_KHR_pipeline_executable_properties)";
  }
  DDGI_TRY(create_device());
  load_device_functions(debug_utils);

  memory_budget_ = options.memory_budget_bytes;
  LOG_INFO << "vulkan device: " << caps_.device_name << " (" << caps_.driver_name << "), ray query "
           << (caps_.ray_query ? "yes" : "no") << ", ray-tracing pipeline "
           << (caps_.ray_tracing_pipeline ? "yes" : "no") << ", backend "
           << backend_name(default_backend_) << (validation_enabled_ ? ", validation on" : "");
  return ok_status();
}

Status Context::create_instance(const std::vector<const char*>& layers, bool debug_utils,
                                bool validation) {
  std::vector<const char*> extensions;
  if (debug_utils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "ddgi";
  app.applicationVersion = VK_MAKE_VERSION(0, 1, 0);
  app.pEngineName = "ddgi";
  app.apiVersion = VK_API_VERSION_1_2;

  VkDebugUtilsMessengerCreateInfoEXT messenger_info{
      VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger_info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                   VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger_info.messageType =
      VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
  messenger_info.pfnUserCallback = &Context::debug_callback;
  messenger_info.pUserData = this;

  VkInstanceCreateInfo instance_info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  instance_info.pApplicationInfo = &app;
  instance_info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  instance_info.ppEnabledLayerNames = layers.data();
  instance_info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  instance_info.ppEnabledExtensionNames = extensions.data();
  if (validation && debug_utils) instance_info.pNext = &messenger_info;
  VK_TRY(vkCreateInstance(&instance_info, nullptr, &instance_));

  if (validation && debug_utils) {
    auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    if (!create_messenger) {
      return failed_precondition(
          "validation requested but vkCreateDebugUtilsMessengerEXT is missing, so validation "
          "messages could not be counted");
    }
    VK_TRY(create_messenger(instance_, &messenger_info, nullptr, &messenger_));
  }
  // On only with a messenger that counts what the layer reports.
  validation_enabled_ = messenger_ != VK_NULL_HANDLE;
  return ok_status();
}

Status Context::pick_physical_device(const std::string& device_filter) {
  uint32_t device_count = 0;
  vkEnumeratePhysicalDevices(instance_, &device_count, nullptr);
  if (device_count == 0) {
    return unavailable(
        "no Vulkan device found (on a machine without a GPU install Mesa's lavapipe: "
        "mesa-vulkan-drivers from bookworm-backports)");
  }
  std::vector<VkPhysicalDevice> devices(device_count);
  vkEnumeratePhysicalDevices(instance_, &device_count, devices.data());
  sort_by_device_type(devices);
  std::string rejected;
  for (VkPhysicalDevice candidate : devices) {
    DeviceCapabilities caps = query_capabilities(candidate);
    if (!device_filter.empty() && caps.device_name.find(device_filter) == std::string::npos) {
      rejected += "\n  " + caps.device_name + ": does not match --device '" + device_filter + "'";
      continue;
    }
    const std::string missing = missing_for_tracing(caps);
    if (!missing.empty()) {
      rejected += "\n  " + caps.device_name + ": lacks " + missing;
      continue;
    }
    physical_device_ = candidate;
    caps_ = caps;
    return ok_status();
  }
  return failed_precondition("no Vulkan device can trace rays:" + rejected);
}

Status Context::pick_queue_family() {
  uint32_t family_count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device_, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_device_, &family_count, families.data());
  bool found_family = false;
  for (uint32_t i = 0; i < family_count; ++i) {
    if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      queue_family_ = i;
      found_family = true;
      if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) break;  // the universal queue
    }
  }
  if (!found_family) return failed_precondition(caps_.device_name + " has no compute queue");
  caps_.timestamps = caps_.timestamps && families[queue_family_].timestampValidBits > 0;
  return ok_status();
}

Status Context::create_device() {
  std::vector<const char*> extensions = {VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
                                         VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME};
  if (caps_.ray_query) extensions.push_back(VK_KHR_RAY_QUERY_EXTENSION_NAME);
  if (caps_.ray_tracing_pipeline) extensions.push_back(VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME);
  if (shader_statistics_enabled_) {
    extensions.push_back(VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME);
  }

  VkPhysicalDeviceRayTracingPipelineFeaturesKHR rt_features{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR};
  rt_features.rayTracingPipeline = VK_TRUE;
  VkPhysicalDeviceRayQueryFeaturesKHR rq_features{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  rq_features.rayQuery = VK_TRUE;
  VkPhysicalDeviceAccelerationStructureFeaturesKHR as_features{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  as_features.accelerationStructure = VK_TRUE;
  VkPhysicalDeviceVulkan12Features features12{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  features12.bufferDeviceAddress = VK_TRUE;
  features12.scalarBlockLayout = VK_TRUE;
  features12.descriptorIndexing = VK_TRUE;
  features12.runtimeDescriptorArray = VK_TRUE;
  features12.shaderSampledImageArrayNonUniformIndexing = VK_TRUE;
  features12.descriptorBindingPartiallyBound = VK_TRUE;
  features12.descriptorBindingVariableDescriptorCount = VK_TRUE;
  features12.hostQueryReset = VK_TRUE;
  features12.timelineSemaphore = VK_TRUE;  // core in 1.2; tests hold submissions back with it
  VkPhysicalDeviceFeatures2 features2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  features2.features.shaderInt64 = VK_TRUE;
  features2.pNext = &features12;
  features12.pNext = &as_features;
  void** tail = &as_features.pNext;
  if (caps_.ray_query) {
    *tail = &rq_features;
    tail = &rq_features.pNext;
  }
  if (caps_.ray_tracing_pipeline) {
    *tail = &rt_features;
    tail = &rt_features.pNext;
  }
  VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR executable_features{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
  executable_features.pipelineExecutableInfo = VK_TRUE;
  if (shader_statistics_enabled_) {
    *tail = &executable_features;
    tail = &executable_features.pNext;
  }

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue_info.queueFamilyIndex = queue_family_;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  device_info.pNext = &features2;
  device_info.queueCreateInfoCount = 1;
  device_info.pQueueCreateInfos = &queue_info;
  device_info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  device_info.ppEnabledExtensionNames = extensions.data();
  VK_TRY(vkCreateDevice(physical_device_, &device_info, nullptr, &device_));
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
  return ok_status();
}

void Context::load_device_functions(bool debug_utils) {
#define DDGI_LOAD_DEVICE_FN(name) \
  fn_.name = reinterpret_cast<PFN_##name>(vkGetDeviceProcAddr(device_, #name))
  DDGI_LOAD_DEVICE_FN(vkCreateAccelerationStructureKHR);
  DDGI_LOAD_DEVICE_FN(vkDestroyAccelerationStructureKHR);
  DDGI_LOAD_DEVICE_FN(vkGetAccelerationStructureBuildSizesKHR);
  DDGI_LOAD_DEVICE_FN(vkCmdBuildAccelerationStructuresKHR);
  DDGI_LOAD_DEVICE_FN(vkGetAccelerationStructureDeviceAddressKHR);
  if (caps_.ray_tracing_pipeline) {
    DDGI_LOAD_DEVICE_FN(vkCreateRayTracingPipelinesKHR);
    DDGI_LOAD_DEVICE_FN(vkGetRayTracingShaderGroupHandlesKHR);
    DDGI_LOAD_DEVICE_FN(vkCmdTraceRaysKHR);
  }
  if (shader_statistics_enabled_) {
    DDGI_LOAD_DEVICE_FN(vkGetPipelineExecutablePropertiesKHR);
    DDGI_LOAD_DEVICE_FN(vkGetPipelineExecutableStatisticsKHR);
  }
#undef DDGI_LOAD_DEVICE_FN
  if (debug_utils) {
    fn_.vkSetDebugUtilsObjectNameEXT = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
    fn_.vkCmdBeginDebugUtilsLabelEXT = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance_, "vkCmdBeginDebugUtilsLabelEXT"));
    fn_.vkCmdEndDebugUtilsLabelEXT = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(
        vkGetInstanceProcAddr(instance_, "vkCmdEndDebugUtilsLabelEXT"));
  }
}

Context::Context() = default;

Context::~Context() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    idle_one_shots_.clear();  // into the garbage below
    {
      std::lock_guard<std::mutex> lock(serial_mutex_);
      pending_serials_.clear();  // the device is idle: everything completed
    }
    collect_garbage();
    vkDestroyDevice(device_, nullptr);
  }
  if (messenger_) {
    auto destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy_messenger) destroy_messenger(instance_, messenger_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

Status Context::check_backend(TraceBackend backend) const {
  return backend_supported(caps_, backend);
}

void Context::set_name(uint64_t handle, VkObjectType type, const std::string& name) const {
  if (!fn_.vkSetDebugUtilsObjectNameEXT || handle == 0) return;
  VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name.c_str();
  fn_.vkSetDebugUtilsObjectNameEXT(device_, &info);
}

Result<std::unique_ptr<CommandSlot>> Context::take_one_shot() {
  {
    std::lock_guard<std::mutex> lock(one_shot_mutex_);
    if (!idle_one_shots_.empty()) {
      std::unique_ptr<CommandSlot> slot = std::move(idle_one_shots_.back());
      idle_one_shots_.pop_back();
      return slot;
    }
  }
  DDGI_ASSIGN_OR_RETURN(CommandSlot slot, CommandSlot::create(*this, "one-shot commands"));
  return std::make_unique<CommandSlot>(std::move(slot));
}

void Context::return_one_shot(std::unique_ptr<CommandSlot> slot) {
  std::lock_guard<std::mutex> lock(one_shot_mutex_);
  idle_one_shots_.push_back(std::move(slot));
}

Status Context::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) {
  DDGI_ASSIGN_OR_RETURN(std::unique_ptr<CommandSlot> slot, take_one_shot());
  DDGI_ASSIGN_OR_RETURN(VkCommandBuffer cmd, slot->begin());
  record(cmd);
  DDGI_TRY(slot->submit());
  DDGI_TRY(slot->wait());
  return_one_shot(std::move(slot));  // kept only after a clean run: a failed one is dropped
  return ok_status();
}

Result<uint64_t> Context::submit(const VkSubmitInfo& info, VkFence fence) {
  VkResult result = injected_fault(FaultSite::kQueueSubmit);
  {
    // One queue, used by one thread at a time; only vkQueueSubmit waits here.
    std::lock_guard<std::mutex> lock(queue_mutex_);
    if (device_lost_) return lose_device(VK_ERROR_DEVICE_LOST, "vkQueueSubmit");
    if (result == VK_SUCCESS) result = vkQueueSubmit(queue_, 1, &info, fence);
    if (result == VK_SUCCESS) {
      std::lock_guard<std::mutex> serials(serial_mutex_);
      const uint64_t serial = ++submitted_serial_;
      pending_serials_.insert(serial);
      gpu_share::submitted();
      return serial;
    }
  }
  if (result == VK_ERROR_DEVICE_LOST) return lose_device(result, "vkQueueSubmit");
  return vk_error(result, "vkQueueSubmit");
}

Status Context::wait(uint64_t serial, VkFence fence) {
  VkResult result = vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX);
  if (result == VK_SUCCESS) {
    std::lock_guard<std::mutex> lock(serial_mutex_);
    pending_serials_.erase(serial);
  }
  if (result == VK_SUCCESS) result = injected_fault(FaultSite::kFenceWait);
  if (result == VK_ERROR_DEVICE_LOST) return lose_device(result, "vkWaitForFences");
  if (result != VK_SUCCESS) return vk_error(result, "vkWaitForFences");
  gpu_share::waited();  // outside every lock: a throttled thread sleeps here
  return ok_status();
}

Error Context::lose_device(VkResult result, const char* call) {
  std::function<void(const Error&)> on_lost;
  Error error = unavailable("");
  {
    std::lock_guard<std::mutex> lock(fault_mutex_);
    if (device_lost_error_) return *device_lost_error_;
    device_lost_error_ = unavailable(std::string("the GPU device was lost (") + call + ": " +
                                     result_name(result) + "); the server must be restarted");
    device_lost_ = true;
    error = *device_lost_error_;
    on_lost = on_device_lost_;
  }
  if (on_lost) on_lost(error);
  return error;
}

void Context::set_device_lost_handler(std::function<void(const Error& why)> on_lost) {
  std::lock_guard<std::mutex> lock(fault_mutex_);
  on_device_lost_ = std::move(on_lost);
}

void Context::set_test_fault_hook(FaultHook hook) {
  std::lock_guard<std::mutex> lock(fault_mutex_);
  fault_hook_ = std::move(hook);
}

VkResult Context::injected_fault(FaultSite site) const {
  FaultHook hook;
  {
    std::lock_guard<std::mutex> lock(fault_mutex_);
    if (!fault_hook_) return VK_SUCCESS;
    hook = fault_hook_;
  }
  return hook(site);
}

uint64_t Context::submitted_serial() const {
  std::lock_guard<std::mutex> lock(serial_mutex_);
  return submitted_serial_;
}

uint64_t Context::completed_serial() const {
  std::lock_guard<std::mutex> lock(serial_mutex_);
  return pending_serials_.empty() ? submitted_serial_ : *pending_serials_.begin() - 1;
}

void Context::defer_destroy(std::function<void()> destroy) {
  uint64_t serial;
  {
    std::lock_guard<std::mutex> lock(serial_mutex_);
    serial = submitted_serial_;
  }
  std::lock_guard<std::mutex> lock(garbage_mutex_);
  garbage_.emplace_back(serial, std::move(destroy));
}

void Context::collect_garbage() {
  const uint64_t completed = completed_serial();
  std::deque<std::function<void()>> ready;
  {
    std::lock_guard<std::mutex> lock(garbage_mutex_);
    while (!garbage_.empty() && garbage_.front().first <= completed) {
      ready.push_back(std::move(garbage_.front().second));
      garbage_.pop_front();
    }
  }
  for (auto& destroy : ready) destroy();
}

Status Context::reserve_memory(uint64_t bytes, const std::string& what) {
  uint64_t current = allocated_bytes_.load();
  const uint64_t limit = memory_budget_ ? memory_budget_ : caps_.device_local_bytes;
  while (true) {
    if (limit && current + bytes > limit) {
      return resource_exhausted(what + " needs " + std::to_string(bytes) +
                                " bytes of GPU memory; " + std::to_string(current) + " of the " +
                                std::to_string(limit) + "-byte budget are in use");
    }
    if (allocated_bytes_.compare_exchange_weak(current, current + bytes)) return ok_status();
  }
}

Status Context::check_fits(uint64_t bytes, uint64_t replaced_bytes, const std::string& what) const {
  const uint64_t limit = memory_budget_ ? memory_budget_ : caps_.device_local_bytes;
  const uint64_t current = allocated_bytes_.load();
  const uint64_t others = current - std::min(current, replaced_bytes);
  if (!limit || others + bytes <= limit) return ok_status();
  return resource_exhausted(what + " needs " + std::to_string(bytes) + " bytes of GPU memory; " +
                            std::to_string(limit - std::min(limit, others)) + " bytes of the " +
                            std::to_string(limit) + "-byte budget are free");
}

void Context::release_memory(uint64_t bytes) {
  allocated_bytes_.fetch_sub(bytes);
}

Result<uint32_t> Context::find_memory_type(uint32_t type_bits, VkMemoryPropertyFlags required,
                                           VkMemoryPropertyFlags preferred) const {
  VkPhysicalDeviceMemoryProperties memory{};
  vkGetPhysicalDeviceMemoryProperties(physical_device_, &memory);
  for (int pass = 0; pass < 2; ++pass) {
    const VkMemoryPropertyFlags wanted = pass == 0 ? (required | preferred) : required;
    for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
      if ((type_bits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & wanted) == wanted) {
        return i;
      }
    }
  }
  return internal_error("no memory type with the required properties");
}

Status Context::no_validation_messages() const {
  const uint32_t messages = validation_message_count();
  if (messages == 0) return ok_status();
  return internal_error(std::to_string(messages) + " Vulkan validation messages (see above)");
}

}  // namespace ddgi::vk
