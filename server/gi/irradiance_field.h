// One DDGI irradiance field: its probe grid, the irradiance and distance atlases it owns
// (persistent history) or, with the SH basis, the probes' SH coefficients (docs/sh-probes.md),
// the probe-ray buffer, and the kernels of one update:
//   fused (the default): trace + shade -> blend both maps and their borders, per probe;
//   split (the reference the fused update is tested against, and the benchmark's comparison):
//   trace -> shade -> blend irradiance -> blend distance -> borders, per ray and per texel.
// Frame kernels sample it through descriptor set 2 (shaders/shared/field_data.h).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/result.h"
#include "gi/field_params.h"
#include "gi/field_sets.h"
#include "gi/probe_scheduler.h"
#include "gi/shadow_field.h"
#include "gpu_scene/frame_types.h"
#include "gpu_scene/gpu_scene.h"
#include "shared/field_data.h"
#include "vk/context.h"
#include "vk/pass.h"
#include "vk/pipeline.h"
#include "vk/resources.h"
#include "vk/timer.h"

namespace ddgi {

struct IrradianceQuery {
  glm::vec3 position{0.0f};
  glm::vec3 normal{0.0f, 1.0f, 0.0f};
  glm::vec3 to_viewer{0.0f, 1.0f, 0.0f};  // the self-shadow bias leans this way
};

// The coefficients of SH probes as plain floats: 27 per probe (nine RGB), in probe order, as the
// dumps and the probe stream send them.
std::vector<float> sh_coefficient_values(const std::vector<gpu::ShProbe>& probes);

// How an update is split into passes; both give the same atlases (tests/gpu/field_update_test).
enum class FieldUpdatePath {
  kFused,  // field_trace (trace + shade), field_blend (per probe, borders included)
  kSplit,  // field_trace_surfels, field_shade, field_blend_irradiance/_distance, field_borders
};

class IrradianceField;
// Probe streams describe one grid: FAILED_PRECONDITION naming `what` for a field of several
// volumes (cascades, static volumes), whose per-volume streams are not built yet
// (docs/cascades.md).
Status require_one_volume(const IrradianceField& field, const std::string& what);

class IrradianceField {
 public:
  // `shadow_field` (optional, must outlive the field): what probe-ray hits read in the
  // shadow-field and AO direct modes; without one those modes trace shadow rays there. The
  // caller updates it (before this field's updates, so that they read its newest state).
  static Result<std::unique_ptr<IrradianceField>> create(vk::Context& context, GpuScene& scene,
                                                         const IrradianceFieldParams& params,
                                                         vk::TraceBackend backend,
                                                         const ShadowField* shadow_field = nullptr);

  const IrradianceFieldParams& params() const { return params_; }
  // Applies new parameters. Changes of the grid, ray or texel counts rebuild the atlases and
  // start the field over; other changes keep its history.
  Status set_params(const IrradianceFieldParams& params);
  // Drops all history: every probe starts over at its next update.
  Status reset();

  // The field's volumes as they are now, finest first (docs/cascades.md): the grid of params()
  // and its cascades, and the static volumes (FieldVolume says which is which).
  std::vector<FieldVolume> volumes() const;
  // Volume `index` as it is now, or an error naming how many volumes there are.
  Result<FieldVolume> volume(uint32_t index) const;
  // Moves `volume` by `cells` whole cells (its origin by cells x spacing) as a 3D circular
  // buffer (docs/cascades.md): probes whose world position stays keep their slot, maps and
  // state bit for bit; the planes that leave are re-initialised on the other side (maps
  // cleared, history reset, relocated and classified) and traced by the next update. A move of
  // the whole grid or more starts the volume over. `start`: at once, in a submission of its own
  // waited for, or in the next update's passes (as track() does).
  enum class ScrollStart { kNow, kInNextUpdate };
  Status scroll(uint32_t volume, glm::ivec3 cells, ScrollStart start = ScrollStart::kNow);
  // The circular buffer's phase of `volume` (FieldConstants::scroll).
  glm::ivec3 scroll_phase(uint32_t volume = 0) const { return volumes_.at(volume).scroll; }
  // A tracking field (track_camera) follows `camera`: every cascade scrolls back around it
  // (static volumes stay), and the cascades' blend boxes are centred on it from the next update
  // on. The entering probes start in the next update's passes (update_passes()), in the same
  // submission: no GPU work and no wait here. Does nothing to a field that does not track.
  void track(glm::vec3 camera);
  // Whether track(camera) would scroll a volume (the tools mark such frames).
  bool tracking_would_scroll(glm::vec3 camera) const;

