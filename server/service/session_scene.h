// The scene a session has loaded: what it was loaded from (label, loader warnings, default
// camera), its GI stack (the scene's GPU copy, the irradiance field, the shadow field), the
// renderer whose kernels every view shares, and the session's lights. Replaced as a whole by
// LoadScene; owned and used by the session's loop thread only.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "gi/gi_stack.h"
#include "render/renderer.h"
#include "scene/scene.h"
#include "service/light_set.h"
#include "service/limits.h"
#include "service/session_budget.h"
#include "vk/context.h"

namespace ddgi::service {

// What the session's scene comes from and how its field starts.
struct SceneRequest {
  std::string label;            // "cornell_box" or "upload:<bytes>"
  std::string path;             // a library file; empty for an upload
  std::vector<uint8_t> upload;  // the .glb bytes of an upload
  uint32_t warmup_updates = 16;
};

// How a session's scenes are set up (fixed when the session is created).
struct SessionOptions {
  bool gi = true;
  DirectMode direct_mode = DirectMode::kTracedShadows;
  std::vector<std::string> field_assignments;  // "name=value", applied over the scene's defaults
  // Shadow-field "name=value" over the grid fitted to the scene; the field exists only in the
  // shadow-field and AO direct modes.
  std::vector<std::string> shadow_assignments;
  // The time budget (field parameter budget_ms): nothing takes the server's --budget-ms; 0 none.
  std::optional<double> budget_ms;
};

class SessionScene {
 public:
  // Loads the scene (a library file, or an upload within the upload limit), builds its GI stack
  // and runs the warm-up. With a time budget (options.budget_ms, else budget.default_ms) the
  // field's configuration is the budget's choice (calibrated or cached). `session_id` is for
  // the log.
  static Result<std::unique_ptr<SessionScene>> load(
      vk::Context& context, const SceneRequest& request, const SessionOptions& options,
      const ServiceLimits& limits, BudgetService& budget, const std::string& session_id);

  const std::string& label() const { return label_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  const Camera& default_camera() const { return default_camera_; }
  GpuScene& gpu_scene() const { return gi_->scene(); }
  IrradianceField* field() const { return gi_->field(); }
  ShadowField* shadow_field() const { return gi_->shadow_field(); }
  // The time budget's choice the field follows, if any.
  const std::optional<tools::BudgetChoice>& budget() const { return budget_; }
  // The field's parameters as the session set them: under a budget, those its choice was
  // applied over (a new budget starts from them, not from the last choice).
  const IrradianceFieldParams& own_field_params() const {
    return budget_ ? budget_base_ : field()->params();
  }
  // Sets the field to the best configuration within `budget_ms` over `params` (own_field_params()
  // with a request's other assignments); 0 ends the budget and sets `params`, or leaves the
  // field as it is when the request set nothing else (`ends_budget_only`).
  Status set_field_budget(const IrradianceFieldParams& params, DirectMode direct_mode,
                          double budget_ms, bool ends_budget_only, BudgetService& budget,
                          const std::string& session_id);
  // Parameters set by hand: the field no longer follows a budget.
  void end_budget() { budget_.reset(); }
  // The energy calibration's choice made on load, if any (BudgetService::energy).
  const std::optional<tools::EnergyChoice>& energy() const { return energy_; }
  // One of its parameters set by hand: the field's energy settings are no longer its choice.
  void end_energy() { energy_.reset(); }
  // The scene's and both fields' GPU bytes.
  uint64_t gpu_bytes() const;

  const LightSet& lights() const { return lights_; }
  // As LightSet's, uploading to the GPU scene.
  Result<LightSlot> add_light(const Light& light);
  Result<LightSlot> update_light(uint32_t id, const Light& light);
  Result<LightSlot> remove_light(uint32_t id);

  // Submits a frame into `target`, after one update of each field when `field_due`, without
  // waiting for it. The renderer is built at the first frame. Building the irradiance field's
  // update may write its host-visible probe list: no earlier update may be in flight then.
  Result<PendingFrame> submit(const FrameSettings& settings, FrameTarget& target, bool field_due);
  // One update of each field without a frame (probe streams with nobody watching), waited for.
  Status update_fields() { return gi_->update(1); }

 private:
  SessionScene() = default;
  Status upload_lights(const std::vector<Light>& lights);
  Status choose_energy(vk::Context& context, const Scene& scene, const SessionOptions& options,
                       BudgetService& budget, const std::string& session_id,
                       const std::string& label, GiStackOptions& gi_options);

  vk::Context* context_ = nullptr;
  std::string label_;
  std::vector<std::string> warnings_;
  Camera default_camera_;
  std::unique_ptr<GiStack> gi_;
  std::unique_ptr<Renderer> renderer_;  // after gi_: it points at its scene and fields
  LightSet lights_;
  std::optional<tools::BudgetChoice> budget_;
  IrradianceFieldParams budget_base_;  // what budget_ was chosen over
  std::optional<tools::EnergyChoice> energy_;
};

}  // namespace ddgi::service
