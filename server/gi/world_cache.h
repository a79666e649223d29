// The world-space hashed cache (docs/world-cache.md; Delaere 2021): values cached at implicit
// points in a fixed-size GPU hash table, with no structure built from the scene. The frame's
// ao-cache direct mode feeds it one AO sample per pixel and reads it back with a modified
// Shepard interpolation (shaders/common/world_cache.glsl). This class owns the table, its
// counters and constants, and the resolve pass; the renderer owns the passes that sample and
// read it (they need the frame's G-buffer).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "core/result.h"
#include "gi/param_table.h"
#include "vk/context.h"
#include "vk/pass.h"
#include "vk/pipeline.h"
#include "vk/resources.h"

namespace ddgi {

// Every field: default, range (in world_cache_param_table()), reason.
struct WorldCacheParams {
  // Slots of the hash table, a power of two in [2^10, 2^26]. 2^20 x 32 bytes = 32 MiB holds the
  // ~0.5 M points a 1080p view touches at the default density with room to probe; the memory
  // never grows: a fuller scene evicts and drops instead.
  uint32_t entries = 1u << 20;
  // Levels of the cell hierarchy, [1, 20]. 12 spans 16 m cells to 8 mm ones.
  uint32_t levels = 12;
  // Cell edge of level 0 in scene units, (0, 1e6]. 16: as large as the rooms of our scenes.
  float coarsest_cell = 16.0f;
  // Density: a cell spans this many pixels where it is seen, [1, 1024]. 16 pixels ~ 3 to 4 cached
  // points across 16 pixels (8 points per cell), a few hundred samples each at 1 sample per
  // pixel per frame within a second; fewer pixels show finer AO and converge slower.
  float cell_pixels = 16.0f;
  // The history's weight is capped at this many samples, [1, 1e6]: past it an entry is a moving
  // average of about that many frames' samples. 256: the noise of 1 spp AO falls 16x.
  float max_samples = 256.0f;
  // After geometry moves, every entry's history is cut to this many samples, [1, 1e6]: the cache
  // follows the new occlusion within a few frames instead of max_samples.
  float follow_samples = 4.0f;
  // Frames an entry may go unsampled before it is freed, [1, 1e7]. 600: 10 s at 60 fps, so a
  // turned-away view finds its cache again.
  uint32_t max_age = 600;
  // Slots tried from a key's own before a sample is dropped, [1, 64].
  uint32_t max_probes = 8;
  // AO rays longer than this count as open, (0, 1e30]. Unbounded: the sky's visibility, like the
  // shadow field's AO.
  float ao_distance = 1e30f;
  // Bits of a point's 32-bit key kept, [1, 32]. Only tests lower it: keys then collide, and the
  // checksum must keep the points apart.
  uint32_t key_bits = 32;

  bool operator==(const WorldCacheParams&) const = default;
};
const ParamTable<WorldCacheParams>& world_cache_param_table();
// The table's ranges, then: entries a power of two.
Status validate(const WorldCacheParams& params);
// Bytes of GPU memory a cache of these parameters holds.
uint64_t world_cache_bytes(const WorldCacheParams& params);

// The cache's counters since it was made (or cleared), as far as the GPU got: read while a frame
// runs, they count part of it. 32-bit and wrapping: take differences.
struct WorldCacheCounters {
  uint32_t inserted = 0;          // points that got an entry
  uint32_t evicted = 0;           // entries freed, unsampled for max_age frames
  uint32_t dropped = 0;           // samples not cached: no free slot within max_probes
  uint32_t checksum_rejects = 0;  // probes that met the key held by another point
  uint32_t live() const { return inserted - evicted; }
};

class WorldCache {
 public:
  static Result<std::unique_ptr<WorldCache>> create(vk::Context& context,
                                                    const WorldCacheParams& params);
  const WorldCacheParams& params() const { return params_; }
  VkDescriptorSetLayout layout() const { return layout_.handle(); }
  VkDescriptorSet descriptor_set() const { return set_; }
  uint64_t gpu_bytes() const { return gpu_bytes_; }
  uint32_t capacity() const { return params_.entries; }

  // The pass that opens one frame's use of the cache: its constants (camera position, the
  // footprint of a pixel per unit distance: 2 tan(yfov/2) / height).
  // `geometry_moves`: GpuScene::move_count(); a change since the last frame cuts histories.
  vk::Pass begin_frame_pass(const glm::vec3& camera_position, float pixel_footprint,
                            uint64_t geometry_moves);
  // The pass that folds the frame's samples in (after the sampling pass).
  vk::Pass resolve_pass() const;
  WorldCacheCounters counters() const;

 private:
  explicit WorldCache(vk::Context& context) : context_(context) {}
  Status create_resources();
  Status clear();  // empties the table and zeroes the counters

  vk::Context& context_;
  WorldCacheParams params_;
  vk::DescriptorLayout layout_;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  vk::Buffer constants_;
  vk::Buffer table_;
  vk::Buffer stats_;  // host-visible: read after the frame without a copy
  vk::Kernel resolve_;
  uint64_t gpu_bytes_ = 0;
  uint32_t frame_ = 0;
  uint64_t geometry_moves_ = 0;
};

}  // namespace ddgi
