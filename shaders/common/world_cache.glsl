// The world-space hashed cache (set DDGI_WORLD_CACHE_SET; shared/world_cache_data.h,
// docs/world-cache.md): implicit points, the level a surface position uses, the table's
// find-or-insert and lookup, the stochastic choice of the point a sample feeds (3D barycentric
// probabilities over the three nearest points) and the modified Shepard reconstruction.
#ifndef DDGI_COMMON_WORLD_CACHE_GLSL
#define DDGI_COMMON_WORLD_CACHE_GLSL

#extension GL_EXT_scalar_block_layout : require

#ifndef DDGI_WORLD_CACHE_SET
#error "define DDGI_WORLD_CACHE_SET (the descriptor set the world cache is bound to)"
#endif

#include "common/math.glsl"
#include "shared/world_cache_data.h"

layout(set = DDGI_WORLD_CACHE_SET, binding = kWorldCacheBindingConstants, scalar) readonly buffer
    WorldCacheBlock {
  WorldCacheConstants cache;
};
layout(set = DDGI_WORLD_CACHE_SET, binding = kWorldCacheBindingTable, scalar) buffer
    WorldCacheTable {
  WorldCacheEntry cache_table[];
};
layout(set = DDGI_WORLD_CACHE_SET, binding = kWorldCacheBindingStats, scalar) buffer
    WorldCacheStatsBlock {
  WorldCacheStats cache_stats;
};

// --- Levels ---------------------------------------------------------------------------------
// The level a position at `distance` from the camera wants, continuous: the cell edge that spans
// cell_pixels pixels there is distance * footprint_scale; level L has cells of
// coarsest_cell / 2^L, so L = log2(coarsest_cell / wanted), clamped to the levels there are.
float cache_level(float distance) {
  const float wanted = max(distance * cache.footprint_scale, 1e-20);
  return clamp(log2(cache.coarsest_cell / wanted), 0.0, float(cache.levels - 1u));
}
float cache_cell_size(uint level) { return cache.coarsest_cell * exp2(-float(level)); }

// --- Implicit points: 8 per cell, one per octant, jittered by a hash of (level, cell, octant) --
struct CachePoint {
  vec3 position;
  uint key;       // never 0
  uint checksum;  // never 0
};

uint cache_point_seed(uint level, ivec3 cell, uint octant) {
  return pcg_hash(uint(cell.x) + pcg_hash(uint(cell.y) + pcg_hash(uint(cell.z) +
                                                                   pcg_hash(level * 8u + octant))));
}
// A second hash of the same coordinates through other mixing (Murmur3's finaliser over a
// running combination), independent of the seed: two points whose keys agree differ here.
uint cache_mix(uint h, uint v) {
  v *= 0xcc9e2d51u;
  v = (v << 15u) | (v >> 17u);
  h ^= v * 0x1b873593u;
  h = (h << 13u) | (h >> 19u);
  return h * 5u + 0xe6546b64u;
}
uint cache_checksum(uint level, ivec3 cell, uint octant, uint bucket) {
  uint h = cache_mix(0x8badf00du, uint(cell.x));
  h = cache_mix(h, uint(cell.y));
  h = cache_mix(h, uint(cell.z));
  h = cache_mix(h, (level << 8u) | (octant << 4u) | bucket);
  h ^= h >> 16u;
  h *= 0x85ebca6bu;
  h ^= h >> 13u;
  h *= 0xc2b2ae35u;
  h ^= h >> 16u;
  return max(h, 1u);
}

// The surfaces a point serves are split by the dominant axis of their normal (6 buckets), so
// the two sides of a wall, or a floor and the wall it meets, never share an entry.
uint cache_normal_bucket(vec3 n) {
  const vec3 a = abs(n);
  const uint axis = a.x >= a.y && a.x >= a.z ? 0u : (a.y >= a.z ? 1u : 2u);
  return axis * 2u + (n[axis] < 0.0 ? 1u : 0u);
}

