// Descriptor sets and kernels. A Kernel is one GPU pass: a compute shader, or, for a tracing
// kernel on the pipeline backend, a ray-tracing pipeline built from the kernel's ray-generation
// shader plus the shared hit/miss shaders. Both forms take the same descriptor sets and push
// constants, so pass code does not care which backend runs.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "vk/context.h"
#include "vk/resources.h"

namespace ddgi::vk {

// Stages that may read a binding: compute and every ray-tracing stage.
constexpr VkShaderStageFlags kAllKernelStages =
    VK_SHADER_STAGE_COMPUTE_BIT | VK_SHADER_STAGE_RAYGEN_BIT_KHR |
    VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR | VK_SHADER_STAGE_ANY_HIT_BIT_KHR |
    VK_SHADER_STAGE_MISS_BIT_KHR;

struct Binding {
  uint32_t binding = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  uint32_t count = 1;  // > 1: an array; the last binding may be variable-sized (see below)
  bool variable_count = false;
};

// A descriptor set layout plus one pool that allocates sets of it.
class DescriptorLayout {
 public:
  DescriptorLayout() = default;
  static Result<DescriptorLayout> create(Context& context, std::vector<Binding> bindings,
                                         uint32_t max_sets, const std::string& name);
  ~DescriptorLayout() { reset(); }
  DescriptorLayout(DescriptorLayout&& other) noexcept { *this = std::move(other); }
  DescriptorLayout& operator=(DescriptorLayout&& other) noexcept;
  DescriptorLayout(const DescriptorLayout&) = delete;
  DescriptorLayout& operator=(const DescriptorLayout&) = delete;
  void reset();

  VkDescriptorSetLayout handle() const { return layout_; }
  // `variable_count`: elements of the variable-sized last binding (when it has one).
  Result<VkDescriptorSet> allocate(uint32_t variable_count = 0);

 private:
  Context* context_ = nullptr;
  VkDescriptorSetLayout layout_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  bool has_variable_ = false;
};

// Collects descriptor writes for one set, then applies them together.
class DescriptorWriter {
 public:
  explicit DescriptorWriter(VkDescriptorSet set) : set_(set) {}
  DescriptorWriter& buffer(uint32_t binding, const Buffer& buffer);
  DescriptorWriter& storage_image(uint32_t binding, const Image& image);
  DescriptorWriter& sampled_image(uint32_t binding, const Image& image, VkSampler sampler,
                                  uint32_t array_element = 0,
                                  VkImageLayout layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  DescriptorWriter& acceleration_structure(uint32_t binding, VkAccelerationStructureKHR as);
  void apply(VkDevice device);

 private:
  struct Pending {
    uint32_t binding;
    uint32_t element;
    VkDescriptorType type;
    size_t info_index;
  };
  VkDescriptorSet set_;
  std::vector<Pending> pending_;
  std::vector<VkDescriptorBufferInfo> buffers_;
  std::vector<VkDescriptorImageInfo> images_;
  std::vector<VkAccelerationStructureKHR> structures_;
};

// Where SPIR-V files are: $DDGI_SHADER_DIR, else spirv/ beside the executable, else the
// build tree the binary came from.
std::string shader_directory();
Result<std::vector<uint32_t>> load_spirv(const std::string& file_name);

struct KernelDesc {
  std::string name;     // shader base name: "<name>.comp.spv" or "<name>.query.comp.spv" ...
  bool traces = false;  // a tracing kernel, compiled for both backends
  std::vector<VkDescriptorSetLayout> set_layouts;
  uint32_t push_constant_bytes = 0;
  glm::uvec3 workgroup{8, 8, 1};  // compute local size (set through specialization constants)
};

// A one-invocation-per-item dispatch of `count` items, folded into rows of `row_width` so
// that no dimension exceeds device limits (shaders/common/dispatch.glsl unfolds it).
struct LinearDispatch {
  uint32_t row_width = 0;
  glm::uvec3 size{0, 1, 1};
};
LinearDispatch linear_dispatch(uint32_t count);

class Kernel {
 public:
  Kernel() = default;
  // `backend` matters only for tracing kernels.
  static Result<Kernel> create(Context& context, const KernelDesc& desc, TraceBackend backend);
  ~Kernel() { reset(); }
  Kernel(Kernel&& other) noexcept { *this = std::move(other); }
  Kernel& operator=(Kernel&& other) noexcept;
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;
  void reset();

  // Runs one invocation per element of `size` (threads, or rays on the pipeline backend).
  void dispatch(VkCommandBuffer cmd, std::span<const VkDescriptorSet> sets,
                const void* push_constants, glm::uvec3 size) const;
  const std::string& name() const { return name_; }
  // Created (not default-constructed or reset).
  bool valid() const { return pipeline_ != VK_NULL_HANDLE; }

 private:
  Status create_compute(const KernelDesc& desc, const std::string& spirv_file);
  Status create_ray_tracing(const KernelDesc& desc);

  Context* context_ = nullptr;
  std::string name_;
  bool ray_tracing_ = false;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
  uint32_t push_constant_bytes_ = 0;
  glm::uvec3 workgroup_{8, 8, 1};
  Buffer sbt_;
  VkStridedDeviceAddressRegionKHR raygen_region_{};
  VkStridedDeviceAddressRegionKHR miss_region_{};
  VkStridedDeviceAddressRegionKHR hit_region_{};
  VkStridedDeviceAddressRegionKHR callable_region_{};
};

}  // namespace ddgi::vk
