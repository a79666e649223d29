// One DDGI irradiance field: its probe grid, the irradiance and distance atlases it owns
// (persistent history), the probe-ray buffer, and the kernels of one update:
//   trace -> shade -> blend irradiance -> blend distance -> borders.
// Frame kernels sample it through descriptor set 2 (shaders/shared/field_data.h).
#pragma once

#include <memory>
#include <vector>

#include "core/result.h"
#include "gi/field_params.h"
#include "render/frame_types.h"
#include "render/gpu_scene.h"
#include "shared/field_data.h"
#include "vk/context.h"
#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace ddgi {

struct IrradianceQuery {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
  glm::vec3 to_viewer{0.0f, 1.0f, 0.0f};  // the self-shadow bias leans this way
};

class IrradianceField {
 public:
  static Result<std::unique_ptr<IrradianceField>> create(vk::Context& context, GpuScene& scene,
                                                         const IrradianceFieldParams& params,
                                                         vk::TraceBackend backend);

  const IrradianceFieldParams& params() const { return params_; }
  // Applies new parameters. Changes of the grid, ray or texel counts rebuild the atlases and
  // start the field over; other changes keep its history.
  Status set_params(const IrradianceFieldParams& params);
  // Drops all history: every probe starts over at its next update.
  Status reset();

  // Records one update into `cmd`, timing its passes with `timer`.
  void record_update(VkCommandBuffer cmd, vk::GpuTimer& timer, DirectMode direct_mode);
  // Runs `count` updates, each its own submission; returns the pass times of the last.
  Result<std::vector<vk::PassTime>> update(uint32_t count, DirectMode direct_mode);

  // Field irradiance M (= E / pi) at arbitrary points.
  Result<std::vector<glm::vec3>> query(const std::vector<IrradianceQuery>& queries);

  struct AtlasImage {
    uint32_t width = 0;
    uint32_t height = 0;
    uint32_t channels = 0;  // 4: irradiance RGBA (encoded), 2: distance (mean, mean square)
    std::vector<float> texels;
  };
  Result<AtlasImage> read_irradiance_atlas();
  Result<AtlasImage> read_distance_atlas();

  VkDescriptorSetLayout sampling_layout() const { return sampling_layout_.handle(); }
  VkDescriptorSet sampling_set() const { return sampling_set_; }
  uint64_t gpu_bytes() const { return gpu_bytes_; }
  uint64_t updates() const { return update_index_; }
  // Rays traced by one update: probe rays plus one shadow ray per light per shaded ray.
  uint64_t rays_per_update() const;

 private:
  IrradianceField(vk::Context& context, GpuScene& scene) : context_(context), scene_(scene) {}
  Status create_layouts_and_kernels(vk::TraceBackend backend);
  Status create_resources();
  gpu::FieldConstants constants(DirectMode direct_mode) const;
  Result<AtlasImage> read_atlas(const vk::Image& image, uint32_t channels);

  vk::Context& context_;
  GpuScene& scene_;
  IrradianceFieldParams params_;
  AtlasLayout layout_;
  uint64_t update_index_ = 0;
  uint64_t gpu_bytes_ = 0;

  vk::DescriptorLayout sampling_layout_;  // set 2
  vk::DescriptorLayout update_layout_;    // set 1 of update kernels
  vk::DescriptorLayout query_layout_;     // set 1 of the query kernel
  VkDescriptorSet sampling_set_ = VK_NULL_HANDLE;
  VkDescriptorSet update_set_ = VK_NULL_HANDLE;
  VkDescriptorSet query_set_ = VK_NULL_HANDLE;  // rewritten by every query
  vk::Kernel trace_;
  vk::Kernel shade_;
  vk::Kernel blend_irradiance_;
  vk::Kernel blend_distance_;
  vk::Kernel borders_;
  vk::Kernel query_;
  vk::GpuTimer timer_;

  vk::Buffer constants_;
  vk::Buffer probes_;
  vk::Buffer rays_;
  vk::Image irradiance_;
  vk::Image distance_;
  vk::Sampler sampler_;
};

}  // namespace ddgi