CachePoint cache_point(uint level, ivec3 cell, uint octant, uint bucket) {
  const float size = cache_cell_size(level);
  const uint seed = cache_point_seed(level, cell, octant);
  const vec3 jitter = vec3(float(pcg_hash(seed) >> 8), float(pcg_hash(seed ^ 0x68e31da4u) >> 8),
                           float(pcg_hash(seed ^ 0xb5297a4du) >> 8)) *
                      (1.0 / 16777216.0);
  const vec3 corner = vec3(uvec3(octant & 1u, (octant >> 1u) & 1u, (octant >> 2u) & 1u));
  CachePoint p;
  p.position = (vec3(cell) + (corner + jitter) * 0.5) * size;
  p.key = max(pcg_hash(seed ^ (bucket * 0x9e3779b9u)) & cache.key_mask, 1u);
  p.checksum = cache_checksum(level, cell, octant, bucket);
  return p;
}

// The 216 candidates around a cell `home` of `level`: the 8 points of it and of each of its 26
// neighbours, numbered i = ((dz + 1) * 9 + (dy + 1) * 3 + dx + 1) * 8 + octant.
const uint kCacheCandidates = 216u;
CachePoint cache_candidate(uint level, ivec3 home, uint i, uint bucket) {
  const uint cell = i / 8u;
  const ivec3 offset = ivec3(int(cell % 3u), int((cell / 3u) % 3u), int(cell / 9u)) - 1;
  return cache_point(level, home + offset, i % 8u, bucket);
}

// --- The table ------------------------------------------------------------------------------
// The slot holding `p`, or -1. Probes every slot of the window (no early stop at an empty one:
// eviction leaves holes in a run).
int cache_find(CachePoint p) {
  for (uint i = 0u; i < cache.max_probes; ++i) {
    const uint slot = (p.key + i) & cache.capacity_mask;
    if (cache_table[slot].key == p.key && cache_table[slot].checksum == p.checksum) {
      return int(slot);
    }
  }
  return -1;
}

// The slot of `p`, claimed if it has none; -1 when the window is full (counted as dropped). A
// slot is claimed in two compare-and-swaps, the key then the checksum: whoever sets the
// checksum owns the slot, so two points with one key never share it (the loser counts a
// checksum reject and probes on).
int cache_find_or_insert(CachePoint p) {
  const int found = cache_find(p);
  if (found >= 0) return found;
  for (uint i = 0u; i < cache.max_probes; ++i) {
    const uint slot = (p.key + i) & cache.capacity_mask;
    const uint key = atomicCompSwap(cache_table[slot].key, 0u, p.key);
    if (key != 0u && key != p.key) continue;
    const uint checksum = atomicCompSwap(cache_table[slot].checksum, 0u, p.checksum);
    if (checksum == 0u) {
      atomicAdd(cache_stats.inserted, 1u);
      return int(slot);
    }
    if (checksum == p.checksum) return int(slot);
    atomicAdd(cache_stats.checksum_rejects, 1u);
  }
  atomicAdd(cache_stats.dropped, 1u);
  return -1;
}

// Adds one sample in [0, 1] to the entry's pending sum (the resolve pass folds it in).
void cache_add_sample(int slot, float value) {
  if (slot < 0) return;
  atomicAdd(cache_table[slot].pending_sum,
            uint(clamp(value, 0.0, 1.0) * kWorldCachePendingScale + 0.5));
  atomicAdd(cache_table[slot].pending_count, 1u);
  cache_table[slot].last_frame = cache.frame;
}

