// Between the wire types (ddgi.v1) and the server's own types, and the only place that does it.
// Inbound, with validation: every value a client sends passes through here before it reaches a
// session; errors are INVALID_ARGUMENT naming the field ("camera.position", "light.intensity")
// and the allowed range. Outbound: the renderer's values and the session's domain state (its
// scene, views, lights, fields, frames) as replies, frames and summaries.
#pragma once

#include <glm/glm.hpp>

#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "gi/irradiance_field.h"
#include "gi/shadow_field.h"
#include "gpu_scene/frame_types.h"
#include "gpu_scene/gpu_scene.h"
#include "scene/scene.h"
#include "service/frame_record.h"
#include "service/light_set.h"
#include "service/limits.h"
#include "service/session_state.h"
#include "service/session_view.h"

namespace ddgi::service {

// Applies the fields present in `in` onto `config`; `config` is unchanged on error.
Status apply_view_settings(const v1::ViewSettings& in, const ServiceLimits& limits,
                           ViewConfig& config);
void to_proto(const ViewConfig& config, v1::ViewSettings* out);

// `base` supplies what the wire camera does not carry (the near distance).
Result<Camera> camera_from_proto(const v1::Camera& in, const Camera& base);
void to_proto(const Camera& camera, v1::Camera* out);

// Applies the fields present in `in` onto `base` and validates the result.
Result<Light> light_from_proto(const v1::Light& in, const Light& base);
void to_proto(const Light& light, v1::Light* out);

Result<glm::mat4> matrix_from_proto(const v1::Matrix4& in);
void to_proto(const glm::mat4& matrix, v1::Matrix4* out);

Result<IrradianceQuery> query_from_proto(const v1::QueryPoint& in, size_t index);

Result<DirectMode> direct_mode_from_proto(v1::DirectMode mode);

void to_proto(const glm::vec3& v, v1::Vec3* out);
glm::vec3 from_proto(const v1::Vec3& v);

// ---- The session's state, outbound -------------------------------------------------------------

void to_proto(const SessionView& view, v1::ViewInfo* out);
void to_proto(const LightSlot& slot, v1::LightEntry* out);
void to_proto(const LightSlot& slot, uint64_t command_seq, v1::LightReply* out);
// Instance `index` of `scene`.
void to_proto(const GpuScene& scene, uint32_t index, uint64_t command_seq, v1::InstanceReply* out);
// Every parameter in effect (by the parameter tables), probes, bytes, updates; the irradiance
// field's probe-state counts.
void to_proto(const IrradianceField& field, uint64_t command_seq, v1::FieldParams* out);
// The scene's irradiance field, with the time budget's choice it follows (if any).
void to_proto(const SessionScene& scene, uint64_t command_seq, v1::FieldParams* out);
void to_proto(const ShadowField& field, uint64_t command_seq, v1::FieldParams* out);
// `frames`: the loop's frame count; `command_seq`: the command being answered.
void to_proto(const SessionState& session, uint64_t frames, uint64_t command_seq,
              v1::SessionInfo* out);
void to_proto(const SessionState& session, uint64_t frames, v1::SessionSummary* out);
// Everything but the JPEG bytes and the encode time (the encoder adds those).
void to_proto(const FrameRecord& frame, v1::Frame* out);
void to_proto(const std::vector<glm::vec3>& irradiance, uint64_t field_updates,
              v1::QueryIrradianceReply* out);

}  // namespace ddgi::service
