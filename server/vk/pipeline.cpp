#include "vk/pipeline.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "vk/check.h"

#ifndef DDGI_BUILD_SHADER_DIR
#define DDGI_BUILD_SHADER_DIR ""
#endif

namespace ddgi::vk {
namespace {

VkDeviceSize align_up(VkDeviceSize value, VkDeviceSize alignment) {
  return (value + alignment - 1) / alignment * alignment;
}

Result<VkShaderModule> create_module(Context& context, const std::string& file_name) {
  DDGI_ASSIGN_OR_RETURN(std::vector<uint32_t> code, load_spirv(file_name));
  VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  info.codeSize = code.size() * sizeof(uint32_t);
  info.pCode = code.data();
  VkShaderModule module = VK_NULL_HANDLE;
  VK_TRY(vkCreateShaderModule(context.device(), &info, nullptr, &module));
  context.set_name(reinterpret_cast<uint64_t>(module), VK_OBJECT_TYPE_SHADER_MODULE, file_name);
  return module;
}

// The shared hit and miss shaders of every ray-tracing pipeline. Ray type 0 finds the closest
// hit; ray type 1 measures transmittance (shadow rays).
struct SharedStage {
  const char* file;
  VkShaderStageFlagBits stage;
};
constexpr std::array<SharedStage, 6> kSharedStages = {{
    {"closest.rmiss.spv", VK_SHADER_STAGE_MISS_BIT_KHR},
    {"shadow.rmiss.spv", VK_SHADER_STAGE_MISS_BIT_KHR},
    {"closest.rchit.spv", VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR},
    {"closest.rahit.spv", VK_SHADER_STAGE_ANY_HIT_BIT_KHR},
    {"shadow.rchit.spv", VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR},
    {"shadow.rahit.spv", VK_SHADER_STAGE_ANY_HIT_BIT_KHR},
}};

}  // namespace

// ---------------------------------------------------------------------------------------------
// Descriptors

Result<DescriptorLayout> DescriptorLayout::create(Context& context, std::vector<Binding> bindings,
                                                  uint32_t max_sets, const std::string& name) {
  DescriptorLayout result;
  result.context_ = &context;
  std::vector<VkDescriptorSetLayoutBinding> vk_bindings;
  std::vector<VkDescriptorBindingFlags> flags;
  std::vector<VkDescriptorPoolSize> pool_sizes;
  for (const Binding& b : bindings) {
    VkDescriptorSetLayoutBinding vk_binding{};
    vk_binding.binding = b.binding;
    vk_binding.descriptorType = b.type;
    vk_binding.descriptorCount = b.count;
    vk_binding.stageFlags = kAllKernelStages;
    vk_bindings.push_back(vk_binding);
    VkDescriptorBindingFlags binding_flags = 0;
    if (b.variable_count) {
      binding_flags = VK_DESCRIPTOR_BINDING_VARIABLE_DESCRIPTOR_COUNT_BIT |
                      VK_DESCRIPTOR_BINDING_PARTIALLY_BOUND_BIT;
      result.has_variable_ = true;
    }
    flags.push_back(binding_flags);
    pool_sizes.push_back({b.type, b.count * max_sets});
  }
  VkDescriptorSetLayoutBindingFlagsCreateInfo flags_info{
      VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_BINDING_FLAGS_CREATE_INFO};
  flags_info.bindingCount = static_cast<uint32_t>(flags.size());
  flags_info.pBindingFlags = flags.data();
  VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  info.pNext = &flags_info;
  info.bindingCount = static_cast<uint32_t>(vk_bindings.size());
  info.pBindings = vk_bindings.data();
  VK_TRY(vkCreateDescriptorSetLayout(context.device(), &info, nullptr, &result.layout_));
  context.set_name(reinterpret_cast<uint64_t>(result.layout_), VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT,
                   name);

  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.maxSets = max_sets;
  pool_info.poolSizeCount = static_cast<uint32_t>(pool_sizes.size());
  pool_info.pPoolSizes = pool_sizes.data();
  VK_TRY(vkCreateDescriptorPool(context.device(), &pool_info, nullptr, &result.pool_));
  context.set_name(reinterpret_cast<uint64_t>(result.pool_), VK_OBJECT_TYPE_DESCRIPTOR_POOL,
                   name + " pool");
  return result;
}

DescriptorLayout& DescriptorLayout::operator=(DescriptorLayout&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    layout_ = std::exchange(other.layout_, VK_NULL_HANDLE);
    pool_ = std::exchange(other.pool_, VK_NULL_HANDLE);
    has_variable_ = other.has_variable_;
  }
  return *this;
}