// --- The point a sample at x feeds ----------------------------------------------------------
// The three nearest implicit points of x's cell and its 26 neighbours (216 candidates); one is
// picked with probability proportional to 1/d^2 (the paper's 3D barycentric weights:
// P_i = a_i / sum a, a_0 = d1^2 d2^2 and so on), which blurs the cells' borders instead of
// showing them. `u` in [0, 1).
CachePoint cache_pick_point(vec3 x, uint level, uint bucket, float u) {
  const float size = cache_cell_size(level);
  const ivec3 home = ivec3(floor(x / size));
  CachePoint best[3];
  float d2[3] = float[3](1e38, 1e38, 1e38);
  for (uint i = 0u; i < kCacheCandidates; ++i) {
    const CachePoint p = cache_candidate(level, home, i, bucket);
    const vec3 e = p.position - x;
    const float d = dot(e, e);
    if (d >= d2[2]) continue;
    if (d < d2[0]) {
      best[2] = best[1], d2[2] = d2[1];
      best[1] = best[0], d2[1] = d2[0];
      best[0] = p, d2[0] = d;
    } else if (d < d2[1]) {
      best[2] = best[1], d2[2] = d2[1];
      best[1] = p, d2[1] = d;
    } else {
      best[2] = p, d2[2] = d;
    }
  }
  const vec3 inverse = 1.0 / max(vec3(d2[0], d2[1], d2[2]), vec3(1e-30 * size * size));
  const float total = inverse.x + inverse.y + inverse.z;
  const float r = u * total;
  if (r < inverse.x) return best[0];
  if (r < inverse.x + inverse.y) return best[1];
  return best[2];
}

// --- Reading -------------------------------------------------------------------------------
// The modified Shepard interpolation at x of one level: every cached point within one cell edge
// r, weighted by max(0, r - |p - x|) (the paper's linear fall-off). Returns (sum w v, sum w).
vec2 cache_shepard(vec3 x, uint level, uint bucket) {
  const float r = cache_cell_size(level);
  const ivec3 home = ivec3(floor(x / r));
  vec2 sum = vec2(0.0);
  for (uint i = 0u; i < kCacheCandidates; ++i) {
    const CachePoint p = cache_candidate(level, home, i, bucket);
    const float w = r - length(p.position - x);
    if (w <= 0.0) continue;
    const int slot = cache_find(p);
    if (slot < 0 || !(cache_table[slot].samples > 0.0)) continue;
    sum += vec2(w * cache_table[slot].value, w);
  }
  return sum;
}

// The cached value at x: the two levels around the continuous level blended by its fraction
// (no seam where the level steps), each falling back to coarser levels while it holds nothing
// near x. -1 when nothing is cached near x at any level.
float cache_read(vec3 x, vec3 normal, float distance) {
  const uint bucket = cache_normal_bucket(normal);
  const float level = cache_level(distance);
  const uint fine = uint(level);
  float result = 0.0;
  float weight = 0.0;
  for (uint k = 0u; k < 2u; ++k) {
    const float share = k == 0u ? 1.0 - fract(level) : fract(level);
    if (share <= 0.0 || fine + k >= cache.levels) continue;
    for (int l = int(fine + k); l >= 0; --l) {
      const vec2 s = cache_shepard(x, uint(l), bucket);
      if (s.y > 0.0) {
        result += share * s.x / s.y;
        weight += share;
        break;
      }
    }
  }
  return weight > 0.0 ? result / weight : -1.0;
}

// The cache-points view: a colour per point, from its key, of the cached point weighing most at
// x on the finer of x's two levels (dark grey where nothing near x is cached yet), so the cells
// and the blend between points show.
vec3 cache_point_colour(vec3 x, vec3 normal, float distance) {
  const uint bucket = cache_normal_bucket(normal);
  const uint level = uint(cache_level(distance));
  const float r = cache_cell_size(level);
  const ivec3 home = ivec3(floor(x / r));
  float best = 0.0;
  uint key = 0u;
  for (uint i = 0u; i < kCacheCandidates; ++i) {
    const CachePoint p = cache_candidate(level, home, i, bucket);
    const float w = r - length(p.position - x);
    if (w <= best || cache_find(p) < 0) continue;
    best = w;
    key = p.key;
  }
  if (key == 0u) return vec3(0.05);
  const uint h = pcg_hash(key);
  return vec3(float(h & 255u), float((h >> 8u) & 255u), float((h >> 16u) & 255u)) / 255.0 * 0.8 +
         0.2;
}

#endif