  // Brings probe states up to date with moved geometry (reclassifies probes near moved
  // instances, waking sleeping ones). Call before recording updates; it submits GPU work.
  Status prepare();
  // The mode probe-ray hits are lit in when the frame (or caller) runs the field in
  // `frame_mode`: the probe_direct parameter if set, else `frame_mode`.
  DirectMode probe_mode(DirectMode frame_mode) const {
    return params_.probe_direct.value_or(frame_mode);
  }
  // The passes of one update: the next window of active probes (all of them unless
  // max_rays_per_update caps it), lit in probe_mode(frame_mode). Building the list advances the
  // field (probe window, update index): record every list built, once, in order.
  std::vector<vk::Pass> update_passes(DirectMode frame_mode);
  // Whether the next prepare() + update_passes() may write the host-visible probe list (moved
  // geometry, probe states changed since the last update, or a scroll's states not taken yet:
  // prepare() takes them once their submission completed, which can come true between this
  // call and that one). An earlier update of this field still in flight reads that list: a
  // caller that pipelines frames finishes it first.
  bool next_update_rewrites_probe_list() const {
    return scene_.move_count() != seen_moves_ || scheduler_.active_changed() ||
           !probe_list_is_active_ || !unread_.empty();
  }
  // Chooses the passes of later updates (the split path allocates its surfel buffer here).
  Status set_update_path(FieldUpdatePath path);
  FieldUpdatePath update_path() const { return update_path_; }
  // The benchmark's baseline: the last update's blended rays traced again by a kernel that only
  // records hit distances (shaders/gi/field_raw_trace.glsl). It overwrites the ray buffer,
  // which the next update writes before reading. Its kernel is built on the first call: only
  // the benchmark asks.
  Result<std::vector<vk::Pass>> raw_trace_passes();
  // The probes the next update will trace, 1 per probe in grid order (the rest 0): the next
  // window's probes, and with adaptive rays (settle_threshold > 0) of those the hot ones, those
  // without history and the maintenance slice, from the probe states on the GPU (waits for the
  // GPU: tools and tests).
  Result<std::vector<uint8_t>> probes_lit_by_next_update();
  // Runs `count` updates, each its own submission; returns the pass times of the last.
  Result<std::vector<vk::PassTime>> update(uint32_t count, DirectMode direct_mode);
  // Converges a new field quickly: three quarters of `count` updates at hysteresis <= 0.5, so
  // light propagates one bounce per update without lag (a high-albedo room needs hundreds of
  // updates at 0.97), then the rest at the configured hysteresis to settle the noise.
  Status warm_up(uint32_t count, DirectMode direct_mode);

  // Field irradiance M (= E / pi) at arbitrary points: blended over the volumes as frames
  // sample it, or from `volume` alone (clamped to its grid); an error names a volume past the
  // field's.
  Result<std::vector<glm::vec3>> query(const std::vector<IrradianceQuery>& queries,
                                       std::optional<uint32_t> volume = std::nullopt);

