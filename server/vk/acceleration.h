// Bottom-level (one per mesh) and top-level (one per scene) acceleration structures.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "vk/context.h"
#include "vk/resources.h"

namespace ddgi::vk {

// One triangle geometry inside a BLAS: vertex positions (vec3 float, tightly packed) and
// uint32 indices, read from device buffers by address.
struct TriangleGeometry {
  VkDeviceAddress positions = 0;  // address of the first vertex of this geometry
  uint32_t vertex_count = 0;
  VkDeviceAddress indices = 0;  // address of the first index of this geometry
  uint32_t triangle_count = 0;
  // Opaque geometry skips any-hit processing; alpha-masked and glass geometry must not.
  bool opaque = true;
};

class AccelerationStructure {
 public:
  AccelerationStructure() = default;
  static Result<AccelerationStructure> create(Context& context, VkAccelerationStructureTypeKHR type,
                                              VkDeviceSize size, const std::string& name);
  ~AccelerationStructure() { reset(); }
  AccelerationStructure(AccelerationStructure&& other) noexcept { *this = std::move(other); }
  AccelerationStructure& operator=(AccelerationStructure&& other) noexcept;
  AccelerationStructure(const AccelerationStructure&) = delete;
  AccelerationStructure& operator=(const AccelerationStructure&) = delete;
  void reset();

  VkAccelerationStructureKHR handle() const { return handle_; }
  VkDeviceAddress address() const { return address_; }
  uint64_t bytes() const { return storage_.size(); }

 private:
  Context* context_ = nullptr;
  VkAccelerationStructureKHR handle_ = VK_NULL_HANDLE;
  VkDeviceAddress address_ = 0;
  Buffer storage_;
};

struct TlasInstance {
  glm::mat4 transform{1.0f};  // object to world
  uint32_t custom_index = 0;  // gl_InstanceCustomIndexEXT: our instance table index
  VkDeviceAddress blas_address = 0;
};

class AccelerationBuilder {
 public:
  explicit AccelerationBuilder(Context& context) : context_(context) {}

  // Builds one BLAS per entry of `meshes` (each a list of geometries), batched so the
  // scratch memory stays bounded.
  Result<std::vector<AccelerationStructure>> build_blases(
      const std::vector<std::vector<TriangleGeometry>>& meshes, const std::string& name);

  // Builds (or rebuilds in place when `tlas` already fits) the top-level structure.
  Status build_tlas(const std::vector<TlasInstance>& instances, AccelerationStructure& tlas,
                    Buffer& instance_buffer, const std::string& name);

 private:
  Context& context_;
};

}  // namespace ddgi::vk
