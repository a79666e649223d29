#include "gi/shadow_field.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "gi/field_params.h"

namespace ddgi {
namespace {

constexpr uint32_t kMaxTimedPasses = 8;
constexpr uint32_t kMaxQuerySamples = 4096;
constexpr glm::uvec3 kLinearWorkgroup{64, 1, 1};

// SplitMix64: update n's rotation depends only on (seed, n).
uint64_t splitmix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

float uniform01(uint64_t& state) {
  state = splitmix64(state);
  return float(state >> 40) * (1.0f / 16777216.0f);
}

// A uniformly distributed rotation (Shoemake's unit quaternion from three uniforms), so that the
// probe rays of successive updates cover the sphere between the Fibonacci directions.
glm::mat4 random_rotation(uint32_t seed, uint64_t update) {
  uint64_t state = (uint64_t(seed) << 32) ^ (update * 0x2545f4914f6cdd1dull);
  const float u1 = uniform01(state), u2 = uniform01(state), u3 = uniform01(state);
  const float a = std::sqrt(1.0f - u1), b = std::sqrt(u1);
  const float two_pi = 6.28318530718f;
  const glm::quat q(a * std::sin(two_pi * u2), a * std::cos(two_pi * u2), b * std::sin(two_pi * u3),
                    b * std::cos(two_pi * u3));
  return glm::mat4_cast(glm::normalize(q));
}

bool layout_changed(const ShadowFieldParams& a, const ShadowFieldParams& b) {
  return a.counts != b.counts || a.rays_per_probe != b.rays_per_probe || a.texels != b.texels ||
         a.max_lights != b.max_lights;
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Whether a shadow field of `params` fits the GPU budget once the `held_bytes` it replaces
// are freed.
Status check_budget(const vk::Context& context, const ShadowFieldParams& params,
                    uint64_t held_bytes) {
  return context.check_fits(shadow_field_gpu_bytes(params), held_bytes,
                            "the shadow field (" + std::to_string(params.counts.x) + "x" +
                                std::to_string(params.counts.y) + "x" +
                                std::to_string(params.counts.z) + " probes, " +
                                std::to_string(params.rays_per_probe) + " rays and " +
                                std::to_string(params.texels) + "^2 texels each)");
}

}  // namespace

Result<std::unique_ptr<ShadowField>> ShadowField::create(vk::Context& context, GpuScene& scene,
                                                         const ShadowFieldParams& params,
                                                         vk::TraceBackend backend) {
  DDGI_TRY(validate(params));
  DDGI_TRY(context.check_backend(backend));
  std::unique_ptr<ShadowField> field(new ShadowField(context, scene));
  field->params_ = params;
  DDGI_TRY(field->create_layouts_and_kernels(backend));
  DDGI_TRY(field->create_resources());
  return field;
}

Status ShadowField::create_layouts_and_kernels(vk::TraceBackend backend) {
  const VkDescriptorType sampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  const VkDescriptorType storage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  FieldSetsDesc desc;
  desc.name = "shadow field";
  desc.sampling = {{gpu::kShadowBindingConstants},
                   {gpu::kShadowBindingVisibility, sampled},
                   {gpu::kShadowBindingMoments, sampled}};
  desc.update = {{gpu::kShadowUpdateBindingRays},
                 {gpu::kShadowUpdateBindingVisibilityOut, storage},
                 {gpu::kShadowUpdateBindingMomentsOut, storage}};
  desc.query = {{gpu::kShadowQueryBindingQueries}, {gpu::kShadowQueryBindingAnswers}};
  desc.query_kernel = "shadow_query";
  desc.query_traces = true;
  desc.push_constant_bytes = sizeof(gpu::ShadowDispatch);
  desc.workgroup = kLinearWorkgroup;
  desc.timed_passes = kMaxTimedPasses;
  DDGI_ASSIGN_OR_RETURN(sets_, FieldSets::create(context_, scene_, desc, backend));

  const uint32_t push = sizeof(gpu::ShadowDispatch);
  const std::vector<VkDescriptorSetLayout> update_layouts = sets_.update_layouts();
  auto kernel = [&](const char* name, bool traces) {
    return vk::Kernel::create(context_, {name, traces, update_layouts, push, kLinearWorkgroup},
                              backend);
  };
  DDGI_ASSIGN_OR_RETURN(trace_, kernel("shadow_trace", true));
  DDGI_ASSIGN_OR_RETURN(blend_, kernel("shadow_blend", false));
  DDGI_ASSIGN_OR_RETURN(borders_, kernel("shadow_borders", false));
  return ok_status();
}

Status ShadowField::create_resources() {
  // Checked before anything is freed, so that a refused grid leaves the field as it was.
  DDGI_TRY(check_budget(context_, params_, gpu_bytes_));
  // Free the old resources before allocating, so the budget sees only the new ones.
  constants_.reset();
  rays_.reset();
  visibility_.reset();
  moments_.reset();

  const uint64_t before = context_.allocated_bytes();
  layout_ = shadow_atlas_layout(params_);
  const uint64_t rays = probe_count(params_) * params_.rays_per_probe;
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  DDGI_ASSIGN_OR_RETURN(constants_,
                        vk::Buffer::create(context_, sizeof(gpu::ShadowFieldConstants), storage,
                                           vk::MemoryUsage::kDeviceLocal, "shadow constants"));
  DDGI_ASSIGN_OR_RETURN(rays_,
                        vk::Buffer::create(context_, rays * sizeof(gpu::ShadowRay), storage,
                                           vk::MemoryUsage::kDeviceLocal, "shadow probe rays"));
  const VkImageUsageFlags usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                  VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  DDGI_ASSIGN_OR_RETURN(
      visibility_,
      vk::Image::create_2d(context_, layout_.visibility_size.x, layout_.visibility_size.y,
                           VK_FORMAT_R32G32B32A32_SFLOAT, usage, "shadow visibility atlas"));
  DDGI_ASSIGN_OR_RETURN(
      moments_, vk::Image::create_2d(context_, layout_.moments_size.x, layout_.moments_size.y,
                                     VK_FORMAT_R32G32B32A32_SFLOAT, usage, "shadow moments atlas"));
  gpu_bytes_ = context_.allocated_bytes() - before;

  vk::DescriptorWriter(sets_.sampling_set())
      .buffer(gpu::kShadowBindingConstants, constants_)
      .sampled_image(gpu::kShadowBindingVisibility, visibility_, sets_.sampler().handle(), 0,
                     VK_IMAGE_LAYOUT_GENERAL)
      .sampled_image(gpu::kShadowBindingMoments, moments_, sets_.sampler().handle(), 0,
                     VK_IMAGE_LAYOUT_GENERAL)
      .apply(context_.device());
  vk::DescriptorWriter(sets_.update_set())
      .buffer(gpu::kShadowUpdateBindingRays, rays_)
      .storage_image(gpu::kShadowUpdateBindingVisibilityOut, visibility_)
      .storage_image(gpu::kShadowUpdateBindingMomentsOut, moments_)
      .apply(context_.device());
  return reset();
}

Status ShadowField::reset() {
  update_index_ = 0;
  updates_since_reset_ = 0;
  ao_history_ = false;
  const gpu::ShadowFieldConstants c = constants(DirectMode::kShadowField);
  return context_.submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdUpdateBuffer(cmd, constants_.handle(), 0, sizeof(c), &c);
    // Invalid surfels and results: a split update's first shadow pass blends nothing.
    vkCmdFillBuffer(cmd, rays_.handle(), 0, VK_WHOLE_SIZE, 0);
    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    // Unobserved texels: lit, and at distance 0 so that Chebyshev's test rejects them.
    const VkClearColorValue lit{{1.0f, 1.0f, 1.0f, 1.0f}};
    const VkClearColorValue unseen{{0.0f, 0.0f, 1.0f, 0.0f}};
    for (auto [image, value] : {std::pair{&visibility_, &lit}, std::pair{&moments_, &unseen}}) {
      vk::transition_image(cmd, image->handle(), VK_IMAGE_LAYOUT_UNDEFINED,
                           VK_IMAGE_LAYOUT_GENERAL);
      vkCmdClearColorImage(cmd, image->handle(), VK_IMAGE_LAYOUT_GENERAL, value, 1, &range);
    }
    vk::barrier_all(cmd);
  });
}

