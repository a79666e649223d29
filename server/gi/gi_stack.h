// The GI stack of one scene: its GPU copy, the optional shadow field and the irradiance field,
// built together by one rule (shadow_field_mode(): a shadow field exists when the frames or the
// probe rays read it) and updated together (the shadow field first: probe rays read its newest
// state). The session, the tools and the GPU tests build their scene and fields through it;
// the Renderer only renders frames and records whatever update passes its caller hands it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/result.h"
#include "gi/field_params.h"
#include "gi/irradiance_field.h"
#include "gi/shadow_field.h"
#include "gi/shadow_params.h"
#include "gpu_scene/frame_types.h"
#include "gpu_scene/gpu_scene.h"
#include "scene/scene.h"
#include "vk/context.h"
#include "vk/pass.h"

namespace ddgi {

struct GiStackOptions {
  // An irradiance field at all; off renders direct light only.
  bool gi = true;
  // The frames' direct mode. With the field's probe_direct it decides whether a shadow field
  // exists and in which mode it is updated (shadow_field_mode()).
  DirectMode direct_mode = DirectMode::kTracedShadows;
  IrradianceFieldParams field;  // used when gi
  ShadowFieldParams shadow;     // used when a shadow field exists
  vk::TraceBackend backend = vk::TraceBackend::kRayQuery;
};

// Options for `scene`: the field fitted to it (default_field_params) and the shadow grid fitted
// to its bounds, each with "name=value" assignments applied over them (refused by name).
Result<GiStackOptions> fitted_gi_options(const Scene& scene, bool gi, DirectMode direct_mode,
                                         const std::vector<std::string>& field_assignments,
                                         const std::vector<std::string>& shadow_assignments,
                                         vk::TraceBackend backend);

// How many updates of each field one frame records before its own passes; [0, 64] each. 1 and
// 1: the real-time loop.
struct GiUpdates {
  uint32_t field = 1;
  uint32_t shadow_field = 1;
};
Status validate(const GiUpdates& updates);

// The passes of one frame's update of these fields (either may be null) in `frame_mode`: the
// shadow field's first (probe rays read its newest state), when the frame or the probe rays of
// an updated field read it; then the irradiance field's, after bringing its probe states up to
// date with moved geometry (GPU work of its own). Record them, once, before the frame's passes.
Result<std::vector<vk::Pass>> gi_update_passes(IrradianceField* field, ShadowField* shadow_field,
                                               DirectMode frame_mode, const GiUpdates& updates);

class GiStack {
 public:
  static Result<std::unique_ptr<GiStack>> create(vk::Context& context, const Scene& scene,
                                                 const GiStackOptions& options);

  GpuScene& scene() const { return *scene_; }
  IrradianceField* field() const { return field_.get(); }
  ShadowField* shadow_field() const { return shadow_field_.get(); }
  const GiStackOptions& options() const { return options_; }
  // The mode the shadow field is updated in for frames in `frame_mode` (shadow_field_mode()).
  DirectMode shadow_update_mode(DirectMode frame_mode) const;

  // A tracking irradiance field (track_camera) follows `camera` (IrradianceField::track); the
  // tools call it with their camera before warm_up(), so that the field is placed around it.
  void track(glm::vec3 camera) {
    if (field_) field_->track(camera);
  }
  // Converges new fields: `count` shadow-field updates, then the irradiance field's warm_up
  // (fast convergence at low hysteresis first).
  Status warm_up(uint32_t count);
  // `count` plain updates of each field (the shadow field's first), at their own hysteresis.
  Status update(uint32_t count);
  // gi_update_passes() of this stack's fields.
  Result<std::vector<vk::Pass>> frame_update(DirectMode frame_mode, const GiUpdates& updates) {
    return gi_update_passes(field_.get(), shadow_field_.get(), frame_mode, updates);
  }

 private:
  explicit GiStack(GiStackOptions options) : options_(std::move(options)) {}
  Status update_shadow_field(uint32_t count);

  GiStackOptions options_;
  std::unique_ptr<GpuScene> scene_;
  std::unique_ptr<ShadowField> shadow_field_;  // before the field: it reads the shadow field
  std::unique_ptr<IrradianceField> field_;
};

}  // namespace ddgi
