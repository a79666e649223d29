// The world-space hashed cache on the GPU (docs/world-cache.md; Delaere 2021, "a world-space
// cache with implicit points"): values cached at implicit points, never stored as geometry. A
// point is one of 8 per cell (one per octant, jittered by a hash of the cell) of a level's cubic
// grid; its entry in a fixed-size hash table is found by a 32-bit key and confirmed by a 32-bit
// checksum computed from the point's coordinates with an independent hash, so two points never
// share an entry: a key held by another point is counted (checksum_rejects) and probing goes on.
//
// Kernels pick the set the cache is bound to with DDGI_WORLD_CACHE_SET (the frame's update and
// direct passes use 2, the resolve pass 0).
#ifndef DDGI_SHARED_WORLD_CACHE_DATA_H
#define DDGI_SHARED_WORLD_CACHE_DATA_H

#include "shared/interop.h"

DDGI_NAMESPACE_BEGIN

DDGI_CONST uint kWorldCacheBindingConstants = 0;  // WorldCacheConstants (one)
DDGI_CONST uint kWorldCacheBindingTable = 1;      // WorldCacheEntry per slot
DDGI_CONST uint kWorldCacheBindingStats = 2;      // WorldCacheStats (one)

// Fixed-point scale of WorldCacheEntry::pending_sum: values in [0, 1] summed by 32-bit integer
// atomics; 2^20 samples of 1 fit in one frame before the sum would wrap.
DDGI_CONST float kWorldCachePendingScale = 4096.0;

// WorldCacheConstants::flags
DDGI_CONST uint kWorldCacheCutHistory = 1u;  // geometry changed: histories cut to follow_samples

// One slot of the table. key == 0: empty. scalar layout, 32 bytes.
struct WorldCacheEntry {
  uint key;            // the point's 32-bit key (never 0)
  uint checksum;       // the point's independent 32-bit hash (never 0)
  float value;         // the cached mean (AO: the open fraction)
  float samples;       // the history's weight, at most max_samples
  uint pending_sum;    // this frame's samples, fixed point (kWorldCachePendingScale)
  uint pending_count;  // ... and their number
  uint last_frame;     // the frame that last wrote a sample
  uint pad0;
};

// Counters since the cache was made (cumulative, so that a frame still running never clears what
// the host reads of an earlier one; live entries = inserted - evicted). 32-bit: the host reads
// differences, which stay right across a wrap. scalar layout, 32 bytes.
struct WorldCacheStats {
  uint inserted;          // points that got a new entry
  uint evicted;           // entries freed: untouched for max_age frames
  uint dropped;           // samples not cached: no free slot within max_probes of the key
  uint checksum_rejects;  // probes that met this key held by another point (kept apart)
  uint pad0;
  uint pad1;
  uint pad2;
  uint pad3;
};

// What every cache kernel reads. scalar layout, 64 bytes.
struct WorldCacheConstants {
  vec3 camera_position;
  float footprint_scale;  // cell edge wanted at distance d: d * footprint_scale
  float coarsest_cell;    // cell edge of level 0; level L: coarsest_cell / 2^L
  uint levels;
  uint capacity_mask;    // slots - 1 (a power of two)
  uint max_probes;       // slots tried from a key's own
  uint frame;            // frames since the cache was made
  uint max_age;          // frames an entry may go untouched before it is freed
  float max_samples;     // the history's weight is capped here (then a moving average)
  float follow_samples;  // ... and cut to this after a geometry change
  uint key_mask;         // bits of the key kept (all but in tests of collisions)
  uint flags;            // kWorldCache*
  float ao_distance;     // AO rays longer than this are open
  uint pad0;
};

// Push constants of the cache's passes: the update reads the G-buffer (width x height), the
// resolve visits every slot in a linear dispatch (count, row_width: shaders/common/dispatch.glsl).
struct WorldCacheDispatch {
  uint width;
  uint height;
  uint count;
  uint row_width;
};

#ifdef __cplusplus
static_assert(sizeof(WorldCacheDispatch) == 16);
static_assert(sizeof(WorldCacheEntry) == 32);
static_assert(offsetof(WorldCacheEntry, key) == 0);
static_assert(offsetof(WorldCacheEntry, checksum) == 4);
static_assert(offsetof(WorldCacheEntry, value) == 8);
static_assert(offsetof(WorldCacheEntry, samples) == 12);
static_assert(offsetof(WorldCacheEntry, pending_sum) == 16);
static_assert(offsetof(WorldCacheEntry, pending_count) == 20);
static_assert(offsetof(WorldCacheEntry, last_frame) == 24);

static_assert(sizeof(WorldCacheStats) == 32);
static_assert(offsetof(WorldCacheStats, inserted) == 0);
static_assert(offsetof(WorldCacheStats, evicted) == 4);
static_assert(offsetof(WorldCacheStats, dropped) == 8);
static_assert(offsetof(WorldCacheStats, checksum_rejects) == 12);

static_assert(sizeof(WorldCacheConstants) == 64);
static_assert(offsetof(WorldCacheConstants, camera_position) == 0);
static_assert(offsetof(WorldCacheConstants, footprint_scale) == 12);
static_assert(offsetof(WorldCacheConstants, coarsest_cell) == 16);
static_assert(offsetof(WorldCacheConstants, levels) == 20);
static_assert(offsetof(WorldCacheConstants, capacity_mask) == 24);
static_assert(offsetof(WorldCacheConstants, max_probes) == 28);
static_assert(offsetof(WorldCacheConstants, frame) == 32);
static_assert(offsetof(WorldCacheConstants, max_age) == 36);
static_assert(offsetof(WorldCacheConstants, max_samples) == 40);
static_assert(offsetof(WorldCacheConstants, follow_samples) == 44);
static_assert(offsetof(WorldCacheConstants, key_mask) == 48);
static_assert(offsetof(WorldCacheConstants, flags) == 52);
static_assert(offsetof(WorldCacheConstants, ao_distance) == 56);
#endif

DDGI_NAMESPACE_END

#endif