  // The readers below give every probe's data in grid order (index x + counts.x * (y +
  // counts.y * z) from the origin, atlas tile by tile), whatever slots a scrolling field keeps
  // them in: what dumps, streams and clients index by.
  struct AtlasImage {
    uint32_t width = 0;
    uint32_t height = 0;
    uint32_t channels = 0;  // 4: irradiance RGBA (encoded), 2: distance (mean, mean square)
    std::vector<float> texels;
  };
  Result<AtlasImage> read_irradiance_atlas();
  Result<AtlasImage> read_distance_atlas();
  // Every probe's SH coefficients (SH fields only; the atlas reads are for octahedral ones).
  Result<std::vector<gpu::ShProbe>> read_sh_probes();

  VkDescriptorSetLayout sampling_layout() const { return sets_.sampling_layout(); }
  VkDescriptorSet sampling_set() const { return sets_.sampling_set(); }
  uint64_t gpu_bytes() const { return gpu_bytes_; }
  uint64_t updates() const { return update_index_; }
  ProbeStateCounts probe_counts() const { return scheduler_.counts(); }
  const ProbeScheduler& scheduler() const { return scheduler_; }
  // Every probe's offset and flags (state in bits 8..15), for dumps and tests.
  Result<std::vector<gpu::ProbeState>> read_probe_states();
  // Probe rays the last recorded update traced (its blended rays: the fixed rays are traced
  // only by probe management). With adaptive rays, what its window allowed: settled probes
  // outside the maintenance slice end at once (probes_lit_by_next_update() counts the rest).
  uint64_t last_update_probe_rays() const {
    return uint64_t(last_update_rays_.probes) * last_update_rays_.per_probe;
  }
  // Rays traced by the last update: probe rays plus one shadow ray per traced light per shaded
  // ray (not the path vertices of probe_bounces, whose number is random).
  uint64_t rays_per_update() const;