void DescriptorLayout::reset() {
  if (!context_) return;
  VkDevice device = context_->device();
  VkDescriptorSetLayout layout = layout_;
  VkDescriptorPool pool = pool_;
  context_->defer_destroy([device, layout, pool] {
    if (pool) vkDestroyDescriptorPool(device, pool, nullptr);
    if (layout) vkDestroyDescriptorSetLayout(device, layout, nullptr);
  });
  context_ = nullptr;
  layout_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
}

Result<VkDescriptorSet> DescriptorLayout::allocate(uint32_t variable_count) {
  VkDescriptorSetVariableDescriptorCountAllocateInfo variable{
      VK_STRUCTURE_TYPE_DESCRIPTOR_SET_VARIABLE_DESCRIPTOR_COUNT_ALLOCATE_INFO};
  variable.descriptorSetCount = 1;
  variable.pDescriptorCounts = &variable_count;
  VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  if (has_variable_) info.pNext = &variable;
  info.descriptorPool = pool_;
  info.descriptorSetCount = 1;
  info.pSetLayouts = &layout_;
  VkDescriptorSet set = VK_NULL_HANDLE;
  VK_TRY(vkAllocateDescriptorSets(context_->device(), &info, &set));
  return set;
}

DescriptorWriter& DescriptorWriter::buffer(uint32_t binding, const Buffer& buffer) {
  buffers_.push_back(buffer.descriptor());
  pending_.push_back({binding, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffers_.size() - 1});
  return *this;
}

DescriptorWriter& DescriptorWriter::storage_image(uint32_t binding, const Image& image) {
  images_.push_back({VK_NULL_HANDLE, image.view(), VK_IMAGE_LAYOUT_GENERAL});
  pending_.push_back({binding, 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, images_.size() - 1});
  return *this;
}

DescriptorWriter& DescriptorWriter::sampled_image(uint32_t binding, const Image& image,
                                                  VkSampler sampler, uint32_t array_element,
                                                  VkImageLayout layout) {
  images_.push_back({sampler, image.view(), layout});
  pending_.push_back(
      {binding, array_element, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, images_.size() - 1});
  return *this;
}

DescriptorWriter& DescriptorWriter::acceleration_structure(uint32_t binding,
                                                           VkAccelerationStructureKHR as) {
  structures_.push_back(as);
  pending_.push_back(
      {binding, 0, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, structures_.size() - 1});
  return *this;
}

void DescriptorWriter::apply(VkDevice device) {
  // Pointers into the vectors are taken only now, after they stopped growing.
  std::vector<VkWriteDescriptorSet> writes;
  std::vector<VkWriteDescriptorSetAccelerationStructureKHR> as_writes;
  as_writes.reserve(pending_.size());
  for (const Pending& p : pending_) {
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set_;
    write.dstBinding = p.binding;
    write.dstArrayElement = p.element;
    write.descriptorCount = 1;
    write.descriptorType = p.type;
    if (p.type == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER) {
      write.pBufferInfo = &buffers_[p.info_index];
    } else if (p.type == VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR) {
      VkWriteDescriptorSetAccelerationStructureKHR as{
          VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR};
      as.accelerationStructureCount = 1;
      as.pAccelerationStructures = &structures_[p.info_index];
      as_writes.push_back(as);
      write.pNext = &as_writes.back();
    } else {
      write.pImageInfo = &images_[p.info_index];
    }
    writes.push_back(write);
  }
  vkUpdateDescriptorSets(device, static_cast<uint32_t>(writes.size()), writes.data(), 0, nullptr);
  pending_.clear();
}

