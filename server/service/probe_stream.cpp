#include "service/probe_stream.h"

#include <algorithm>
#include <cmath>

#include "gi/probe_state.h"
#include "rpc/probe_stream.h"

namespace ddgi::service {
namespace {

v1::ProbeGrid grid_of(const IrradianceFieldParams& p) {
  v1::ProbeGrid g;
  g.set_basis(p.basis == ProbeBasis::kSh ? "sh" : "octahedral");
  g.set_counts_x(p.counts.x);
  g.set_counts_y(p.counts.y);
  g.set_counts_z(p.counts.z);
  g.mutable_origin()->set_x(p.origin.x);
  g.mutable_origin()->set_y(p.origin.y);
  g.mutable_origin()->set_z(p.origin.z);
  g.mutable_spacing()->set_x(p.spacing.x);
  g.mutable_spacing()->set_y(p.spacing.y);
  g.mutable_spacing()->set_z(p.spacing.z);
  g.set_self_shadow_bias(p.self_shadow_bias);
  g.set_weight_crush_threshold(p.weight_crush_threshold);
  if (p.basis == ProbeBasis::kSh) {
    for (const float scale : sh_band_scales(p)) g.add_sh_band_scales(scale);
  } else {
    g.set_irradiance_texels(p.irradiance_texels);
    g.set_distance_texels(p.distance_texels);
    g.set_border_texels(gpu::kAtlasBorder);
    g.set_tiles_per_row(atlas_layout(p).tiles_per_row);
    g.set_irradiance_gamma(p.irradiance_gamma);
  }
  return g;
}

// Appends probe p's tile of `atlas` (`stored` of its channels per texel).
void append_tile(const IrradianceField::AtlasImage& atlas, uint32_t p, uint32_t tiles_per_row,
                 uint32_t tile, uint32_t stored, std::vector<float>& out) {
  const size_t x0 = (p % tiles_per_row) * tile, y0 = (p / tiles_per_row) * tile;
  for (uint32_t y = 0; y < tile; ++y) {
    for (uint32_t x = 0; x < tile; ++x) {
      const float* texel = &atlas.texels[((y0 + y) * atlas.width + x0 + x) * atlas.channels];
      out.insert(out.end(), texel, texel + stored);
    }
  }
}

Status read_values(IrradianceField& field, ProbeSnapshot& s) {
  const IrradianceFieldParams& p = field.params();
  const uint32_t probes = static_cast<uint32_t>(probe_count(p));
  if (p.basis == ProbeBasis::kSh) {
    DDGI_ASSIGN_OR_RETURN(const std::vector<gpu::ShProbe> sh, field.read_sh_probes());
    s.values = sh_coefficient_values(sh);
    return ok_status();
  }
  s.values.reserve(size_t(probes) * s.stride);
  DDGI_ASSIGN_OR_RETURN(const IrradianceField::AtlasImage irradiance,
                        field.read_irradiance_atlas());
  DDGI_ASSIGN_OR_RETURN(const IrradianceField::AtlasImage distance, field.read_distance_atlas());
  const uint32_t tiles = s.grid.tiles_per_row();
  for (uint32_t probe = 0; probe < probes; ++probe) {
    append_tile(irradiance, probe, tiles, p.irradiance_texels + 2 * gpu::kAtlasBorder, 3, s.values);
    const size_t at = s.values.size();
    append_tile(distance, probe, tiles, p.distance_texels + 2 * gpu::kAtlasBorder, 2, s.values);
    // Mean of squares -> variance: what the Chebyshev test uses, which fp16 keeps; the mean of
    // squares itself would lose it to cancellation (mean^2 is most of it).
    for (size_t i = at; i < s.values.size(); i += 2) {
      s.values[i + 1] = std::max(s.values[i + 1] - s.values[i] * s.values[i], 0.0f);
    }
  }
  return ok_status();
}

void append_half(std::string& out, float value) {
  const uint16_t h = float_to_half(value);
  out.push_back(char(h & 0xff));
  out.push_back(char(h >> 8));
}

void set_bit(std::string& mask, size_t p) {
  mask[p / 8] = char(uint8_t(mask[p / 8]) | uint8_t(1u << (p % 8)));
}

}  // namespace

Result<std::shared_ptr<const ProbeSnapshot>> take_probe_snapshot(IrradianceField& field) {
  DDGI_TRY(require_one_volume(field, "StreamProbes"));
  auto s = std::make_shared<ProbeSnapshot>();
  s->field_updates = field.updates();
  s->grid = grid_of(field.params());
  s->stride = probe_value_count(s->grid);
  const uint32_t tile = field.params().irradiance_texels + 2 * gpu::kAtlasBorder;
  s->split = field.params().basis == ProbeBasis::kSh ? s->stride : tile * tile * 3;
  DDGI_TRY(read_values(field, *s));
  DDGI_ASSIGN_OR_RETURN(const std::vector<gpu::ProbeState> states, field.read_probe_states());
  s->states = probe_state_values(states);
  return std::shared_ptr<const ProbeSnapshot>(std::move(s));
}

bool ProbeStreamState::moved(const float* now, const float* known, uint32_t begin,
                             uint32_t end) const {
  float difference = 0.0f, magnitude = 1e-6f;
  for (uint32_t i = begin; i < end; ++i) {
    difference = std::max(difference, std::abs(now[i] - known[i]));
    magnitude = std::max({magnitude, std::abs(now[i]), std::abs(known[i])});
  }
  return difference > options_.change_threshold * magnitude;
}

void ProbeStreamState::encode_locked(const ProbeSnapshot& now, bool full) {
  writing_.Clear();
  writing_.set_field_updates(now.field_updates);
  writing_.set_full(full);
  writing_.set_updates_folded(folded_);
  if (full) {
    *writing_.mutable_grid() = now.grid;
    known_values_.assign(now.values.size(), 0.0f);
    known_states_.assign(now.states.size(), 0);
  }
  const size_t probes = now.states.size() / kProbeStateValues;
  std::string* values = writing_.mutable_values();
  std::string changed(full ? 0 : (probes + 7) / 8, '\0');
  for (size_t p = 0; p < probes; ++p) {
    const float* v = &now.values[p * now.stride];
    float* known = &known_values_[p * now.stride];
    if (!full) {
      if (!moved(v, known, 0, now.split) && !moved(v, known, now.split, now.stride)) continue;
      set_bit(changed, p);
    }
    for (uint32_t i = 0; i < now.stride; ++i) {
      append_half(*values, v[i]);
      known[i] = half_to_float(float_to_half(v[i]));
    }
  }
  std::string state_changed(full ? 0 : (probes + 7) / 8, '\0');
  std::string* states = writing_.mutable_states();
  for (size_t p = 0; p < probes; ++p) {
    uint16_t halves[kProbeStateValues];
    bool differs = full;
    for (uint32_t i = 0; i < kProbeStateValues; ++i) {
      halves[i] = float_to_half(now.states[p * kProbeStateValues + i]);
      differs = differs || halves[i] != known_states_[p * kProbeStateValues + i];
    }
    if (!differs) continue;
    if (!full) set_bit(state_changed, p);
    for (uint32_t i = 0; i < kProbeStateValues; ++i) {
      known_states_[p * kProbeStateValues + i] = halves[i];
      states->push_back(char(halves[i] & 0xff));
      states->push_back(char(halves[i] >> 8));
    }
  }
  writing_.set_changed(std::move(changed));
  writing_.set_state_changed(std::move(state_changed));
}

void ProbeStreamState::offer(std::shared_ptr<const ProbeSnapshot> snapshot) {
  Action action;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finish_requested_ || finished_ || snapshot->field_updates <= last_updates_) return;
    last_updates_ = snapshot->field_updates;
    if (slot_) ++folded_;
    slot_ = std::move(snapshot);
    action = next_action_locked();
  }
  act(action);
}

