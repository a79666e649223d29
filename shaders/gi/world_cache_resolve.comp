#version 460
#extension GL_GOOGLE_include_directive : require
// The world cache's resolve pass (docs/world-cache.md), one invocation per slot: folds the
// frame's pending samples into the entry's mean (history weight capped at max_samples, cut to
// follow_samples after a geometry change) and frees entries untouched for max_age frames.
#define DDGI_WORLD_CACHE_SET 0
#include "common/world_cache.glsl"
#include "common/dispatch.glsl"

layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;
layout(push_constant, scalar) uniform Push { WorldCacheDispatch pc; };

void main() {
  const uint slot = linear_invocation(pc.row_width);
  if (slot >= pc.count) return;
  WorldCacheEntry e = cache_table[slot];
  if (e.key == 0u) return;
  float history = min(e.samples, cache.max_samples);
  if ((cache.flags & kWorldCacheCutHistory) != 0u) history = min(history, cache.follow_samples);
  if (e.pending_count > 0u) {
    const float n = float(e.pending_count);
    const float mean = float(e.pending_sum) / (kWorldCachePendingScale * n);
    e.value = (e.value * history + mean * n) / (history + n);
    e.samples = history + n;
    e.pending_sum = 0u;
    e.pending_count = 0u;
  } else if (cache.frame - e.last_frame > cache.max_age) {
    cache_table[slot] = WorldCacheEntry(0u, 0u, 0.0, 0.0, 0u, 0u, 0u, 0u);
    atomicAdd(cache_stats.evicted, 1u);
    return;
  } else {
    e.samples = history;
  }
  cache_table[slot] = e;
}