// ---------------------------------------------------------------------------------------------
// Shaders

std::string shader_directory() {
  if (const char* env = std::getenv("DDGI_SHADER_DIR"); env && *env) return env;
  std::error_code ec;
  const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const auto beside = exe.parent_path() / "spirv";
    if (std::filesystem::is_directory(beside, ec)) return beside.string();
  }
  return DDGI_BUILD_SHADER_DIR;
}

Result<std::vector<uint32_t>> load_spirv(const std::string& file_name) {
  const std::string path = shader_directory() + "/" + file_name;
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) {
    return not_found("shader '" + path +
                     "' not found (set DDGI_SHADER_DIR to the folder of the .spv files)");
  }
  const std::streamsize size = file.tellg();
  if (size <= 0 || size % 4 != 0) return internal_error("shader '" + path + "' is not SPIR-V");
  std::vector<uint32_t> code(static_cast<size_t>(size) / 4);
  file.seekg(0);
  file.read(reinterpret_cast<char*>(code.data()), size);
  if (code[0] != 0x07230203) return internal_error("shader '" + path + "' is not SPIR-V");
  return code;
}

// ---------------------------------------------------------------------------------------------
// Kernels

LinearDispatch linear_dispatch(uint32_t count) {
  constexpr uint32_t kRowWidth = 65536;  // 1024 workgroups of 64: inside every device's limits
  LinearDispatch d;
  d.row_width = count <= kRowWidth ? std::max(count, 1u) : kRowWidth;
  d.size = {count == 0 ? 0 : d.row_width, (count + d.row_width - 1) / d.row_width, 1};
  return d;
}

Result<Kernel> Kernel::create(Context& context, const KernelDesc& desc, TraceBackend backend) {
  Kernel kernel;
  kernel.context_ = &context;
  kernel.name_ = desc.name;
  kernel.push_constant_bytes_ = desc.push_constant_bytes;
  kernel.workgroup_ = desc.workgroup;

  VkPushConstantRange range{kAllKernelStages, 0, desc.push_constant_bytes};
  VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layout_info.setLayoutCount = static_cast<uint32_t>(desc.set_layouts.size());
  layout_info.pSetLayouts = desc.set_layouts.data();
  layout_info.pushConstantRangeCount = desc.push_constant_bytes ? 1 : 0;
  layout_info.pPushConstantRanges = &range;
  VK_TRY(vkCreatePipelineLayout(context.device(), &layout_info, nullptr, &kernel.layout_));
  context.set_name(reinterpret_cast<uint64_t>(kernel.layout_), VK_OBJECT_TYPE_PIPELINE_LAYOUT,
                   desc.name + " layout");

  if (!desc.traces) {
    DDGI_TRY(kernel.create_compute(desc, desc.name + ".comp.spv"));
  } else if (backend == TraceBackend::kRayQuery) {
    DDGI_TRY(context.check_backend(backend));
    DDGI_TRY(kernel.create_compute(desc, desc.name + ".query.comp.spv"));
  } else {
    DDGI_TRY(context.check_backend(backend));
    DDGI_TRY(kernel.create_ray_tracing(desc));
  }
  context.set_name(reinterpret_cast<uint64_t>(kernel.pipeline_), VK_OBJECT_TYPE_PIPELINE,
                   desc.name);
  return kernel;
}

