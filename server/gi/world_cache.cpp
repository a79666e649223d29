// The world-space hashed cache's table, counters and resolve pass (gi/world_cache.h).
#include "gi/world_cache.h"

#include <cstring>
#include <string>

#include "shared/world_cache_data.h"

namespace ddgi {
namespace {

constexpr glm::uvec3 kLinearWorkgroup{64, 1, 1};

std::vector<vk::Binding> cache_bindings() {
  return {{gpu::kWorldCacheBindingConstants},
          {gpu::kWorldCacheBindingTable},
          {gpu::kWorldCacheBindingStats}};
}

}  // namespace

const ParamTable<WorldCacheParams>& world_cache_param_table() {
  using P = WorldCacheParams;
  // The order is that of --world-cache help.
  static const ParamTable<P> table(
      "world cache parameter", "world cache ",
      {
          param::number("entries", &P::entries, 1u << 10, 1u << 26,
                        "hash-table slots (a power of two; 32 bytes each)"),
          param::number("levels", &P::levels, 1u, 20u, "levels of the cell hierarchy"),
          param::number("coarsest_cell", &P::coarsest_cell, 1e-6f, 1e6f,
                        "cell edge of level 0 (scene units)"),
          param::number("cell_pixels", &P::cell_pixels, 1.0f, 1024.0f,
                        "pixels a cell spans where it is seen (the level rule)"),
          param::number("max_samples", &P::max_samples, 1.0f, 1e6f, "history weight cap (samples)"),
          param::number("follow_samples", &P::follow_samples, 1.0f, 1e6f,
                        "history kept when geometry moves (samples)"),
          param::number("max_age", &P::max_age, 1u, 10000000u,
                        "frames an entry may go unsampled before it is freed"),
          param::number("max_probes", &P::max_probes, 1u, 64u,
                        "slots tried from a key's own before a sample is dropped"),
          param::number("ao_distance", &P::ao_distance, 1e-30f, 1e30f,
                        "longer AO rays count as open sky"),
          param::number("key_bits", &P::key_bits, 1u, 32u,
                        "bits of a point's key kept (tests of collisions)"),
      });
  return table;
}

Status validate(const WorldCacheParams& params) {
  DDGI_TRY(world_cache_param_table().check(params));
  if ((params.entries & (params.entries - 1)) != 0) {
    return invalid_argument("world cache entries must be a power of two (got " +
                            std::to_string(params.entries) + ")");
  }
  return ok_status();
}

uint64_t world_cache_bytes(const WorldCacheParams& params) {
  return uint64_t(params.entries) * sizeof(gpu::WorldCacheEntry) +
         sizeof(gpu::WorldCacheConstants) + sizeof(gpu::WorldCacheStats);
}

Result<std::unique_ptr<WorldCache>> WorldCache::create(vk::Context& context,
                                                       const WorldCacheParams& params) {
  DDGI_TRY(validate(params));
  std::unique_ptr<WorldCache> cache(new WorldCache(context));
  cache->params_ = params;
  DDGI_ASSIGN_OR_RETURN(cache->layout_, vk::DescriptorLayout::create(context, cache_bindings(), 1,
                                                                     "world cache set"));
  DDGI_ASSIGN_OR_RETURN(cache->set_, cache->layout_.allocate());
  DDGI_ASSIGN_OR_RETURN(cache->resolve_, vk::Kernel::create(context,
                                                            {"world_cache_resolve",
                                                             false,
                                                             {cache->layout_.handle()},
                                                             sizeof(gpu::WorldCacheDispatch),
                                                             kLinearWorkgroup},
                                                            vk::TraceBackend::kRayQuery));
  DDGI_TRY(cache->create_resources());
  return cache;
}

Status WorldCache::create_resources() {
  const uint64_t before = context_.allocated_bytes();
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  DDGI_ASSIGN_OR_RETURN(constants_,
                        vk::Buffer::create(context_, sizeof(gpu::WorldCacheConstants), storage,
                                           vk::MemoryUsage::kDeviceLocal, "world cache constants"));
  DDGI_ASSIGN_OR_RETURN(
      table_, vk::Buffer::create(context_, uint64_t(params_.entries) * sizeof(gpu::WorldCacheEntry),
                                 storage, vk::MemoryUsage::kDeviceLocal, "world cache table"));
  DDGI_ASSIGN_OR_RETURN(stats_,
                        vk::Buffer::create(context_, sizeof(gpu::WorldCacheStats), storage,
                                           vk::MemoryUsage::kReadback, "world cache counters"));
  gpu_bytes_ = context_.allocated_bytes() - before;
  vk::DescriptorWriter(set_)
      .buffer(gpu::kWorldCacheBindingConstants, constants_)
      .buffer(gpu::kWorldCacheBindingTable, table_)
      .buffer(gpu::kWorldCacheBindingStats, stats_)
      .apply(context_.device());
  return clear();
}

Status WorldCache::clear() {
  frame_ = 0;
  return context_.submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdFillBuffer(cmd, table_.handle(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, stats_.handle(), 0, VK_WHOLE_SIZE, 0);
    vk::barrier_all(cmd);
  });
}

vk::Pass WorldCache::begin_frame_pass(const glm::vec3& camera_position, float pixel_footprint,
                                      uint64_t geometry_moves) {
  gpu::WorldCacheConstants c{};
  c.camera_position = camera_position;
  c.footprint_scale = pixel_footprint * params_.cell_pixels;
  c.coarsest_cell = params_.coarsest_cell;
  c.levels = params_.levels;
  c.capacity_mask = params_.entries - 1;
  c.max_probes = params_.max_probes;
  c.frame = ++frame_;
  c.max_age = params_.max_age;
  c.max_samples = params_.max_samples;
  c.follow_samples = params_.follow_samples;
  c.key_mask = params_.key_bits >= 32 ? ~0u : (1u << params_.key_bits) - 1u;
  c.flags = geometry_moves != geometry_moves_ ? gpu::kWorldCacheCutHistory : 0u;
  c.ao_distance = params_.ao_distance;
  geometry_moves_ = geometry_moves;
  return vk::upload_pass("cache constants", vk::PassGroup::kFrame, constants_, c);
}

vk::Pass WorldCache::resolve_pass() const {
  const vk::LinearDispatch d = vk::linear_dispatch(params_.entries);
  vk::Pass p;
  p.name = "cache resolve";
  p.group = vk::PassGroup::kFrame;
  p.kernel = &resolve_;
  p.sets = {set_};
  p.push_constants = vk::Pass::push(gpu::WorldCacheDispatch{0, 0, params_.entries, d.row_width});
  p.size = d.size;
  p.reads = {&constants_};
  p.writes = {&table_, &stats_};
  return p;
}

WorldCacheCounters WorldCache::counters() const {
  gpu::WorldCacheStats s{};
  std::memcpy(&s, stats_.mapped(), sizeof(s));
  return {s.inserted, s.evicted, s.dropped, s.checksum_rejects};
}

}  // namespace ddgi
