// Scrolling volumes (docs/cascades.md, "Scrolling"): an IrradianceField's volumes move as 3D
// circular buffers, and the probes that enter start over. The start (maps cleared, history
// reset, relocation, classification) is recorded into the command buffer of the next update, so
// a tracking field scrolls without a submission or a wait of its own; the CPU reads the entering
// probes' states (for the scheduler) once that update's submission has completed.
#include <algorithm>

#include "gi/irradiance_field.h"

namespace ddgi {
namespace {

using vk::with_access;

// vkCmdUpdateBuffer writes at most 64 KiB.
constexpr size_t kListChunk = 65536 / sizeof(uint32_t);

}  // namespace

void IrradianceField::move_volume(uint32_t volume, glm::ivec3 cells,
                                  std::vector<uint32_t>& entering) {
  VolumeState& v = volumes_[volume];
  FieldVolume& g = v.grid;
  v.scrolled_cells += cells;
  g.origin = v.unscrolled_origin + glm::vec3(v.scrolled_cells) * g.spacing;
  if (!g.static_volume && g.cascade == 0) params_.origin = g.origin;
  // Nothing stays: every probe enters, in the volume's new place.
  const bool everything = glm::any(glm::greaterThanEqual(glm::abs(cells), g.counts));
  v.scroll = ((v.scroll + cells) % g.counts + g.counts) % g.counts;
  const uint32_t probes = static_cast<uint32_t>(grid_probe_count(g.counts));
  for (uint32_t local = 0; local < probes; ++local) {
    const glm::ivec3 c = probe_coord(g.counts, v.scroll, local);
    bool entered = everything;
    for (int axis = 0; axis < 3; ++axis) {
      // A scroll by +k brings in the last k planes of the axis, by -k the first k.
      entered = entered || (cells[axis] > 0 && c[axis] >= g.counts[axis] - cells[axis]) ||
                (cells[axis] < 0 && c[axis] < -cells[axis]);
    }
    if (entered) entering.push_back(g.first_probe + local);
  }
}

Status IrradianceField::scroll(uint32_t volume, glm::ivec3 cells, ScrollStart start) {
  if (volume >= volumes_.size()) {
    return invalid_argument("volume " + std::to_string(volume) + " of a field of " +
                            std::to_string(volumes_.size()));
  }
  if (cells == glm::ivec3(0)) return ok_status();
  move_volume(volume, cells, entering_);
  if (start == ScrollStart::kInNextUpdate) return ok_status();
  // At once, in a submission of its own: the start of every probe that entered so far.
  std::vector<vk::Pass> passes = {vk::upload_pass("field constants",
                                                  vk::PassGroup::kIrradianceField, constants_,
                                                  constants(DirectMode::kTracedShadows))};
  add_start_passes(passes);
  DDGI_TRY(context_.submit_and_wait(
      [&](VkCommandBuffer cmd) { vk::record_passes(cmd, nullptr, passes); }));
  adopt_scroll_verdicts();
  return ok_status();
}

std::vector<std::pair<uint32_t, glm::ivec3>> IrradianceField::tracking_scrolls(
    glm::vec3 camera) const {
  std::vector<std::pair<uint32_t, glm::ivec3>> scrolls;
  if (!params_.track_camera) return scrolls;
  for (uint32_t v = 0; v < volumes_.size(); ++v) {
    if (!volumes_[v].grid.tracks(params_)) continue;
    const glm::ivec3 cells = tracking_scroll(volumes_[v].grid, camera);
    if (cells != glm::ivec3(0)) scrolls.push_back({v, cells});
  }
  return scrolls;
}

bool IrradianceField::tracking_would_scroll(glm::vec3 camera) const {
  return !tracking_scrolls(camera).empty();
}

void IrradianceField::track(glm::vec3 camera) {
  if (!params_.track_camera) return;
  tracked_camera_ = camera;
  for (const auto& [volume, cells] : tracking_scrolls(camera))
    move_volume(volume, cells, entering_);
}

void IrradianceField::add_start_passes(std::vector<vk::Pass>& passes) {
  if (entering_.empty()) return;
  std::sort(entering_.begin(), entering_.end());
  entering_.erase(std::unique(entering_.begin(), entering_.end()), entering_.end());
  const std::vector<uint32_t> slots = std::move(entering_);
  entering_.clear();
  const uint32_t n = static_cast<uint32_t>(slots.size());
  // The entering slots go to the second half of the probe list, behind the active probes the
  // updates take (the first half may still be read by a frame in flight: it is not touched).
  const uint32_t at = static_cast<uint32_t>(probe_count(params_));
  vk::Pass list;
  list.name = "scroll: probe list";
  list.group = vk::PassGroup::kIrradianceField;
  list.timed = false;
  list.writes = {&probe_list_};
  list.commands = [buffer = probe_list_.handle(), slots, at](VkCommandBuffer cmd) {
    for (size_t first = 0; first < slots.size(); first += kListChunk) {
      const size_t count = std::min(kListChunk, slots.size() - first);
      vkCmdUpdateBuffer(cmd, buffer, (at + first) * sizeof(uint32_t), count * sizeof(uint32_t),
                        slots.data() + first);
    }
  };
  passes.push_back(list);
  passes.push_back(clear_maps_pass(slots));
  const LinearWork start{at, at + n, n, 1, gpu::kProbeModeStart};
  passes.push_back(
      with_access(linear_pass("probe start", manage_, start), {&probe_list_}, {&probes_}));
  add_management_passes(passes, {at, at + n, n, params_.fixed_rays}, params_.relocation_iterations);
  // The verdicts, for the CPU's scheduler once this submission has completed.
  if (params_.classification) passes.push_back(copy_states_pass(slots));
  unread_.insert(unread_.end(), slots.begin(), slots.end());
  unread_serial_.reset();  // the submission that carries these passes is not made yet
}

vk::Pass IrradianceField::clear_maps_pass(const std::vector<uint32_t>& slots) const {
  const uint32_t irradiance_tile = params_.irradiance_texels + 2 * gpu::kAtlasBorder;
  const uint32_t distance_tile = params_.distance_texels + 2 * gpu::kAtlasBorder;
  const uint32_t per_row = layout_.tiles_per_row;
  // One copy region per probe and map: the tiles of `slots` in each atlas.
  auto tiles = [slots, per_row](uint32_t tile) {
    std::vector<VkBufferImageCopy> regions;
    for (uint32_t p : slots) {
      VkBufferImageCopy r{};
      r.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
      r.imageOffset = {int32_t(p % per_row * tile), int32_t(p / per_row * tile), 0};
      r.imageExtent = {tile, tile, 1};
      regions.push_back(r);
    }
    return regions;
  };
  vk::Pass pass;
  pass.name = "scroll: clear maps";
  pass.group = vk::PassGroup::kIrradianceField;
  pass.timed = false;
  pass.writes = {&irradiance_, &distance_, &sh_};
  if (params_.basis == ProbeBasis::kSh) {
    pass.commands = [sh = sh_.handle(), slots](VkCommandBuffer cmd) {
      for (uint32_t p : slots) {
        vkCmdFillBuffer(cmd, sh, VkDeviceSize(p) * sizeof(gpu::ShProbe), sizeof(gpu::ShProbe), 0);
      }
    };
    return pass;
  }
  pass.commands = [zero = zero_tile_.handle(), irradiance = irradiance_.handle(),
                   distance = distance_.handle(), irradiance_regions = tiles(irradiance_tile),
                   distance_regions = tiles(distance_tile)](VkCommandBuffer cmd) {
    vkCmdCopyBufferToImage(cmd, zero, irradiance, VK_IMAGE_LAYOUT_GENERAL,
                           uint32_t(irradiance_regions.size()), irradiance_regions.data());
    vkCmdCopyBufferToImage(cmd, zero, distance, VK_IMAGE_LAYOUT_GENERAL,
                           uint32_t(distance_regions.size()), distance_regions.data());
  };
  return pass;
}

vk::Pass IrradianceField::copy_states_pass(const std::vector<uint32_t>& slots) const {
  vk::Pass pass;
  pass.name = "scroll: probe states";
  pass.group = vk::PassGroup::kIrradianceField;
  pass.timed = false;
  pass.reads = {&probes_};
  pass.commands = [from = probes_.handle(), to = scroll_states_.handle(),
                   slots](VkCommandBuffer cmd) {
    std::vector<VkBufferCopy> regions;
    for (uint32_t p : slots) {
      const VkDeviceSize offset = VkDeviceSize(p) * sizeof(gpu::ProbeState);
      regions.push_back({offset, offset, sizeof(gpu::ProbeState)});
    }
    vkCmdCopyBuffer(cmd, from, to, uint32_t(regions.size()), regions.data());
    VkMemoryBarrier to_host{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    to_host.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                         &to_host, 0, nullptr, 0, nullptr);
  };
  return pass;
}

void IrradianceField::adopt_scroll_verdicts() {
  if (unread_.empty()) return;
  if (params_.classification) {
    const auto* states = static_cast<const gpu::ProbeState*>(scroll_states_.mapped());
    std::vector<uint8_t> verdicts = scheduler_.states();
    // The start made them Vigilant with a history reset; classification gave their state. No
    // flag needs the CPU: a probe not traced yet still has its reset.
    for (uint32_t p : unread_) {
      verdicts[p] =
          static_cast<uint8_t>((states[p].flags & gpu::kProbeStateMask) >> gpu::kProbeStateShift);
    }
    scheduler_.set_states(verdicts);
  }
  unread_.clear();
  unread_serial_.reset();
}

void IrradianceField::collect_scroll_verdicts() {
  if (unread_.empty()) return;
  // Called as the next update is being built: the submission that carried the start passes
  // was made by now, so the newest serial is at or after it.
  if (!unread_serial_) unread_serial_ = context_.submitted_serial();
  if (context_.completed(*unread_serial_)) adopt_scroll_verdicts();
}

}  // namespace ddgi
