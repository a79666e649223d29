// The scene on the GPU: geometry and material tables, textures, the environment map, one BLAS
// per mesh and the TLAS, all bound as descriptor set 0 (shaders/shared/scene_data.h).
// Instance transforms and lights can change between frames: the TLAS is rebuilt from the
// existing BLASes, which are never rebuilt for a transform change.
#pragma once

#include <deque>
#include <memory>
#include <vector>

#include "core/result.h"
#include "scene/scene.h"
#include "shared/scene_data.h"
#include "vk/acceleration.h"
#include "vk/context.h"
#include "vk/pipeline.h"
#include "vk/resources.h"

namespace ddgi {

class GpuScene {
 public:
  static Result<std::unique_ptr<GpuScene>> create(vk::Context& context, const Scene& scene);

  VkDescriptorSetLayout layout() const { return layout_.handle(); }
  VkDescriptorSet descriptor_set() const { return set_; }
  const Scene& scene() const { return scene_; }
  const Bounds& bounds() const { return bounds_; }
  // Bytes of GPU memory held by the scene (buffers, textures, acceleration structures).
  uint64_t gpu_bytes() const { return gpu_bytes_; }
  uint32_t triangle_count() const { return triangle_count_; }
  // Emissive triangles in the emitter table (binding kSceneBindingEmitters).
  uint32_t emitter_count() const { return emitter_count_; }
  // Changes with every update below, so that accumulating passes know to start over.
  uint64_t revision() const { return revision_; }

  // Moves one instance (index into Scene::instances); rebuilds the TLAS.
  Status set_instance_transform(size_t instance, const glm::mat4& object_to_world);
  // World regions where geometry moved after `after_move` moves (each move contributes the
  // instance's bounds before and after), and the count of moves so far. `*everything` is set
  // when the log no longer reaches back that far: treat the whole scene as changed.
  std::vector<Bounds> moved_regions(uint64_t after_move, bool* everything) const;
  uint64_t move_count() const { return move_count_; }
  // World-space bounds of one instance as placed now.
  Bounds instance_bounds(size_t instance) const;
  // Replaces every light.
  Status set_lights(const std::vector<Light>& lights);

 private:
  explicit GpuScene(vk::Context& context) : context_(context) {}
  Status upload_geometry();
  Status upload_materials();
  Status upload_textures();
  Status upload_environment();
  Status upload_lights();
  Status upload_instances();
  Status upload_emitters();
  Status upload_globals();
  Status build_acceleration_structures();
  Status rebuild_tlas();
  Status create_descriptors();

  vk::Context& context_;
  Scene scene_;  // the CPU copy: the source of truth for updates
  Bounds bounds_;
  std::vector<Bounds> mesh_bounds_;  // object space, per mesh
  std::deque<Bounds> move_log_;      // regions of the last kMaxLoggedMoves moves
  uint64_t move_count_ = 0;
  uint64_t gpu_bytes_ = 0;
  uint32_t triangle_count_ = 0;
  uint32_t emitter_count_ = 0;
  float emitter_total_weight_ = 0.0f;
  uint64_t revision_ = 0;

  // Per mesh, per primitive: where its data lives in the shared buffers.
  struct PrimitiveRange {
    uint32_t first_vertex = 0;
    uint32_t vertex_count = 0;
    uint32_t first_index = 0;
    uint32_t index_count = 0;
    uint32_t material = 0;
    uint32_t flags = 0;
  };
  std::vector<std::vector<PrimitiveRange>> mesh_ranges_;
  std::vector<uint32_t> mesh_first_geometry_;
  uint32_t scene_flags_ = 0;

  vk::Buffer positions_;
  vk::Buffer attributes_;
  vk::Buffer indices_;
  vk::Buffer geometries_;
  vk::Buffer instances_;
  vk::Buffer materials_;
  vk::Buffer lights_;
  vk::Buffer globals_;
  vk::Buffer emitters_;
  std::vector<vk::Image> textures_;
  vk::Image environment_;
  vk::Sampler texture_sampler_;
  vk::Sampler environment_sampler_;
  std::vector<vk::AccelerationStructure> blases_;
  vk::AccelerationStructure tlas_;
  vk::Buffer tlas_instances_;
  vk::DescriptorLayout layout_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

// The descriptor layout of set 0, identical for every scene.
std::vector<vk::Binding> scene_bindings(uint32_t max_textures);

}  // namespace ddgi