Status ShadowField::set_params(const ShadowFieldParams& params) {
  DDGI_TRY(validate(params));
  const ShadowFieldParams old = params_;
  DDGI_TRY(replace_params<ShadowFieldParams>(
      params_, params, layout_changed(old, params),
      [&](const ShadowFieldParams& next) { return check_budget(context_, next, gpu_bytes_); },
      [&] { return create_resources(); }));
  if (old.origin != params.origin || old.spacing != params.spacing ||
      old.split_update != params.split_update) {
    return reset();
  }
  // Sampling reads the constants: bring them up to date before the next update does.
  const vk::Pass upload = vk::upload_pass("shadow constants", vk::PassGroup::kShadowField,
                                          constants_, constants(DirectMode::kShadowField));
  return context_.submit_and_wait(
      [&](VkCommandBuffer cmd) { vk::record_passes(cmd, nullptr, std::span(&upload, 1)); });
}

uint32_t ShadowField::kept_lights() const {
  return static_cast<uint32_t>(
      std::min<size_t>(scene_.scene().lights.size(), size_t(params_.max_lights)));
}

uint64_t ShadowField::rays_per_update(DirectMode direct_mode) const {
  const uint64_t probe_rays = probe_count(params_) * params_.rays_per_probe;
  const uint64_t ao = direct_mode == DirectMode::kAmbientOcclusion ? 1 : 0;
  return probe_rays * (1 + kept_lights() + ao);
}