Status Kernel::create_compute(const KernelDesc& desc, const std::string& spirv_file) {
  DDGI_ASSIGN_OR_RETURN(VkShaderModule module, create_module(*context_, spirv_file));
  // Local size from specialization constants 0..2: the host owns the workgroup shape.
  const std::array<VkSpecializationMapEntry, 3> entries = {{
      {0, 0, 4},
      {1, 4, 4},
      {2, 8, 4},
  }};
  const std::array<uint32_t, 3> values = {desc.workgroup.x, desc.workgroup.y, desc.workgroup.z};
  VkSpecializationInfo specialization{3, entries.data(), sizeof(values), values.data()};
  VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  info.stage.pSpecializationInfo = &specialization;
  info.layout = layout_;
  if (context_->captures_shader_statistics()) {
    info.flags |= VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
  }
  const VkResult result =
      vkCreateComputePipelines(context_->device(), VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
  vkDestroyShaderModule(context_->device(), module, nullptr);
  if (result != VK_SUCCESS) return vk_error(result, "vkCreateComputePipelines(" + name_ + ")");
  context_->keep_shader_statistics(pipeline_, name_);
  return ok_status();
}

Status Kernel::create_ray_tracing(const KernelDesc& desc) {
  ray_tracing_ = true;
  std::vector<VkShaderModule> modules;
  auto destroy_modules = [&] {
    for (VkShaderModule m : modules) vkDestroyShaderModule(context_->device(), m, nullptr);
  };
  std::vector<VkPipelineShaderStageCreateInfo> stages;
  auto add_stage = [&](const std::string& file, VkShaderStageFlagBits stage) -> Status {
    DDGI_ASSIGN_OR_RETURN(VkShaderModule module, create_module(*context_, file));
    modules.push_back(module);
    VkPipelineShaderStageCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    info.stage = stage;
    info.module = module;
    info.pName = "main";
    stages.push_back(info);
    return ok_status();
  };
  Status added = add_stage(desc.name + ".pipeline.rgen.spv", VK_SHADER_STAGE_RAYGEN_BIT_KHR);
  for (const SharedStage& s : kSharedStages) {
    if (added.ok()) added = add_stage(s.file, s.stage);
  }
  if (!added.ok()) {
    destroy_modules();
    return added.error();
  }

  auto general = [](uint32_t stage) {
    VkRayTracingShaderGroupCreateInfoKHR g{
        VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR};
    g.type = VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR;
    g.generalShader = stage;
    g.closestHitShader = g.anyHitShader = g.intersectionShader = VK_SHADER_UNUSED_KHR;
    return g;
  };
  auto hit = [](uint32_t closest, uint32_t any) {
    VkRayTracingShaderGroupCreateInfoKHR g{
        VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR};
    g.type = VK_RAY_TRACING_SHADER_GROUP_TYPE_TRIANGLES_HIT_GROUP_KHR;
    g.generalShader = g.intersectionShader = VK_SHADER_UNUSED_KHR;
    g.closestHitShader = closest;
    g.anyHitShader = any;
    return g;
  };
  // Group order = SBT order: raygen | miss closest, miss shadow | hit closest, hit shadow.
  const std::array<VkRayTracingShaderGroupCreateInfoKHR, 5> groups = {
      general(0), general(1), general(2), hit(3, 4), hit(5, 6)};

  VkRayTracingPipelineCreateInfoKHR info{VK_STRUCTURE_TYPE_RAY_TRACING_PIPELINE_CREATE_INFO_KHR};
  info.stageCount = static_cast<uint32_t>(stages.size());
  info.pStages = stages.data();
  info.groupCount = static_cast<uint32_t>(groups.size());
  info.pGroups = groups.data();
  info.maxPipelineRayRecursionDepth = 1;
  info.layout = layout_;
  if (context_->captures_shader_statistics()) {
    info.flags |= VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
  }
  const VkResult result = context_->fn().vkCreateRayTracingPipelinesKHR(
      context_->device(), VK_NULL_HANDLE, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
  destroy_modules();
  if (result != VK_SUCCESS)
    return vk_error(result, "vkCreateRayTracingPipelinesKHR(" + name_ + ")");
  context_->keep_shader_statistics(pipeline_, name_);

  // Shader binding table: one region per group kind, each record one handle.
  const DeviceCapabilities& caps = context_->caps();
  const uint32_t handle_size = caps.shader_group_handle_size;
  const VkDeviceSize record = align_up(handle_size, caps.shader_group_handle_alignment);
  const VkDeviceSize base = caps.shader_group_base_alignment;
  std::vector<uint8_t> handles(groups.size() * handle_size);
  VK_TRY(context_->fn().vkGetRayTracingShaderGroupHandlesKHR(context_->device(), pipeline_, 0,
                                                             static_cast<uint32_t>(groups.size()),
                                                             handles.size(), handles.data()));
  const VkDeviceSize raygen_size = align_up(record, base);
  const VkDeviceSize miss_size = align_up(2 * record, base);
  const VkDeviceSize hit_size = align_up(2 * record, base);
  DDGI_ASSIGN_OR_RETURN(sbt_, Buffer::create(*context_, raygen_size + miss_size + hit_size + base,
                                             VK_BUFFER_USAGE_SHADER_BINDING_TABLE_BIT_KHR,
                                             MemoryUsage::kDeviceUpload, name_ + " SBT"));
  const VkDeviceAddress start = align_up(sbt_.address(), base);
  uint8_t* mapped = static_cast<uint8_t*>(sbt_.mapped()) + (start - sbt_.address());
  auto copy_handle = [&](uint32_t group, VkDeviceSize offset) {
    std::memcpy(mapped + offset, handles.data() + group * handle_size, handle_size);
  };
  copy_handle(0, 0);
  copy_handle(1, raygen_size);
  copy_handle(2, raygen_size + record);
  copy_handle(3, raygen_size + miss_size);
  copy_handle(4, raygen_size + miss_size + record);
  raygen_region_ = {start, raygen_size, raygen_size};
  miss_region_ = {start + raygen_size, record, 2 * record};
  hit_region_ = {start + raygen_size + miss_size, record, 2 * record};
  callable_region_ = {};
  return ok_status();
}

Kernel& Kernel::operator=(Kernel&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    name_ = std::move(other.name_);
    ray_tracing_ = other.ray_tracing_;
    layout_ = std::exchange(other.layout_, VK_NULL_HANDLE);
    pipeline_ = std::exchange(other.pipeline_, VK_NULL_HANDLE);
    push_constant_bytes_ = other.push_constant_bytes_;
    workgroup_ = other.workgroup_;
    sbt_ = std::move(other.sbt_);
    raygen_region_ = other.raygen_region_;
    miss_region_ = other.miss_region_;
    hit_region_ = other.hit_region_;
    callable_region_ = other.callable_region_;
  }
  return *this;
}

void Kernel::reset() {
  if (!context_) return;
  VkDevice device = context_->device();
  VkPipeline pipeline = pipeline_;
  VkPipelineLayout layout = layout_;
  context_->defer_destroy([device, pipeline, layout] {
    if (pipeline) vkDestroyPipeline(device, pipeline, nullptr);
    if (layout) vkDestroyPipelineLayout(device, layout, nullptr);
  });
  sbt_.reset();
  context_ = nullptr;
  pipeline_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
}

void Kernel::dispatch(VkCommandBuffer cmd, std::span<const VkDescriptorSet> sets,
                      const void* push_constants, glm::uvec3 size) const {
  const VkPipelineBindPoint bind_point =
      ray_tracing_ ? VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR : VK_PIPELINE_BIND_POINT_COMPUTE;
  vkCmdBindPipeline(cmd, bind_point, pipeline_);
  if (!sets.empty()) {
    vkCmdBindDescriptorSets(cmd, bind_point, layout_, 0, static_cast<uint32_t>(sets.size()),
                            sets.data(), 0, nullptr);
  }
  if (push_constant_bytes_) {
    vkCmdPushConstants(cmd, layout_, kAllKernelStages, 0, push_constant_bytes_, push_constants);
  }
  if (size.x == 0 || size.y == 0 || size.z == 0) return;
  if (ray_tracing_) {
    context_->fn().vkCmdTraceRaysKHR(cmd, &raygen_region_, &miss_region_, &hit_region_,
                                     &callable_region_, size.x, size.y, size.z);
  } else {
    vkCmdDispatch(cmd, (size.x + workgroup_.x - 1) / workgroup_.x,
                  (size.y + workgroup_.y - 1) / workgroup_.y,
                  (size.z + workgroup_.z - 1) / workgroup_.z);
  }
}

}  // namespace ddgi::vk
