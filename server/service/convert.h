// Between the wire types (ddgi.v1) and the renderer's types, with validation: every value a
// client sends passes through here before it reaches a session. Errors are INVALID_ARGUMENT
// naming the field ("camera.position", "light.intensity") and the allowed range.
#pragma once

#include <glm/glm.hpp>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "gi/irradiance_field.h"
#include "gpu_scene/frame_types.h"
#include "scene/scene.h"
#include "service/limits.h"

namespace ddgi::service {

// How one view's frames look (everything but the camera).
struct ViewConfig {
  uint32_t width = 640;
  uint32_t height = 480;
  float exposure = 1.0f;
  Tonemap tonemap = Tonemap::kAces;
  View view = View::kFull;
  // 85: small frames for streaming with no visible blocking on renders.
  int jpeg_quality = 85;
};

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

}  // namespace ddgi::service