gpu::ShadowFieldConstants ShadowField::constants(DirectMode direct_mode) const {
  gpu::ShadowFieldConstants c{};
  c.origin = params_.origin;
  c.spacing = params_.spacing;
  c.counts = params_.counts;
  c.rays_per_probe = params_.rays_per_probe;
  c.probe_count = static_cast<uint32_t>(probe_count(params_));
  c.texels = params_.texels;
  c.tiles_per_row = layout_.tiles_per_row;
  c.tile_rows = layout_.tile_rows;
  c.light_count = kept_lights();
  c.scene_light_count = static_cast<uint32_t>(scene_.scene().lights.size());
  c.atlas_size = glm::vec2(layout_.visibility_size.x, layout_.visibility_size.y);
  c.update_index = static_cast<uint32_t>(update_index_);
  // A split update blends nothing the first time (its surfels are not traced yet), so the
  // history counts as empty for two updates.
  const uint64_t empty_updates = params_.split_update ? 2 : 1;
  const bool trace_ao = direct_mode == DirectMode::kAmbientOcclusion;
  c.flags = (updates_since_reset_ < empty_updates ? gpu::kShadowResetHistory : 0u) |
            (trace_ao ? gpu::kShadowTraceAo : 0u) |
            (params_.weighting == ShadowWeighting::kCosine ? gpu::kShadowCosineWeights : 0u) |
            (params_.overflow == ShadowOverflow::kTracedShadows ? gpu::kShadowOverflowTraced : 0u) |
            (trace_ao && !ao_history_ ? gpu::kShadowResetAo : 0u);
  c.hysteresis = params_.hysteresis;
  c.visibility_exponent = params_.visibility_exponent;
  c.distance_exponent = params_.distance_exponent;
  c.normal_bias = params_.normal_bias;
  c.view_bias = params_.view_bias;
  c.sharpening = params_.sharpening;
  c.max_ray_distance = params_.max_ray_distance;
  c.max_visibility_distance = visibility_range(params_.spacing);
  c.ao_distance = params_.ao_distance;
  c.weight_crush_threshold = params_.weight_crush_threshold;
  c.backface_distance_scale = params_.backface_distance_scale;
  c.seed = params_.seed;
  c.ray_rotation = random_rotation(params_.seed, update_index_);
  return c;
}