 private:
  IrradianceField(vk::Context& context, GpuScene& scene, const ShadowField* shadow_field)
      : context_(context), scene_(scene), shadow_field_(shadow_field) {}
  Status create_layouts_and_kernels(vk::TraceBackend backend);
  Status create_resources();
  Status create_surfels();
  // The hit records of `params` (probe_ray_hit_records), replacing the held ones.
  Status create_hits(const IrradianceFieldParams& params);
  // The split path's kernels, built when it is first chosen (the service never uses it).
  Status create_split_kernels();
  // The fused trace with paths from each hit, built the first time they are `wanted`
  // (probe_bounces > 0).
  Status create_path_kernels(bool wanted);
  // The split path has no path-tracing form: FAILED_PRECONDITION for that pair.
  static Status check_path_fits(const IrradianceFieldParams& params, FieldUpdatePath path);
  // A kernel of the update set's layouts (+ the shadow field's sampling set as set 3).
  Result<vk::Kernel> update_kernel(const char* name, bool traces, glm::uvec3 workgroup,
                                   bool reads_shadow_field = false) const;
  // Every volume's constants (the unused entries zero).
  using Constants = std::array<gpu::FieldConstants, gpu::kMaxFieldVolumes>;
  Constants constants(DirectMode direct_mode) const;
  // Where volume v's blend weight is 1 (FieldConstants::blend_min/max).
  std::pair<glm::vec3, glm::vec3> blend_box(const FieldVolume& volume) const;
  // Lights whose visibility probe-ray hits trace in `direct_mode` (the rest read the shadow
  // field or are unshadowed).
  uint32_t traced_lights(DirectMode direct_mode) const;
  // Moves probes out of geometry and classifies them, for the probes in `probes` (all of them
  // at initialisation, those near moved geometry later). `relocate`: run the relocation passes
  // first. `dynamic_regions`: where moving objects are; active probes there are Awake.
  Status manage_probes(const std::vector<uint32_t>& probes, bool relocate,
                       const std::vector<Bounds>& dynamic_regions);
  Status write_probe_list(const std::vector<uint32_t>& probes);
  // The volume that owns `slot`, and the slot's grid point (no relocation offset).
  uint32_t volume_of(uint32_t slot) const;
  glm::vec3 grid_point(uint32_t slot) const;
  // Scrolling (field_scroll.cpp). Moves `volume` by `cells` (its origin and phase) and appends
  // the slots of the probes that entered to `entering`; a move of the whole grid or more enters
  // them all.
  void move_volume(uint32_t volume, glm::ivec3 cells, std::vector<uint32_t>& entering);
  // The volumes tracking `camera` would scroll, with their cells (track() and
  // tracking_would_scroll() decide alike).
  std::vector<std::pair<uint32_t, glm::ivec3>> tracking_scrolls(glm::vec3 camera) const;
  // The start of the probes in entering_ (maps cleared, no offset, history reset, relocated,
  // classified, states copied for the CPU), after the constants of their new place; they move
  // to unread_.
  void add_start_passes(std::vector<vk::Pass>& passes);
  vk::Pass clear_maps_pass(const std::vector<uint32_t>& slots) const;
  vk::Pass copy_states_pass(const std::vector<uint32_t>& slots) const;  // to scroll_states_
  // The scheduler takes the unread_ probes' states from scroll_states_: once the submission
  // that started them completed (collect: checks; adopt: the caller knows).
  void collect_scroll_verdicts();
  void adopt_scroll_verdicts();
  bool scrolled() const;
  // One invocation per (probe, item) over `probes` entries of the probe list from `list_start`.
  struct LinearWork {
    uint32_t list_start = 0;
    uint32_t list_size = 0;
    uint32_t probes = 0;
    uint32_t per_probe = 0;
    uint32_t mode = 0;          // kProbeMode* of the probe-management kernel
    uint32_t first_ray = 0;     // of the tracing kernels
    uint32_t skip_settled = 0;  // FieldDispatch::skip_settled (an adaptive update's lighting)
  };
  // `shadow_set`: bound as set 3 when not null (the lighting kernels' shadow-field variants).
  vk::Pass linear_pass(const char* name, const vk::Kernel& kernel, const LinearWork& work,
                       VkDescriptorSet shadow_set = VK_NULL_HANDLE) const;
  // One workgroup per probe of `work` (field_blend).
  vk::Pass probe_workgroup_pass(const char* name, const vk::Kernel& kernel,
                                const LinearWork& work) const;
  // The lighting passes of one update over `rays` (fused or split path).
  void add_lighting_passes(std::vector<vk::Pass>& passes, const LinearWork& rays,
                           DirectMode direct_mode) const;
  // (Relocation passes x `relocations`, classification) over the probes of `fixed_rays`.
  void add_management_passes(std::vector<vk::Pass>& passes, const LinearWork& fixed_rays,
                             uint32_t relocations) const;
  // `texels`: the interior side of the atlas's maps.
  Result<AtlasImage> read_atlas(const vk::Image& image, uint32_t channels, uint32_t texels);
  // The probe states as the GPU keeps them, slot by slot.
  Result<std::vector<gpu::ProbeState>> read_probe_slots();
  // The slot of the probe at each grid index, and per-slot data put in grid order.
  std::vector<uint32_t> slots_in_grid_order() const;
  template <typename T>
  std::vector<T> in_grid_order(std::vector<T> per_slot) const;

  vk::Context& context_;
  GpuScene& scene_;
  const ShadowField* shadow_field_;
  IrradianceFieldParams params_;
  AtlasLayout layout_;
  uint64_t update_index_ = 0;
  struct VolumeState {
    FieldVolume grid;  // where it is now
    // Where it was at the last reset and the cells it scrolled since: the origin is recomputed
    // from them, so that many scrolls do not accumulate rounding.
    glm::vec3 unscrolled_origin{0.0f};
    glm::ivec3 scrolled_cells{0};
    glm::ivec3 scroll{0};  // FieldConstants::scroll
  };
  std::vector<VolumeState> volumes_;
  // The camera the blend boxes of a tracking field are centred on (track()).
  std::optional<glm::vec3> tracked_camera_;
  float hysteresis_cap_ = 1.0f;  // warm_up() lowers the hysteresis below this for a while
  uint64_t gpu_bytes_ = 0;