ProbeStreamState::Action ProbeStreamState::next_action_locked() {
  if (in_flight_ || finished_ || reactor_ == nullptr) return Action::kNone;
  if (finish_requested_) {
    finished_ = true;
    slot_.reset();
    return Action::kFinish;
  }
  if (!slot_) return Action::kNone;
  const std::string grid = slot_->grid.SerializeAsString();
  const uint32_t interval = std::max(options_.full_refresh_interval, 1u);
  const bool full = grid != known_grid_ || messages_ % interval == 0;
  known_grid_ = grid;
  encode_locked(*slot_, full);
  slot_.reset();
  folded_ = 0;
  ++messages_;
  in_flight_ = true;
  return Action::kWrite;
}

void ProbeStreamState::act(Action action) {
  // Outside the lock (gRPC may run a reaction inline); the reactor is alive while a write or
  // Finish is pending, and only this path starts them.
  if (action == Action::kWrite) reactor_->StartWrite(&writing_);
  if (action == Action::kFinish) reactor_->Finish(finish_status_);
}

void ProbeStreamState::finish(const grpc::Status& status) {
  Action action;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finish_requested_ || finished_) return;
    finish_requested_ = true;
    finish_status_ = status;
    action = next_action_locked();
  }
  act(action);
}

bool ProbeStreamState::ended() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return finish_requested_ || finished_;
}

void ProbeStreamState::write_done(bool ok) {
  Action action;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    in_flight_ = false;
    if (!ok && !finish_requested_) {
      finish_requested_ = true;
      finish_status_ = grpc::Status(grpc::StatusCode::CANCELLED, "the client went away");
    }
    action = next_action_locked();
  }
  act(action);
}

void ProbeStreamState::reactor_done() {
  std::lock_guard<std::mutex> lock(mutex_);
  reactor_ = nullptr;
  finished_ = true;
  slot_.reset();
}

ProbeStreamReactor::ProbeStreamReactor(ProbeStreamOptions options)
    : state_(std::make_shared<ProbeStreamState>(options)) {
  state_->reactor_ = this;
}

void ProbeStreamReactor::OnWriteDone(bool ok) {
  state_->write_done(ok);
}

void ProbeStreamReactor::OnCancel() {
  state_->finish(grpc::Status(grpc::StatusCode::CANCELLED, "the stream was cancelled"));
}

void ProbeStreamReactor::OnDone() {
  state_->reactor_done();
  if (on_done_) on_done_();
  delete this;
}

}  // namespace ddgi::service
