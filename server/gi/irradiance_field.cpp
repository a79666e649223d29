#include "gi/irradiance_field.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <tuple>

#include <glm/gtc/quaternion.hpp>

#include "core/log.h"
#include "gi/probe_grid.h"

namespace ddgi {
namespace {

// An update's passes, and a scroll's start before them (relocations + 1 traces and management
// passes each, and the start).
constexpr uint32_t kMaxTimedPasses = 64;

using vk::with_access;
constexpr glm::uvec3 kLinearWorkgroup{64, 1, 1};
// field_hit_light: 128 invocations (a ray of 128 neighbouring probes) took 0.97-0.98 of the time
// of 64 on an H100, 256 no less (docs/results/field-at-ray-cost.md).
constexpr glm::uvec3 kHitLightWorkgroup{128, 1, 1};
// field_blend: one workgroup per probe. 64 invocations: the default maps (8x8 irradiance, 16x16
// distance texels) in four full rounds.
constexpr glm::uvec3 kProbeWorkgroup{64, 1, 1};
// Probes per row of workgroups (inside every device's 65535-workgroup limit per dimension).
constexpr uint32_t kProbeWorkgroupRow = 4096;

// SplitMix64: a counter-based generator, so update n's rotation depends only on (seed, n).
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

// A uniformly distributed random rotation (Shoemake's unit quaternion from three uniforms).
glm::mat4 random_rotation(uint32_t seed, uint64_t update) {
  uint64_t state = (uint64_t(seed) << 32) ^ update;
  const float u1 = uniform01(state), u2 = uniform01(state), u3 = uniform01(state);
  const float a = std::sqrt(1.0f - u1), b = std::sqrt(u1);
  const float two_pi = 6.28318530718f;
  const glm::quat q(a * std::sin(two_pi * u2), a * std::cos(two_pi * u2), b * std::sin(two_pi * u3),
                    b * std::cos(two_pi * u3));
  return glm::mat4_cast(glm::normalize(q));
}

bool grid_changed(const IrradianceFieldParams& a, const IrradianceFieldParams& b) {
  return a.counts != b.counts || a.rays_per_probe != b.rays_per_probe ||
         a.relocation_iterations != b.relocation_iterations ||
         a.classification != b.classification || a.probe_offset_limit != b.probe_offset_limit ||
         a.min_frontface_distance != b.min_frontface_distance ||
         a.backface_threshold != b.backface_threshold || a.fixed_rays != b.fixed_rays ||
         a.irradiance_texels != b.irradiance_texels || a.distance_texels != b.distance_texels ||
         a.basis != b.basis || a.cascades != b.cascades || a.static_volumes != b.static_volumes;
}

// Whether a field of `params` fits the GPU budget once the `held_bytes` it replaces are freed.
Status check_budget(const vk::Context& context, const IrradianceFieldParams& params,
                    uint64_t held_bytes) {
  return context.check_fits(
      field_gpu_bytes(params), held_bytes,
      "the irradiance field (" + std::to_string(params.counts.x) + "x" +
          std::to_string(params.counts.y) + "x" + std::to_string(params.counts.z) + " probes, " +
          std::to_string(params.rays_per_probe + params.fixed_rays) + " rays each)");
}

}  // namespace

Result<std::unique_ptr<IrradianceField>> IrradianceField::create(
    vk::Context& context, GpuScene& scene, const IrradianceFieldParams& params,
    vk::TraceBackend backend, const ShadowField* shadow_field) {
  DDGI_TRY(validate(params));
  std::unique_ptr<IrradianceField> field(new IrradianceField(context, scene, shadow_field));
  field->params_ = params;
  DDGI_TRY(field->create_layouts_and_kernels(backend));
  DDGI_TRY(field->create_resources());
  return field;
}

Status IrradianceField::create_layouts_and_kernels(vk::TraceBackend backend) {
  const VkDescriptorType sampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  const VkDescriptorType storage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  FieldSetsDesc desc;
  desc.name = "field";
  desc.sampling = {{gpu::kFieldBindingConstants},
                   {gpu::kFieldBindingProbes},
                   {gpu::kFieldBindingIrradiance, sampled},
                   {gpu::kFieldBindingDistance, sampled},
                   {gpu::kFieldBindingSh}};
  desc.update = {{gpu::kFieldUpdateBindingRays},
                 {gpu::kFieldUpdateBindingIrradianceOut, storage},
                 {gpu::kFieldUpdateBindingDistanceOut, storage},
                 {gpu::kFieldUpdateBindingProbeList},
                 {gpu::kFieldUpdateBindingSurfels},
                 {gpu::kFieldUpdateBindingDrift},
                 {gpu::kFieldUpdateBindingHits}};
  desc.query = {{gpu::kFieldQueryBindingQueries}, {gpu::kFieldQueryBindingAnswers}};
  desc.query_kernel = "field_query";
  desc.push_constant_bytes = sizeof(gpu::FieldDispatch);
  desc.workgroup = kLinearWorkgroup;
  desc.timed_passes = kMaxTimedPasses;
  DDGI_ASSIGN_OR_RETURN(sets_, FieldSets::create(context_, scene_, desc, backend));

  backend_ = backend;
  DDGI_ASSIGN_OR_RETURN(trace_, update_kernel("field_trace", true, kLinearWorkgroup));
  DDGI_ASSIGN_OR_RETURN(hit_light_, update_kernel("field_hit_light", false, kHitLightWorkgroup));
  DDGI_ASSIGN_OR_RETURN(blend_, update_kernel("field_blend", false, kProbeWorkgroup));
  DDGI_ASSIGN_OR_RETURN(blend_sh_, update_kernel("field_blend_sh", false, kProbeWorkgroup));
  DDGI_ASSIGN_OR_RETURN(manage_, update_kernel("field_probes", false, kLinearWorkgroup));
  if (shadow_field_) {
    DDGI_ASSIGN_OR_RETURN(trace_with_shadow_field_,
                          update_kernel("field_trace_shadow_field", true, kLinearWorkgroup, true));
  }
  return create_path_kernels(params_.probe_bounces > 0);
}

Status IrradianceField::create_path_kernels(bool wanted) {
  if (!wanted || trace_paths_.valid()) return ok_status();
  DDGI_ASSIGN_OR_RETURN(trace_paths_, update_kernel("field_trace_paths", true, kLinearWorkgroup));
  if (shadow_field_) {
    DDGI_ASSIGN_OR_RETURN(
        trace_with_shadow_field_paths_,
        update_kernel("field_trace_shadow_field_paths", true, kLinearWorkgroup, true));
  }
  return ok_status();
}

Status IrradianceField::check_path_fits(const IrradianceFieldParams& params, FieldUpdatePath path) {
  if (params.settle_threshold > 0.0f && path == FieldUpdatePath::kSplit) {
    return failed_precondition(
        "settle_threshold > 0 (adaptive rays) measures each probe's change in the fused blend "
        "only; the split update path (a benchmark reference) traces every probe");
  }
  if (params.probe_bounces > 0 && path == FieldUpdatePath::kSplit) {
    return failed_precondition(
        "probe_bounces > 0 traces paths in the fused update only; the split update path (a "
        "benchmark reference) reads the field at probe-ray hits");
  }
  return ok_status();
}

Status IrradianceField::create_split_kernels() {
  DDGI_ASSIGN_OR_RETURN(trace_surfels_,
                        update_kernel("field_trace_surfels", true, kLinearWorkgroup));
  DDGI_ASSIGN_OR_RETURN(shade_, update_kernel("field_shade", true, kLinearWorkgroup));
  DDGI_ASSIGN_OR_RETURN(blend_irradiance_,
                        update_kernel("field_blend_irradiance", false, kLinearWorkgroup));
  DDGI_ASSIGN_OR_RETURN(blend_distance_,
                        update_kernel("field_blend_distance", false, kLinearWorkgroup));
  DDGI_ASSIGN_OR_RETURN(borders_, update_kernel("field_borders", false, kLinearWorkgroup));
  if (shadow_field_) {
    DDGI_ASSIGN_OR_RETURN(shade_with_shadow_field_,
                          update_kernel("field_shade_shadow_field", true, kLinearWorkgroup, true));
  }
  return ok_status();
}

Result<vk::Kernel> IrradianceField::update_kernel(const char* name, bool traces,
                                                  glm::uvec3 workgroup,
                                                  bool reads_shadow_field) const {
  std::vector<VkDescriptorSetLayout> layouts = sets_.update_layouts();
  // The lighting kernels' shadow-field variants bind it as set 3.
  if (reads_shadow_field) layouts.push_back(shadow_field_->sampling_layout());
  return vk::Kernel::create(
      context_, {name, traces, layouts, uint32_t(sizeof(gpu::FieldDispatch)), workgroup}, backend_);
}

Status IrradianceField::create_resources() {
  // Checked before anything is freed, so that a refused grid leaves the field as it was.
  DDGI_TRY(check_budget(context_, params_, gpu_bytes_));
  // Free the old resources before allocating, so the budget sees only the new ones (and
  // gpu_bytes_ below counts only them).
  constants_.reset();
  probes_.reset();
  rays_.reset();
  hits_.reset();
  surfels_.reset();
  probe_list_.reset();
  irradiance_.reset();
  distance_.reset();
  sh_.reset();

  const uint64_t before = context_.allocated_bytes();
  layout_ = atlas_layout(params_);
  const uint64_t probes = probe_count(params_);
  const uint64_t rays = probes * (params_.rays_per_probe + params_.fixed_rays);
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  DDGI_ASSIGN_OR_RETURN(constants_,
                        vk::Buffer::create(context_, sizeof(Constants), storage,
                                           vk::MemoryUsage::kDeviceLocal, "field constants"));
  DDGI_ASSIGN_OR_RETURN(probes_,
                        vk::Buffer::create(context_, probes * sizeof(gpu::ProbeState), storage,
                                           vk::MemoryUsage::kDeviceLocal, "probe states"));
  DDGI_ASSIGN_OR_RETURN(rays_, vk::Buffer::create(context_, rays * sizeof(gpu::ProbeRay), storage,
                                                  vk::MemoryUsage::kDeviceLocal, "probe rays"));
  const uint64_t sh_probes = params_.basis == ProbeBasis::kSh ? probes : 1;
  DDGI_ASSIGN_OR_RETURN(sh_, vk::Buffer::create(context_, sh_probes * sizeof(gpu::ShProbe), storage,
                                                vk::MemoryUsage::kDeviceLocal, "SH probes"));
  DDGI_ASSIGN_OR_RETURN(
      drift_, vk::Buffer::create(context_, sizeof(glm::vec4) + probes * sizeof(gpu::ProbeDrift),
                                 storage, vk::MemoryUsage::kDeviceLocal, "probe drift"));
  // Two halves: the active probes the updates take, and the probes a scroll starts.
  DDGI_ASSIGN_OR_RETURN(
      probe_list_,
      vk::Buffer::create(context_, 2 * probes * sizeof(uint32_t),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         vk::MemoryUsage::kDeviceUpload, "probe list"));
  DDGI_ASSIGN_OR_RETURN(scroll_states_,
                        vk::Buffer::create(context_, probes * sizeof(gpu::ProbeState),
                                           VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           vk::MemoryUsage::kReadback, "scrolled probe states"));
  DDGI_ASSIGN_OR_RETURN(
      zero_tile_,
      vk::Buffer::create(context_, largest_map_tile_bytes(params_),
                         VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                         vk::MemoryUsage::kDeviceLocal, "zero map tile"));
  const VkImageUsageFlags image_usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
                                        VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                                        VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  DDGI_ASSIGN_OR_RETURN(
      irradiance_,
      vk::Image::create_2d(context_, layout_.irradiance_size.x, layout_.irradiance_size.y,
                           VK_FORMAT_R32G32B32A32_SFLOAT, image_usage, "irradiance atlas"));
  DDGI_ASSIGN_OR_RETURN(
      distance_, vk::Image::create_2d(context_, layout_.distance_size.x, layout_.distance_size.y,
                                      VK_FORMAT_R32G32_SFLOAT, image_usage, "distance atlas"));
  DDGI_TRY(create_hits(params_));
  gpu_bytes_ = context_.allocated_bytes() - before;

  vk::DescriptorWriter(sets_.sampling_set())
      .buffer(gpu::kFieldBindingConstants, constants_)
      .buffer(gpu::kFieldBindingProbes, probes_)
      .sampled_image(gpu::kFieldBindingIrradiance, irradiance_, sets_.sampler().handle(), 0,
                     VK_IMAGE_LAYOUT_GENERAL)
      .sampled_image(gpu::kFieldBindingDistance, distance_, sets_.sampler().handle(), 0,
                     VK_IMAGE_LAYOUT_GENERAL)
      .buffer(gpu::kFieldBindingSh, sh_)
      .apply(context_.device());
  vk::DescriptorWriter(sets_.update_set())
      .buffer(gpu::kFieldUpdateBindingRays, rays_)
      .storage_image(gpu::kFieldUpdateBindingIrradianceOut, irradiance_)
      .storage_image(gpu::kFieldUpdateBindingDistanceOut, distance_)
      .buffer(gpu::kFieldUpdateBindingProbeList, probe_list_)
      .buffer(gpu::kFieldUpdateBindingDrift, drift_)
      .apply(context_.device());
  if (update_path_ == FieldUpdatePath::kSplit) DDGI_TRY(create_surfels());
  return reset();
}

Status IrradianceField::create_hits(const IrradianceFieldParams& params) {
  DDGI_ASSIGN_OR_RETURN(
      vk::Buffer hits,
      vk::Buffer::create(context_, probe_ray_hit_records(params) * sizeof(gpu::ProbeRayHit),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, vk::MemoryUsage::kDeviceLocal,
                         "probe ray hits"));
  hits_ = std::move(hits);
  vk::DescriptorWriter(sets_.update_set())
      .buffer(gpu::kFieldUpdateBindingHits, hits_)
      .apply(context_.device());
  return ok_status();
}

Status IrradianceField::create_surfels() {
  const uint64_t rays = probe_count(params_) * (params_.rays_per_probe + params_.fixed_rays);
  DDGI_ASSIGN_OR_RETURN(surfels_,
                        vk::Buffer::create(context_, rays * sizeof(gpu::ProbeSurfel),
                                           VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                           vk::MemoryUsage::kDeviceLocal, "probe surfels"));
  vk::DescriptorWriter(sets_.update_set())
      .buffer(gpu::kFieldUpdateBindingSurfels, surfels_)
      .apply(context_.device());
  return ok_status();
}

Status IrradianceField::set_update_path(FieldUpdatePath path) {
  DDGI_TRY(check_path_fits(params_, path));
  if (path == FieldUpdatePath::kSplit && !shade_.valid()) DDGI_TRY(create_split_kernels());
  if (path == FieldUpdatePath::kSplit && !surfels_) DDGI_TRY(create_surfels());
  update_path_ = path;
  return ok_status();
}

Status IrradianceField::reset() {
  update_index_ = 0;
  volumes_.clear();
  entering_.clear();  // every probe starts over below
  unread_.clear();
  unread_serial_.reset();
  for (const FieldVolume& grid : field_volumes(params_)) {
    volumes_.push_back({grid, grid.origin, glm::ivec3(0), glm::ivec3(0)});
  }
  const uint32_t probes = static_cast<uint32_t>(probe_count(params_));
  std::vector<gpu::ProbeState> states(probes);
  for (gpu::ProbeState& s : states) s = {glm::vec3(0.0f), gpu::kProbeResetHistory};
  DDGI_TRY(vk::update_buffer(
      context_, probes_,
      {reinterpret_cast<const uint8_t*>(states.data()), states.size() * sizeof(states[0])}));
  scheduler_ = ProbeScheduler(probes);
  seen_moves_ = scene_.move_count();
  seen_revision_ = scene_.revision();
  sweep_left_ = params_.hot_updates;
  maintenance_cursor_ = 0;
  const Constants c = constants(DirectMode::kTracedShadows);
  DDGI_TRY(context_.submit_and_wait([&](VkCommandBuffer cmd) {
    vkCmdUpdateBuffer(cmd, constants_.handle(), 0, sizeof(c), c.data());
    const VkClearColorValue zero{};
    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    for (const vk::Image* image : {&irradiance_, &distance_}) {
      vk::transition_image(cmd, image->handle(), VK_IMAGE_LAYOUT_UNDEFINED,
                           VK_IMAGE_LAYOUT_GENERAL);
      vkCmdClearColorImage(cmd, image->handle(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
    }
    vkCmdFillBuffer(cmd, sh_.handle(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, drift_.handle(), 0, VK_WHOLE_SIZE, 0);
    vkCmdFillBuffer(cmd, zero_tile_.handle(), 0, VK_WHOLE_SIZE, 0);
    vk::barrier_all(cmd);
  }));
  if (params_.relocation_iterations == 0 && !params_.classification) return ok_status();
  std::vector<uint32_t> all(probes);
  for (uint32_t p = 0; p < probes; ++p) all[p] = p;
  return manage_probes(all, params_.relocation_iterations > 0, {});
}

Status IrradianceField::write_probe_list(const std::vector<uint32_t>& probes) {
  std::memcpy(probe_list_.mapped(), probes.data(), probes.size() * sizeof(uint32_t));
  probe_list_size_ = static_cast<uint32_t>(probes.size());
  return ok_status();
}

vk::Pass IrradianceField::linear_pass(const char* name, const vk::Kernel& kernel,
                                      const LinearWork& work, VkDescriptorSet shadow_set) const {
  const uint64_t count = uint64_t(work.probes) * work.per_probe;
  const vk::LinearDispatch d = vk::linear_dispatch(static_cast<uint32_t>(count));
  const gpu::FieldDispatch push{static_cast<uint32_t>(count),
                                d.row_width,
                                work.list_start,
                                std::max(work.list_size, 1u),
                                work.per_probe,
                                work.first_ray,
                                work.mode,
                                work.skip_settled};
  vk::Pass pass;
  pass.name = name;
  pass.group = vk::PassGroup::kIrradianceField;
  pass.kernel = &kernel;
  pass.sets = {scene_.descriptor_set(), sets_.update_set(), sets_.sampling_set()};
  if (shadow_set) pass.sets.push_back(shadow_set);
  pass.push_constants = vk::Pass::push(push);
  pass.size = d.size;
  return pass;
}

vk::Pass IrradianceField::probe_workgroup_pass(const char* name, const vk::Kernel& kernel,
                                               const LinearWork& work) const {
  const uint32_t row = std::min(work.probes, kProbeWorkgroupRow);
  const gpu::FieldDispatch push{work.probes, row, work.list_start,  std::max(work.list_size, 1u), 1,
                                0,           0,   work.skip_settled};
  vk::Pass pass;
  pass.name = name;
  pass.group = vk::PassGroup::kIrradianceField;
  pass.kernel = &kernel;
  pass.sets = {scene_.descriptor_set(), sets_.update_set(), sets_.sampling_set()};
  pass.push_constants = vk::Pass::push(push);
  pass.size = {row * kProbeWorkgroup.x, (work.probes + row - 1) / std::max(row, 1u), 1};
  return pass;
}

void IrradianceField::add_management_passes(std::vector<vk::Pass>& passes,
                                            const LinearWork& fixed_rays,
                                            uint32_t relocations) const {
  // (trace fixed rays, relocate) x relocations, trace fixed rays, classify.
  auto fixed_rays_then = [&](uint32_t mode) {
    passes.push_back(with_access(linear_pass("management trace", trace_, fixed_rays),
                                 {&probes_, &probe_list_, &irradiance_, &distance_, &sh_},
                                 {&rays_}));
    LinearWork manage = fixed_rays;
    manage.per_probe = 1;
    manage.mode = mode;
    passes.push_back(with_access(linear_pass("probe management", manage_, manage),
                                 {&rays_, &probe_list_}, {&probes_}));
  };
  for (uint32_t i = 0; i < relocations; ++i) fixed_rays_then(gpu::kProbeModeRelocate);
  if (params_.classification) fixed_rays_then(gpu::kProbeModeClassify);
}

Status IrradianceField::manage_probes(const std::vector<uint32_t>& probes, bool relocate,
                                      const std::vector<Bounds>& dynamic_regions) {
  if (probes.empty()) return ok_status();
  DDGI_TRY(write_probe_list(probes));
  probe_list_is_active_ = false;
  const uint32_t n = static_cast<uint32_t>(probes.size());
  const Constants c = constants(DirectMode::kTracedShadows);
  std::vector<vk::Pass> passes = {
      vk::upload_pass("field constants", vk::PassGroup::kIrradianceField, constants_, c)};
  add_management_passes(passes, {0, n, n, params_.fixed_rays},
                        relocate ? params_.relocation_iterations : 0);
  DDGI_TRY(context_.submit_and_wait(
      [&](VkCommandBuffer cmd) { vk::record_passes(cmd, nullptr, passes); }));
  if (!params_.classification) return ok_status();

  // The GPU's verdicts, then what only the CPU knows: probes near moving objects are Awake.
  DDGI_ASSIGN_OR_RETURN(std::vector<gpu::ProbeState> states, read_probe_slots());
  std::vector<uint8_t> verdicts = scheduler_.states();
  bool relabelled = false;
  for (uint32_t p : probes) {
    uint32_t state = (states[p].flags & gpu::kProbeStateMask) >> gpu::kProbeStateShift;
    const glm::vec3 position = grid_point(p) + states[p].offset;
    for (const Bounds& region : dynamic_regions) {
      const bool inside = glm::all(glm::greaterThanEqual(position, region.min)) &&
                          glm::all(glm::lessThanEqual(position, region.max));
      if (inside && state != gpu::kProbeOff) state = gpu::kProbeAwake;
    }
    const uint32_t before = verdicts[p];
    const bool was_active = before == gpu::kProbeVigilant || before == gpu::kProbeAwake;
    const bool is_active = state == gpu::kProbeVigilant || state == gpu::kProbeAwake;
    // A probe that starts being traced has no valid history (2021 paper: Newly Awake/Vigilant).
    if (is_active && !was_active) states[p].flags |= gpu::kProbeResetHistory;
    const uint32_t flags =
        (states[p].flags & ~gpu::kProbeStateMask) | (state << gpu::kProbeStateShift);
    relabelled = relabelled || flags != states[p].flags;
    states[p].flags = flags;
    verdicts[p] = static_cast<uint8_t>(state);
  }
  scheduler_.set_states(verdicts);
  if (!relabelled) return ok_status();
  return vk::update_buffer(
      context_, probes_,
      {reinterpret_cast<const uint8_t*>(states.data()), states.size() * sizeof(states[0])});
}

Status require_one_volume(const IrradianceField& field, const std::string& what) {
  const size_t volumes = field.volumes().size();
  if (volumes == 1) return ok_status();
  return failed_precondition(what + " of a field of " + std::to_string(volumes) +
                             " volumes is not supported yet: per-volume streams are not built "
                             "(docs/cascades.md; DumpAtlas dumps one volume at a time); use "
                             "cascades=1 and no static_volumes");
}

uint32_t IrradianceField::volume_of(uint32_t slot) const {
  uint32_t v = 0;
  while (v + 1 < volumes_.size() && slot >= volumes_[v + 1].grid.first_probe) ++v;
  return v;
}

glm::vec3 IrradianceField::grid_point(uint32_t slot) const {
  const VolumeState& v = volumes_[volume_of(slot)];
  const FieldVolume& g = v.grid;
  return g.origin + g.spacing * glm::vec3(probe_coord(g.counts, v.scroll, slot - g.first_probe));
}

std::vector<FieldVolume> IrradianceField::volumes() const {
  std::vector<FieldVolume> grids;
  for (const VolumeState& v : volumes_) grids.push_back(v.grid);
  return grids;
}

Result<FieldVolume> IrradianceField::volume(uint32_t index) const {
  if (index >= volumes_.size()) {
    return invalid_argument("volume " + std::to_string(index) + ": the field has " +
                            std::to_string(volumes_.size()) + " volume(s), 0 to " +
                            std::to_string(volumes_.size() - 1) +
                            " (FieldParams.volumes lists them)");
  }
  return volumes_[index].grid;
}

bool IrradianceField::scrolled() const {
  return std::any_of(volumes_.begin(), volumes_.end(),
                     [](const VolumeState& v) { return v.scroll != glm::ivec3(0); });
}

Status IrradianceField::prepare() {
  collect_scroll_verdicts();
  // Adaptive rays: any change of the scene (lights, objects, environment) may change any
  // probe's light; the next hot_updates updates trace them all, and their drifts decide which
  // stay hot.
  if (scene_.revision() != seen_revision_) {
    seen_revision_ = scene_.revision();
    sweep_left_ = params_.hot_updates;
  }
  if (scene_.move_count() == seen_moves_) return ok_status();
  bool everything = false;
  std::vector<Bounds> regions = scene_.moved_regions(seen_moves_, &everything);
  seen_moves_ = scene_.move_count();
  if (!params_.classification) return ok_status();
  const uint32_t probes = static_cast<uint32_t>(probe_count(params_));
  std::vector<uint32_t> affected;
  if (everything) {
    for (uint32_t p = 0; p < probes; ++p) affected.push_back(p);
    regions = {scene_.bounds()};
  } else {
    // Grow each region by a cell and the self-shadow bias (2021 paper, fig. 10): probes that
    // can be in the cage of a point on the moved object, before and after the move; per
    // volume, since cells differ. The coarsest volume's growth marks probes Awake (the most).
    const std::vector<Bounds> moved = regions;
    for (const VolumeState& v : volumes_) {
      const FieldVolume& g = v.grid;
      const float min_spacing = std::min({g.spacing.x, g.spacing.y, g.spacing.z});
      const glm::vec3 grow = g.spacing + glm::vec3(0.75f * min_spacing * params_.self_shadow_bias);
      regions = moved;
      for (Bounds& r : regions) {
        r.min -= grow;
        r.max += grow;
      }
      // The probe may sit up to the offset limit from its grid point.
      const glm::vec3 slack = params_.probe_offset_limit * g.spacing;
      const uint32_t end = g.first_probe + static_cast<uint32_t>(grid_probe_count(g.counts));
      for (uint32_t p = g.first_probe; p < end; ++p) {
        const glm::vec3 grid = grid_point(p);
        const bool near = std::any_of(regions.begin(), regions.end(), [&](const Bounds& r) {
          return glm::all(glm::greaterThanEqual(grid + slack, r.min)) &&
                 glm::all(glm::lessThanEqual(grid - slack, r.max));
        });
        if (near) affected.push_back(p);
      }
    }
  }
  // Probes are not relocated around moving geometry: that would make them unstable (2021
  // paper, sec. 5); they are reclassified where it moved.
  return manage_probes(affected, false, regions);
}

Result<std::vector<gpu::ProbeState>> IrradianceField::read_probe_slots() {
  std::vector<gpu::ProbeState> states(probe_count(params_));
  DDGI_TRY(vk::download_buffer(context_, probes_, states.data(),
                               states.size() * sizeof(gpu::ProbeState)));
  return states;
}

Result<std::vector<gpu::ProbeState>> IrradianceField::read_probe_states() {
  DDGI_ASSIGN_OR_RETURN(std::vector<gpu::ProbeState> states, read_probe_slots());
  return in_grid_order(std::move(states));
}

Status IrradianceField::set_params(const IrradianceFieldParams& params) {
  DDGI_TRY(validate(params));
  DDGI_TRY(check_path_fits(params, update_path_));
  DDGI_TRY(create_path_kernels(params.probe_bounces > 0));  // before anything changes
  const IrradianceFieldParams old = params_;
  const bool rebuild = grid_changed(old, params);
  // probe_bounces alone changes which hit records the update needs, not the grid's resources.
  if (!rebuild && probe_ray_hit_records(params) != probe_ray_hit_records(old)) {
    DDGI_TRY(check_budget(context_, params, gpu_bytes_));
    const uint64_t before = context_.allocated_bytes();
    DDGI_TRY(create_hits(params));
    gpu_bytes_ = gpu_bytes_ + context_.allocated_bytes() - before;  // the old records freed
  }
  DDGI_TRY(replace_params<IrradianceFieldParams>(
      params_, params, rebuild,
      [&](const IrradianceFieldParams& next) { return check_budget(context_, next, gpu_bytes_); },
      [&] { return create_resources(); }));
  if (old.origin != params.origin || old.spacing != params.spacing ||
      old.cascade_spacing_ratio != params.cascade_spacing_ratio) {
    return reset();  // the volumes are placed anew
  }
  // Drifts were not kept while adaptive rays were off: every probe is measured anew.
  if (old.settle_threshold != params.settle_threshold) sweep_left_ = params_.hot_updates;
  return ok_status();
}

IrradianceField::Constants IrradianceField::constants(DirectMode direct_mode) const {
  Constants all{};
  gpu::FieldConstants c{};
  c.probe_count = static_cast<uint32_t>(probe_count(params_));
  c.rays_per_probe = params_.rays_per_probe;
  c.fixed_rays = params_.fixed_rays;
  c.irradiance_texels = params_.irradiance_texels;
  c.distance_texels = params_.distance_texels;
  c.tiles_per_row = layout_.tiles_per_row;
  c.update_index = static_cast<uint32_t>(update_index_);
  c.irradiance_atlas_size = glm::vec2(layout_.irradiance_size);
  c.distance_atlas_size = glm::vec2(layout_.distance_size);
  c.hysteresis = std::min(params_.hysteresis, hysteresis_cap_);
  c.distance_hysteresis = params_.distance_hysteresis;
  c.change_threshold = params_.change_threshold;
  c.new_distribution_threshold = params_.new_distribution_threshold;
  c.irradiance_gamma = params_.irradiance_gamma;
  c.distance_exponent = params_.distance_exponent;
  c.backface_distance_scale = params_.backface_distance_scale;
  c.self_shadow_bias = params_.self_shadow_bias;
  c.energy_conservation = params_.energy_conservation;
  c.weight_crush_threshold = params_.weight_crush_threshold;
  c.max_ray_distance = params_.max_ray_distance;
  c.ray_rotation = random_rotation(params_.seed, update_index_);
  c.direct_mode = static_cast<uint32_t>(direct_mode);
  c.probe_offset_limit = params_.probe_offset_limit;
  c.backface_threshold = params_.backface_threshold;
  c.emitter_samples = params_.emitter_samples;
  c.basis = static_cast<uint32_t>(params_.basis);
  const std::array<float, 3> bands = sh_band_scales(params_);
  c.sh_band1 = bands[1];
  c.sh_band2 = bands[2];
  c.probe_bounces = params_.probe_bounces;
  c.settle_threshold = params_.settle_threshold;
  c.hot_updates = params_.hot_updates;
  c.maintenance_start = maintenance_.start;
  c.maintenance_count = maintenance_.count;
  c.volume_count = static_cast<uint32_t>(volumes_.size());
  // What differs between volumes: the grid and what scales with its spacing.
  for (size_t v = 0; v < volumes_.size(); ++v) {
    gpu::FieldConstants& volume = all[v];
    volume = c;
    const FieldVolume& g = volumes_[v].grid;
    volume.origin = g.origin;
    volume.spacing = g.spacing;
    volume.counts = g.counts;
    volume.scroll = volumes_[v].scroll;
    volume.first_probe = g.first_probe;
    volume.max_visibility_distance = visibility_range(g.spacing);
    volume.min_frontface_distance =
        params_.min_frontface_distance * std::min({g.spacing.x, g.spacing.y, g.spacing.z});
    std::tie(volume.blend_min, volume.blend_max) = blend_box(g);
    volume.blend_cell = g.spacing;
  }
  return all;
}

std::pair<glm::vec3, glm::vec3> IrradianceField::blend_box(const FieldVolume& g) const {
  const glm::vec3 half_cells = 0.5f * glm::vec3(g.counts - 1);
  if (g.tracks(params_) && tracked_camera_) {
    // Centred on the camera, tightened by two cells from the grid's half extent (2021 paper,
    // sec. 7.3): with the grid's centre within a cell of the camera, the weight is 0 before the
    // grid's edge however the grid last leapfrogged, so a scroll changes no weight.
    const glm::vec3 half = g.spacing * glm::max(half_cells - 2.0f, glm::vec3(0.0f));
    return {*tracked_camera_ - half, *tracked_camera_ + half};
  }
  // The grid shrunk by a cell: the weight is 0 on its outer probe planes, where cages end.
  const glm::vec3 inset = g.spacing * glm::min(glm::vec3(1.0f), half_cells);
  return {g.origin + inset, g.origin + g.spacing * glm::vec3(g.counts - 1) - inset};
}

uint64_t IrradianceField::rays_per_update() const {
  // Every blended ray is lit: one shadow ray per traced light each.
  return last_update_probe_rays() * (1 + last_update_traced_lights_);
}

uint32_t IrradianceField::traced_lights(DirectMode direct_mode) const {
  const uint32_t lights = static_cast<uint32_t>(scene_.scene().lights.size());
  if (direct_mode == DirectMode::kUnshadowed) return 0;
  if (!uses_shadow_field(direct_mode) || !shadow_field_) return lights;
  if (shadow_field_->params().overflow != ShadowOverflow::kTracedShadows) return 0;
  return lights - std::min(lights, shadow_field_->kept_lights());
}

std::vector<vk::Pass> IrradianceField::update_passes(DirectMode frame_mode) {
  const DirectMode direct_mode = probe_mode(frame_mode);
  if (scheduler_.take_active_changed() || !probe_list_is_active_) {
    (void)write_probe_list(scheduler_.active());
    probe_list_is_active_ = true;
  }
  const ProbeScheduler::Window window = scheduler_.next_window(budget_probes());
  last_update_traced_lights_ = traced_lights(direct_mode);
  const bool adaptive = params_.settle_threshold > 0.0f;
  last_update_rays_ = {
      window.start,       probe_list_size_,  window.count, params_.rays_per_probe, 0,
      params_.fixed_rays, adaptive ? 1u : 0u};
  maintenance_ = adaptive ? next_maintenance_slice(probe_list_size_) : Slice{};
  maintenance_cursor_ += maintenance_.count;
  if (sweep_left_ > 0) --sweep_left_;

  std::vector<vk::Pass> passes = {vk::upload_pass(
      "field constants", vk::PassGroup::kIrradianceField, constants_, constants(direct_mode))};
  add_start_passes(passes);  // of the probes a scroll (track()) brought in
  add_lighting_passes(passes, last_update_rays_, direct_mode);
  ++update_index_;
  return passes;
}

IrradianceField::Slice IrradianceField::next_maintenance_slice(uint32_t list_size) const {
  const uint32_t list = std::max(list_size, 1u);
  const uint32_t count =
      sweep_left_ > 0
          ? list
          : std::clamp(static_cast<uint32_t>(std::ceil(params_.maintenance_rate * list)), 1u, list);
  return {maintenance_cursor_ % list, count};
}

Result<std::vector<uint8_t>> IrradianceField::probes_lit_by_next_update() {
  DDGI_TRY(prepare());
  const std::vector<uint32_t>& active = scheduler_.active();
  ProbeScheduler preview = scheduler_;  // the window without advancing the real scheduler
  const ProbeScheduler::Window window = preview.next_window(budget_probes());
  DDGI_ASSIGN_OR_RETURN(std::vector<gpu::ProbeState> states, read_probe_slots());
  const uint32_t list = static_cast<uint32_t>(active.size());
  const bool adaptive = params_.settle_threshold > 0.0f;
  const Slice slice = next_maintenance_slice(list);
  std::vector<uint8_t> lit(states.size(), 0);
  for (uint32_t i = 0; i < window.count; ++i) {
    const uint32_t index = (window.start + i) % list;
    const bool in_slice = (index + list - slice.start) % list < slice.count;
    const uint32_t flags = states[active[index]].flags;
    const bool hot = (flags & (gpu::kProbeResetHistory | gpu::kProbeHeatMask)) != 0;
    lit[active[index]] = !adaptive || in_slice || hot ? 1 : 0;
  }
  return in_grid_order(std::move(lit));
}

void IrradianceField::add_lighting_passes(std::vector<vk::Pass>& passes, const LinearWork& rays,
                                          DirectMode direct_mode) const {
  const bool reads_shadow_field = shadow_field_ && uses_shadow_field(direct_mode);
  const VkDescriptorSet shadow_set =
      reads_shadow_field ? shadow_field_->sampling_set() : VK_NULL_HANDLE;
  auto per_probe = [&](uint32_t items) {
    LinearWork work = rays;
    work.per_probe = items;
    return work;
  };
  if (update_path_ == FieldUpdatePath::kFused) {
    const bool paths = params_.probe_bounces > 0;
    const vk::Kernel& trace =
        reads_shadow_field ? (paths ? trace_with_shadow_field_paths_ : trace_with_shadow_field_)
                           : (paths ? trace_paths_ : trace_);
    passes.push_back(with_access(linear_pass("field trace", trace, rays, shadow_set),
                                 {&probes_, &probe_list_, &irradiance_, &distance_, &sh_},
                                 {&rays_, &hits_}));
    if (!paths) {
      passes.push_back(with_access(
          linear_pass("field hit light", hit_light_, rays),
          {&rays_, &hits_, &probes_, &probe_list_, &irradiance_, &distance_, &sh_}, {&rays_}));
    }
    if (params_.basis == ProbeBasis::kSh) {
      passes.push_back(with_access(probe_workgroup_pass("field blend", blend_sh_, rays),
                                   {&rays_, &probes_, &sh_}, {&sh_, &probes_}));
      return;
    }
    passes.push_back(with_access(probe_workgroup_pass("field blend", blend_, rays),
                                 {&rays_, &probes_, &drift_},
                                 {&irradiance_, &distance_, &probes_, &drift_}));
    return;
  }
  const uint32_t ti = params_.irradiance_texels, td = params_.distance_texels;
  const vk::Kernel& shade = reads_shadow_field ? shade_with_shadow_field_ : shade_;
  passes.push_back(with_access(linear_pass("field trace", trace_surfels_, rays),
                               {&probes_, &probe_list_}, {&surfels_}));
  passes.push_back(with_access(linear_pass("field shade", shade, rays, shadow_set),
                               {&surfels_, &irradiance_, &distance_, &sh_}, {&rays_}));
  if (params_.basis == ProbeBasis::kSh) {
    passes.push_back(with_access(probe_workgroup_pass("field blend", blend_sh_, rays),
                                 {&rays_, &probes_, &sh_}, {&sh_, &probes_}));
    return;
  }
  passes.push_back(
      with_access(linear_pass("blend irradiance", blend_irradiance_, per_probe(ti * ti)),
                  {&rays_, &probes_}, {&irradiance_}));
  passes.push_back(with_access(linear_pass("blend distance", blend_distance_, per_probe(td * td)),
                               {&rays_, &probes_}, {&distance_, &probes_}));
  passes.push_back(
      with_access(linear_pass("borders", borders_, per_probe(4 * (std::max(ti, td) + 1))), {},
                  {&irradiance_, &distance_}));
}

Result<std::vector<vk::Pass>> IrradianceField::raw_trace_passes() {
  if (!raw_trace_.valid()) {
    DDGI_ASSIGN_OR_RETURN(raw_trace_, update_kernel("field_raw_trace", true, kLinearWorkgroup));
  }
  vk::Pass pass = with_access(linear_pass("field raw trace", raw_trace_, last_update_rays_),
                              {&probes_, &probe_list_}, {&rays_});
  pass.group = vk::PassGroup::kBaseline;
  return std::vector<vk::Pass>{pass};
}

Result<std::vector<vk::PassTime>> IrradianceField::update(uint32_t count, DirectMode direct_mode) {
  DDGI_TRY(prepare());
  for (uint32_t i = 0; i < count; ++i) {
    const std::vector<vk::Pass> passes = update_passes(direct_mode);
    DDGI_TRY(context_.submit_and_wait([&](VkCommandBuffer cmd) {
      sets_.timer().begin_frame(cmd);
      vk::record_passes(cmd, &sets_.timer(), passes);
    }));
    adopt_scroll_verdicts();  // of a scroll this update started: its submission is done
  }
  context_.collect_garbage();
  return sets_.timer().read();
}

Status IrradianceField::warm_up(uint32_t count, DirectMode direct_mode) {
  const uint32_t fast = count - count / 4;
  hysteresis_cap_ = 0.5f;
  const auto converged = update(fast, direct_mode);
  hysteresis_cap_ = 1.0f;
  if (!converged.ok()) return converged.error();
  const auto settled = update(count - fast, direct_mode);
  return settled.ok() ? ok_status() : Status(settled.error());
}

Result<std::vector<glm::vec3>> IrradianceField::query(const std::vector<IrradianceQuery>& queries,
                                                      std::optional<uint32_t> volume) {
  if (volume) {
    const Result<FieldVolume> chosen = this->volume(*volume);
    if (!chosen.ok()) return chosen.error();
  }
  const uint32_t mode = volume ? gpu::kQueryVolume0 + *volume : gpu::kQueryBlended;
  std::vector<gpu::FieldQuery> input;
  for (const IrradianceQuery& q : queries) {
    input.push_back(
        {q.position, 0.0f, glm::normalize(q.normal), 0.0f, glm::normalize(q.to_viewer), 0.0f});
  }
  DDGI_ASSIGN_OR_RETURN(
      const std::vector<glm::vec4> answers,
      (sets_.query<gpu::FieldQuery, glm::vec4>(input, [mode](uint32_t count, uint32_t row_width) {
        return vk::Pass::push(gpu::FieldDispatch{count, row_width, 0, 1, 1, 0, mode, 0});
      })));
  std::vector<glm::vec3> result;
  for (const glm::vec4& a : answers) result.push_back(glm::vec3(a));
  return result;
}

Result<IrradianceField::AtlasImage> IrradianceField::read_atlas(const vk::Image& image,
                                                                uint32_t channels,
                                                                uint32_t texels) {
  if (params_.basis != ProbeBasis::kOctahedral) {
    return failed_precondition("the field's probes are SH coefficients, not octahedral maps");
  }
  AtlasImage slots;
  slots.width = image.width();
  slots.height = image.height();
  slots.channels = channels;
  slots.texels.resize(size_t(slots.width) * slots.height * channels);
  DDGI_TRY(vk::download_image(context_, image, slots.texels.data(),
                              slots.texels.size() * sizeof(float)));
  if (!scrolled()) return slots;
  // Tile g of the result is the tile of the probe at grid index g.
  AtlasImage grid = slots;
  const uint32_t side = texels + 2 * gpu::kAtlasBorder;
  const size_t row_values = size_t(side) * channels;
  auto tile_start = [&](uint32_t tile) {
    return (size_t(tile / layout_.tiles_per_row) * side * slots.width +
            size_t(tile % layout_.tiles_per_row) * side) *
           channels;
  };
  const std::vector<uint32_t> order = slots_in_grid_order();
  for (uint32_t g = 0; g < order.size(); ++g) {
    for (uint32_t y = 0; y < side; ++y) {
      const size_t row = size_t(y) * slots.width * channels;
      std::copy_n(slots.texels.begin() + tile_start(order[g]) + row, row_values,
                  grid.texels.begin() + tile_start(g) + row);
    }
  }
  return grid;
}

std::vector<uint32_t> IrradianceField::slots_in_grid_order() const {
  std::vector<uint32_t> order;
  order.reserve(probe_count(params_));
  for (const VolumeState& v : volumes_) {
    const FieldVolume& g = v.grid;
    const uint32_t probes = static_cast<uint32_t>(grid_probe_count(g.counts));
    for (uint32_t local = 0; local < probes; ++local) {
      order.push_back(g.first_probe +
                      probe_slot(g.counts, v.scroll, probe_coord(g.counts, glm::ivec3(0), local)));
    }
  }
  return order;
}

template <typename T>
std::vector<T> IrradianceField::in_grid_order(std::vector<T> per_slot) const {
  if (!scrolled()) return per_slot;
  const std::vector<uint32_t> order = slots_in_grid_order();
  std::vector<T> per_probe(per_slot.size());
  for (size_t g = 0; g < order.size(); ++g) per_probe[g] = per_slot[order[g]];
  return per_probe;
}

std::vector<float> sh_coefficient_values(const std::vector<gpu::ShProbe>& probes) {
  std::vector<float> values;
  values.reserve(probes.size() * 27);
  for (const gpu::ShProbe& probe : probes) {
    for (const glm::vec3& c : probe.coefficients) values.insert(values.end(), {c.x, c.y, c.z});
  }
  return values;
}

Result<std::vector<gpu::ShProbe>> IrradianceField::read_sh_probes() {
  if (params_.basis != ProbeBasis::kSh) {
    return failed_precondition("the field's probes are octahedral maps, not SH coefficients");
  }
  std::vector<gpu::ShProbe> probes(probe_count(params_));
  DDGI_TRY(vk::download_buffer(context_, sh_, probes.data(), probes.size() * sizeof(gpu::ShProbe)));
  return in_grid_order(std::move(probes));
}

Result<IrradianceField::AtlasImage> IrradianceField::read_irradiance_atlas() {
  return read_atlas(irradiance_, 4, params_.irradiance_texels);
}

Result<IrradianceField::AtlasImage> IrradianceField::read_distance_atlas() {
  return read_atlas(distance_, 2, params_.distance_texels);
}

}  // namespace ddgi