std::vector<vk::Pass> ShadowField::update_passes(DirectMode direct_mode) {
  const uint64_t probes = probe_count(params_);
  auto pass = [&](const vk::Kernel& kernel, const char* name, uint32_t per_probe, uint32_t mode,
                  std::vector<vk::ResourceRef> reads, std::vector<vk::ResourceRef> writes) {
    const uint32_t count = static_cast<uint32_t>(probes * per_probe);
    const vk::LinearDispatch d = vk::linear_dispatch(count);
    vk::Pass p;
    p.name = name;
    p.group = vk::PassGroup::kShadowField;
    p.kernel = &kernel;
    p.sets = {scene_.descriptor_set(), sets_.update_set(), sets_.sampling_set()};
    p.push_constants = vk::Pass::push(gpu::ShadowDispatch{count, d.row_width, mode, per_probe});
    p.size = d.size;
    p.reads = std::move(reads);
    p.writes = std::move(writes);
    return p;
  };
  const uint32_t rays = params_.rays_per_probe;
  const uint32_t t = params_.texels;
  std::vector<vk::Pass> passes = {vk::upload_pass("shadow constants", vk::PassGroup::kShadowField,
                                                  constants_, constants(direct_mode))};
  if (params_.split_update) {
    passes.push_back(pass(trace_, "shadow trace+rays", rays,
                          gpu::kShadowPassShadow | gpu::kShadowPassPrimary, {&rays_}, {&rays_}));
  } else {
    passes.push_back(pass(trace_, "shadow trace", rays, gpu::kShadowPassPrimary, {}, {&rays_}));
    passes.push_back(pass(trace_, "shadow rays", rays, gpu::kShadowPassShadow, {&rays_}, {&rays_}));
  }
  passes.push_back(pass(blend_, "shadow blend", t * t, 0, {&rays_}, {&visibility_, &moments_}));
  passes.push_back(pass(borders_, "shadow borders", 4 * (t + 1), 0, {}, {&visibility_, &moments_}));

  // An AO history exists once an update blended valid AO results.
  const bool blended = updates_since_reset_ + 1 >= (params_.split_update ? 2u : 1u);
  if (direct_mode == DirectMode::kAmbientOcclusion && blended) ao_history_ = true;
  ++update_index_;
  ++updates_since_reset_;
  return passes;
}

Result<std::vector<vk::PassTime>> ShadowField::update(uint32_t count, DirectMode direct_mode) {
  for (uint32_t i = 0; i < count; ++i) {
    const std::vector<vk::Pass> passes = update_passes(direct_mode);
    DDGI_TRY(context_.submit_and_wait([&](VkCommandBuffer cmd) {
      sets_.timer().begin_frame(cmd);
      vk::record_passes(cmd, &sets_.timer(), passes);
    }));
  }
  context_.collect_garbage();
  return sets_.timer().read();
}

Result<std::vector<ShadowFieldAnswer>> ShadowField::query(
    const std::vector<ShadowFieldQuery>& queries) {
  if (queries.empty()) return std::vector<ShadowFieldAnswer>{};
  std::vector<gpu::ShadowQuery> input;
  input.reserve(queries.size());
  for (size_t i = 0; i < queries.size(); ++i) {
    const ShadowFieldQuery& q = queries[i];
    if (!finite(q.position) || !finite(q.normal) || !finite(q.to_viewer) ||
        glm::length(q.normal) < 1e-6f || glm::length(q.to_viewer) < 1e-6f) {
      return invalid_argument("shadow field query " + std::to_string(i) +
                              ": position must be finite, normal and to_viewer finite and "
                              "non-zero");
    }
    if (q.traced_samples < 1 || q.traced_samples > kMaxQuerySamples || q.ao_samples < 1 ||
        q.ao_samples > kMaxQuerySamples) {
      return invalid_argument("shadow field query " + std::to_string(i) +
                              ": traced_samples and ao_samples must be in [1, " +
                              std::to_string(kMaxQuerySamples) + "]");
    }
    input.push_back({q.position, q.traced_samples, glm::normalize(q.normal), q.ao_samples,
                     glm::normalize(q.to_viewer), static_cast<uint32_t>(i)});
  }
  // Sampling reads the constants: the query's first, in the shadow-field mode.
  std::vector<vk::Pass> before = {vk::upload_pass("shadow constants", vk::PassGroup::kShadowField,
                                                  constants_, constants(DirectMode::kShadowField))};
  DDGI_ASSIGN_OR_RETURN(const std::vector<gpu::ShadowAnswer> raw,
                        (sets_.query<gpu::ShadowQuery, gpu::ShadowAnswer>(
                            input,
                            [](uint32_t count, uint32_t row_width) {
                              return vk::Pass::push(gpu::ShadowDispatch{count, row_width, 0, 1});
                            },
                            std::move(before))));

  std::vector<ShadowFieldAnswer> answers(raw.size());
  for (size_t i = 0; i < raw.size(); ++i) {
    for (uint32_t l = 0; l < gpu::kShadowMaxLights; ++l) {
      const uint32_t g = l / gpu::kShadowLightsPerGroup, k = l % gpu::kShadowLightsPerGroup;
      answers[i].field_visibility[l] = raw[i].field_visibility[g][k];
      answers[i].traced_visibility[l] = raw[i].traced_visibility[g][k];
    }
    answers[i].field_ao = raw[i].field_ao;
    answers[i].traced_ao = raw[i].traced_ao;
    answers[i].weight_sum = raw[i].weight_sum;
  }
  return answers;
}

}  // namespace ddgi
