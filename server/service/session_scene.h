// The scene a session has loaded: what it was loaded from (label, loader warnings, default
// camera), its GI stack (the scene's GPU copy, the irradiance field, the shadow field), the
// renderer whose kernels every view shares, the session's lights, and its configuration: the
// calibration of the scene (taken from the cache at load, or measured in the background while
// the static default streams) and the rule's choice within the session's budget
// (tools/field_choice.h). Replaced as a whole by LoadScene; owned and used by the session's loop
// thread only.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
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
  // The time budget (field parameter budget_ms): nothing (or 0) takes the server's --budget-ms.
  std::optional<double> budget_ms;
};

class SessionScene {
 public:
  // Loads the scene (a library file, or an upload within the upload limit), builds its GI stack
  // and runs the warm-up. The field starts with the rule's choice where the scene's calibration
  // is cached, else with the static default (start_calibration() then measures it).
  // `session_id` is for the log.
  static Result<std::unique_ptr<SessionScene>> load(
      vk::Context& context, const SceneRequest& request, const SessionOptions& options,
      const ServiceLimits& limits, BudgetService& budget, const std::string& session_id);

  const std::string& label() const { return label_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  const Camera& default_camera() const { return default_camera_; }
  GpuScene& gpu_scene() const { return gi_->scene(); }
  IrradianceField* field() const { return gi_->field(); }
  ShadowField* shadow_field() const { return gi_->shadow_field(); }

  // The rule's choice the field follows, if any.
  const std::optional<tools::BudgetChoice>& budget() const { return choice_; }
  // Queues the scene's calibration where load() found none cached; `landed` runs on the
  // calibrator's thread when it is done (the session then calls adopt_calibration on its loop).
  void start_calibration(BudgetService& budget, std::function<void()> landed);
  // Where the calibration finished: its choice becomes the field's (unless the field was set by
  // hand since), or its failure is reported. Nothing while it runs.
  Status adopt_calibration(const std::string& session_id);
  // Sets the session's budget (0: the server's default) and, where the scene is calibrated,
  // the field to the rule's choice within it with `hand_set` applied over it; before then, the
  // choice waits for the calibration.
  Status set_field_budget(double budget_ms, const std::vector<std::string>& hand_set,
                          const BudgetService& budget, const std::string& session_id);
  // Parameters set by hand: the field no longer follows the rule's choice.
  void end_budget() {
    choice_.reset();
    hand_set_ = true;
  }
  // FieldParams.calibration.
  void calibration_to_proto(v1::FieldCalibration* out) const;
  // The scene's, both fields' and the world cache's GPU bytes.
  uint64_t gpu_bytes() const;
  // The world cache, once an ao-cache frame made it (nullptr before, and in other modes).
  const WorldCache* world_cache() const { return renderer_ ? renderer_->world_cache() : nullptr; }

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
  // Where the scene's calibration is cached: the choice applied to `gi_options` before the
  // field exists. Else the calibration is left to start_calibration().
  void take_cached_calibration(vk::Context& context, const Scene& scene,
                               const SessionOptions& options, BudgetService& budget,
                               GiStackOptions& gi_options);
  // The field set to the rule's choice within budget_ms_ over the session's own parameters, with
  // `hand_set` over it.
  Status follow_choice(const std::vector<std::string>& hand_set, const std::string& session_id);

  vk::Context* context_ = nullptr;
  std::string label_;
  std::vector<std::string> warnings_;
  Camera default_camera_;
  std::unique_ptr<GiStack> gi_;
  std::unique_ptr<Renderer> renderer_;  // after gi_: it points at its scene and fields
  LightSet lights_;
  uint32_t warmup_updates_ = 0;

  // The configuration. base_: the options the session asked for (the static default with its
  // own assignments), which the calibration measured over; fixed_: those assignments, which the
  // candidates keep.
  GiStackOptions base_;
  std::vector<std::string> fixed_;
  double budget_ms_ = 0.0;
  std::string calibration_key_;
  std::shared_ptr<const tools::Calibration> calibration_;
  bool calibration_from_cache_ = false;
  std::optional<tools::BudgetChoice> choice_;
  bool hand_set_ = false;        // parameters set by hand since the last choice
  std::string calibration_off_;  // why the scene is not calibrated (empty: it is)
  std::string calibration_error_;
  // While the calibration runs: the job, this scene's interest in it, and the CPU scene it
  // measures (a copy: the session's lights and instances change its own).
  std::shared_ptr<CalibrationJob> job_;
  std::shared_ptr<void> wants_job_;
  std::shared_ptr<const Scene> scene_to_calibrate_;
  std::chrono::steady_clock::time_point loaded_at_;
  double switched_after_s_ = 0.0;
};

}  // namespace ddgi::service
