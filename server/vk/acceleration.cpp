#include "vk/acceleration.h"

#include <algorithm>
#include <cstring>

#include "vk/check.h"

namespace ddgi::vk {
namespace {

VkDeviceSize align_up(VkDeviceSize value, VkDeviceSize alignment) {
  return (value + alignment - 1) / alignment * alignment;
}

// Scratch memory used by one batch of BLAS builds: bounds peak memory on huge scenes.
constexpr VkDeviceSize kMaxBatchScratchBytes = 256ull << 20;

VkTransformMatrixKHR to_vk_transform(const glm::mat4& m) {
  VkTransformMatrixKHR t{};
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 4; ++col) t.matrix[row][col] = m[col][row];
  }
  return t;
}

}  // namespace

Result<AccelerationStructure> AccelerationStructure::create(Context& context,
                                                            VkAccelerationStructureTypeKHR type,
                                                            VkDeviceSize size,
                                                            const std::string& name) {
  AccelerationStructure result;
  DDGI_ASSIGN_OR_RETURN(
      result.storage_,
      Buffer::create(context, size, VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR,
                     MemoryUsage::kDeviceLocal, name + " storage"));
  result.context_ = &context;
  VkAccelerationStructureCreateInfoKHR info{
      VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
  info.buffer = result.storage_.handle();
  info.size = size;
  info.type = type;
  VK_TRY(context.fn().vkCreateAccelerationStructureKHR(context.device(), &info, nullptr,
                                                       &result.handle_));
  context.set_name(reinterpret_cast<uint64_t>(result.handle_),
                   VK_OBJECT_TYPE_ACCELERATION_STRUCTURE_KHR, name);
  VkAccelerationStructureDeviceAddressInfoKHR address{
      VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
  address.accelerationStructure = result.handle_;
  result.address_ =
      context.fn().vkGetAccelerationStructureDeviceAddressKHR(context.device(), &address);
  return result;
}

AccelerationStructure& AccelerationStructure::operator=(AccelerationStructure&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    handle_ = std::exchange(other.handle_, VK_NULL_HANDLE);
    address_ = std::exchange(other.address_, 0);
    storage_ = std::move(other.storage_);
  }
  return *this;
}

void AccelerationStructure::reset() {
  if (context_ && handle_) {
    Context* context = context_;
    VkAccelerationStructureKHR handle = handle_;
    context->defer_destroy([context, handle] {
      context->fn().vkDestroyAccelerationStructureKHR(context->device(), handle, nullptr);
    });
  }
  storage_.reset();  // queued after the handle, so it is freed after it
  context_ = nullptr;
  handle_ = VK_NULL_HANDLE;
  address_ = 0;
}

Result<std::vector<AccelerationStructure>> AccelerationBuilder::build_blases(
    const std::vector<std::vector<TriangleGeometry>>& meshes, const std::string& name) {
  const size_t count = meshes.size();
  std::vector<std::vector<VkAccelerationStructureGeometryKHR>> geometries(count);
  std::vector<std::vector<VkAccelerationStructureBuildRangeInfoKHR>> ranges(count);
  std::vector<VkAccelerationStructureBuildGeometryInfoKHR> infos(count);
  std::vector<VkDeviceSize> scratch_sizes(count);
  std::vector<AccelerationStructure> blases(count);

  for (size_t m = 0; m < count; ++m) {
    std::vector<uint32_t> primitive_counts;
    for (const TriangleGeometry& g : meshes[m]) {
      VkAccelerationStructureGeometryKHR geometry{
          VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
      geometry.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
      // Any-hit must see each candidate once so glass tints multiply exactly once.
      geometry.flags = g.opaque ? VK_GEOMETRY_OPAQUE_BIT_KHR
                                : VK_GEOMETRY_NO_DUPLICATE_ANY_HIT_INVOCATION_BIT_KHR;
      auto& tri = geometry.geometry.triangles;
      tri.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR;
      tri.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
      tri.vertexData.deviceAddress = g.positions;
      tri.vertexStride = sizeof(float) * 3;
      tri.maxVertex = g.vertex_count == 0 ? 0 : g.vertex_count - 1;
      tri.indexType = VK_INDEX_TYPE_UINT32;
      tri.indexData.deviceAddress = g.indices;
      geometries[m].push_back(geometry);
      ranges[m].push_back({g.triangle_count, 0, 0, 0});
      primitive_counts.push_back(g.triangle_count);
    }
    VkAccelerationStructureBuildGeometryInfoKHR& info = infos[m];
    info = {VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
    info.type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR;
    info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
    info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
    info.geometryCount = static_cast<uint32_t>(geometries[m].size());
    info.pGeometries = geometries[m].data();
    VkAccelerationStructureBuildSizesInfoKHR sizes{
        VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
    context_.fn().vkGetAccelerationStructureBuildSizesKHR(
        context_.device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info,
        primitive_counts.data(), &sizes);
    DDGI_ASSIGN_OR_RETURN(
        blases[m], AccelerationStructure::create(
                       context_, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
                       sizes.accelerationStructureSize, name + " BLAS " + std::to_string(m)));
    info.dstAccelerationStructure = blases[m].handle();
    scratch_sizes[m] = align_up(sizes.buildScratchSize, context_.caps().min_scratch_alignment);
  }

  // Batches of builds that share one scratch buffer, each build at its own offset.
  size_t first = 0;
  while (first < count) {
    size_t last = first;
    VkDeviceSize batch_scratch = 0;
    while (last < count &&
           (last == first || batch_scratch + scratch_sizes[last] <= kMaxBatchScratchBytes)) {
      batch_scratch += scratch_sizes[last];
      ++last;
    }
    DDGI_ASSIGN_OR_RETURN(
        Buffer scratch,
        Buffer::create(context_, batch_scratch + context_.caps().min_scratch_alignment,
                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::kDeviceLocal,
                       name + " BLAS scratch"));
    VkDeviceAddress scratch_address =
        align_up(scratch.address(), context_.caps().min_scratch_alignment);
    std::vector<const VkAccelerationStructureBuildRangeInfoKHR*> range_pointers;
    for (size_t m = first; m < last; ++m) {
      infos[m].scratchData.deviceAddress = scratch_address;
      scratch_address += scratch_sizes[m];
      range_pointers.push_back(ranges[m].data());
    }
    DDGI_TRY(context_.submit_and_wait([&](VkCommandBuffer cmd) {
      context_.fn().vkCmdBuildAccelerationStructuresKHR(
          cmd, static_cast<uint32_t>(last - first), infos.data() + first, range_pointers.data());
    }));
    first = last;
  }
  return blases;
}

Status AccelerationBuilder::build_tlas(const std::vector<TlasInstance>& instances,
                                       AccelerationStructure& tlas, Buffer& instance_buffer,
                                       const std::string& name) {
  const VkDeviceSize instance_bytes =
      std::max<size_t>(1, instances.size()) * sizeof(VkAccelerationStructureInstanceKHR);
  if (!instance_buffer || instance_buffer.size() < instance_bytes) {
    DDGI_ASSIGN_OR_RETURN(
        instance_buffer,
        Buffer::create(context_, instance_bytes,
                       VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR,
                       MemoryUsage::kUpload, name + " instances"));
  }
  auto* out = static_cast<VkAccelerationStructureInstanceKHR*>(instance_buffer.mapped());
  for (size_t i = 0; i < instances.size(); ++i) {
    VkAccelerationStructureInstanceKHR vk_instance{};
    vk_instance.transform = to_vk_transform(instances[i].transform);
    vk_instance.instanceCustomIndex = instances[i].custom_index & 0xFFFFFF;
    vk_instance.mask = 0xFF;
    vk_instance.instanceShaderBindingTableRecordOffset = 0;
    // Probe rays must see back faces (relocation and classification count them).
    vk_instance.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
    vk_instance.accelerationStructureReference = instances[i].blas_address;
    out[i] = vk_instance;
  }

  VkAccelerationStructureGeometryKHR geometry{
      VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  geometry.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  geometry.geometry.instances.sType =
      VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR;
  geometry.geometry.instances.data.deviceAddress = instance_buffer.address();
  VkAccelerationStructureBuildGeometryInfoKHR info{
      VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
  info.type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR;
  info.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  info.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  info.geometryCount = 1;
  info.pGeometries = &geometry;
  const uint32_t instance_count = static_cast<uint32_t>(instances.size());
  VkAccelerationStructureBuildSizesInfoKHR sizes{
      VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
  context_.fn().vkGetAccelerationStructureBuildSizesKHR(
      context_.device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &info, &instance_count,
      &sizes);
  if (!tlas.handle() || tlas.bytes() < sizes.accelerationStructureSize) {
    DDGI_ASSIGN_OR_RETURN(
        tlas, AccelerationStructure::create(context_, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR,
                                            sizes.accelerationStructureSize, name));
  }
  DDGI_ASSIGN_OR_RETURN(
      Buffer scratch,
      Buffer::create(context_, sizes.buildScratchSize + context_.caps().min_scratch_alignment,
                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::kDeviceLocal,
                     name + " scratch"));
  info.dstAccelerationStructure = tlas.handle();
  info.scratchData.deviceAddress =
      align_up(scratch.address(), context_.caps().min_scratch_alignment);
  VkAccelerationStructureBuildRangeInfoKHR range{instance_count, 0, 0, 0};
  const VkAccelerationStructureBuildRangeInfoKHR* range_pointer = &range;
  return context_.submit_and_wait([&](VkCommandBuffer cmd) {
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_HOST_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_HOST_BIT,
                         VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, 0, 1, &barrier, 0,
                         nullptr, 0, nullptr);
    context_.fn().vkCmdBuildAccelerationStructuresKHR(cmd, 1, &info, &range_pointer);
  });
}

}  // namespace ddgi::vk