  FieldSets sets_;    // sampling (set 2 of frames), update and query sets; query kernel; timer
  vk::Kernel trace_;  // fused: traces and lights (also the fixed rays)
  vk::Kernel trace_with_shadow_field_;  // only with a shadow field
  vk::Kernel trace_paths_;              // probe_bounces > 0: paths from each hit
  vk::Kernel trace_with_shadow_field_paths_;
  vk::Kernel hit_light_;  // fused, without paths: the previous field's light at each hit
  vk::Kernel blend_;      // fused: both maps and their borders, per probe
  vk::Kernel blend_sh_;   // SH fields (both paths): coefficients, per probe
  vk::Kernel manage_;
  vk::Kernel raw_trace_;
  vk::Kernel trace_surfels_;  // the split path's kernels
  vk::Kernel shade_;
  vk::Kernel shade_with_shadow_field_;  // only with a shadow field
  vk::Kernel blend_irradiance_;
  vk::Kernel blend_distance_;
  vk::Kernel borders_;
  FieldUpdatePath update_path_ = FieldUpdatePath::kFused;
  vk::TraceBackend backend_ = vk::TraceBackend::kRayQuery;

  vk::Buffer constants_;
  vk::Buffer probes_;
  vk::Buffer rays_;
  vk::Buffer hits_;        // the fused path's hit-light pass only
  vk::Buffer surfels_;     // the split path only
  vk::Buffer probe_list_;  // host-visible: the probes the next dispatches work on
  uint32_t probe_list_size_ = 0;
  bool probe_list_is_active_ = false;  // else it holds probes being managed
  ProbeScheduler scheduler_;
  uint64_t seen_moves_ = 0;  // GpuScene::move_count() already handled
  // Adaptive rays: the scene revision the probes last saw (a change traces every probe for
  // hot_updates updates: `sweep_left_`, so that every probe's drift sees it), and where the
  // next maintenance slice starts in the active list.
  uint64_t seen_revision_ = 0;
  uint32_t sweep_left_ = 0;
  uint32_t maintenance_cursor_ = 0;
  struct Slice {
    uint32_t start = 0;
    uint32_t count = 0;
  };
  Slice maintenance_ = {};  // of the update being built (constants())
  // Probes one update may trace under max_rays_per_update (0: all).
  uint32_t budget_probes() const {
    if (params_.max_rays_per_update == 0) return 0;
    return static_cast<uint32_t>(
        std::max<uint64_t>(1, params_.max_rays_per_update / params_.rays_per_probe));
  }
  // The maintenance slice of the next update over an active list of `list_size` probes.
  Slice next_maintenance_slice(uint32_t list_size) const;
  LinearWork last_update_rays_;  // the blended rays of the last update (raw_trace_passes)
  uint32_t last_update_traced_lights_ = 0;
  vk::Image irradiance_;
  vk::Image distance_;
  vk::Buffer sh_;         // ShProbe per probe of an SH field, one otherwise
  vk::Buffer drift_;      // header + ProbeDrift per probe (adaptive rays)
  vk::Buffer zero_tile_;  // zeros the size of a map tile: what a scroll copies to clear maps
  // Scrolls (field_scroll.cpp): probes that entered and are not started yet; probes started
  // whose states the scheduler has not taken yet, copied to `scroll_states_` (host-visible)
  // by the submission after serial `unread_serial_` (unknown until the next update is built).
  std::vector<uint32_t> entering_;
  std::vector<uint32_t> unread_;
  std::optional<uint64_t> unread_serial_;
  vk::Buffer scroll_states_;
};

}  // namespace ddgi
