// One shadow field (docs/shadow-field.md; thesis ch. 5): its probe grid, the visibility atlas
// (one RGBA32F channel per kept light, groups of four stacked vertically) and the moments atlas
// (mean distance, mean squared distance, ambient occlusion) it owns as persistent history, the
// probe-ray buffer, and the kernels of one update:
//   trace probe rays -> shadow (and AO) rays from their hits -> blend -> borders
// (split: shadow rays from the previous update's hits and new probe rays in one pass).
// Frame kernels sample it through the sampling set (shaders/shared/shadow_field_data.h).
#pragma once

#include <memory>
#include <vector>

#include "core/result.h"
#include "gi/field_sets.h"
#include "gi/shadow_params.h"
#include "gpu_scene/frame_types.h"
#include "gpu_scene/gpu_scene.h"
#include "shared/shadow_field_data.h"
#include "vk/context.h"
#include "vk/pass.h"
#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace ddgi {

struct ShadowFieldQuery {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
  glm::vec3 to_viewer{0.0f, 1.0f, 0.0f};  // the view bias leans this way
  // Shadow rays per spherical light behind the traced answer, [1, 4096].
  uint32_t traced_samples = 64;
  // Cosine-distributed rays behind the traced AO answer, [1, 4096].
  uint32_t ao_samples = 64;
};

struct ShadowFieldAnswer {
  float field_visibility[gpu::kShadowMaxLights] = {};   // kept lights; 1 past them
  float traced_visibility[gpu::kShadowMaxLights] = {};  // the scene's first 8 lights
  float field_ao = 1.0f;
  float traced_ao = 1.0f;
  float weight_sum = 0.0f;  // 0: no probe of the cage could answer
};

class ShadowField {
 public:
  static Result<std::unique_ptr<ShadowField>> create(vk::Context& context, GpuScene& scene,
                                                     const ShadowFieldParams& params,
                                                     vk::TraceBackend backend);

  const ShadowFieldParams& params() const { return params_; }
  // Applies new parameters. Changes of the grid, rays, texels or max_lights rebuild the atlases
  // and start over; others keep the history (a moved grid starts over too).
  Status set_params(const ShadowFieldParams& params);
  // Drops all history: the next update replaces every texel.
  Status reset();

  // The passes of one update (named "shadow ...", group kShadowField). `direct_mode`
  // kAmbientOcclusion also traces and blends the AO rays. Building the list advances the field:
  // record every list built, once, in order.
  std::vector<vk::Pass> update_passes(DirectMode direct_mode);
  // Runs `count` updates, each its own submission; returns the pass times of the last.
  Result<std::vector<vk::PassTime>> update(uint32_t count, DirectMode direct_mode);

  // The field's and traced rays' answers at arbitrary surface points.
  Result<std::vector<ShadowFieldAnswer>> query(const std::vector<ShadowFieldQuery>& queries);

  // Lights the atlas holds now: min(scene lights, max_lights).
  uint32_t kept_lights() const;
  // Whether an update in `mode` changes anything its readers sample: the AO mode reads the
  // moments; the shadow-field mode only the kept lights' visibility, so a scene without a
  // punctual light (lit by emitters or the sky) has nothing to update (the field models only
  // what the scene has; updates resume when a light is added).
  bool needs_update(DirectMode mode) const {
    return mode == DirectMode::kAmbientOcclusion || kept_lights() > 0;
  }
  // The persistent atlases (RGBA32F, GENERAL layout), for dumps (the service's DumpAtlas).
  const vk::Image& visibility_atlas() const { return visibility_; }
  const vk::Image& moments_atlas() const { return moments_; }
  const ShadowAtlasLayout& atlas_layout() const { return layout_; }
  VkDescriptorSetLayout sampling_layout() const { return sets_.sampling_layout(); }
  VkDescriptorSet sampling_set() const { return sets_.sampling_set(); }
  uint64_t gpu_bytes() const { return gpu_bytes_; }
  uint64_t updates() const { return update_index_; }
  // Rays one update traces: probe rays plus one shadow ray per kept light per probe ray (plus
  // one AO ray each in the AO mode).
  uint64_t rays_per_update(DirectMode direct_mode) const;

 private:
  ShadowField(vk::Context& context, GpuScene& scene) : context_(context), scene_(scene) {}
  Status create_layouts_and_kernels(vk::TraceBackend backend);
  Status create_resources();
  gpu::ShadowFieldConstants constants(DirectMode direct_mode) const;

  vk::Context& context_;
  GpuScene& scene_;
  ShadowFieldParams params_;
  ShadowAtlasLayout layout_;
  uint64_t update_index_ = 0;
  uint64_t updates_since_reset_ = 0;
  bool ao_history_ = false;  // an update has blended AO since the last reset
  uint64_t gpu_bytes_ = 0;

  // Sampling (set 2 of its kernels and of the frame's direct pass), update and query sets; the
  // query kernel; the timer of standalone updates; the atlas sampler.
  FieldSets sets_;
  vk::Kernel trace_;
  vk::Kernel blend_;
  vk::Kernel borders_;

  vk::Buffer constants_;
  vk::Buffer rays_;
  vk::Image visibility_;
  vk::Image moments_;
};

}  // namespace ddgi
