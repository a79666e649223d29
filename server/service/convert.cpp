#include "service/convert.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <string>

#include <glm/gtc/matrix_access.hpp>

#include "gi/field_params.h"
#include "gi/shadow_params.h"

namespace ddgi::service {
namespace {

constexpr float kPi = 3.14159265358979f;
constexpr float kMaxMagnitude = 1e9f;  // colours, intensities, ranges
constexpr float kMaxCoordinate = 1e12f;

// "%g" without the exponent's sign and leading zeros: 1e9, not 1e+09.
std::string num(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%g", value);
  std::string out;
  for (const char* c = text; *c; ++c) {
    out += *c;
    if (*c != 'e') continue;
    if (c[1] == '+') ++c;
    if (c[1] == '-') out += *++c;
    while (c[1] == '0' && c[2] != '\0') ++c;
  }
  return out;
}

std::string vec_text(const glm::vec3& v) {
  // Appended piece by piece: GCC 12 at -O3 warns falsely (-Wrestrict) on "(" + std::string.
  std::string out = "(";
  out.append(num(v.x)).append(", ").append(num(v.y)).append(", ").append(num(v.z)).append(")");
  return out;
}

bool finite(const glm::vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

Status check_position(const glm::vec3& v, const std::string& what) {
  if (!finite(v) || glm::any(glm::greaterThan(glm::abs(v), glm::vec3(kMaxCoordinate)))) {
    return invalid_argument(what + " must be finite with each coordinate in [-1e12, 1e12] (got " +
                            vec_text(v) + ")");
  }
  return ok_status();
}

Status check_direction(const glm::vec3& v, const std::string& what) {
  if (!finite(v)) {
    return invalid_argument(what + " must be finite (got " + vec_text(v) + ")");
  }
  if (glm::length(v) < 1e-12f) return invalid_argument(what + " must be non-zero");
  return ok_status();
}

Status check_scalar(float value, float min, float max, const std::string& what) {
  if (!std::isfinite(value) || value < min || value > max) {
    return invalid_argument(what + " must be finite and in [" + num(min) + ", " + num(max) +
                            "] (got " + num(value) + ")");
  }
  return ok_status();
}

Status check_size(uint32_t value, uint32_t max, const char* what, const char* flag) {
  if (value < 1 || value > max) {
    return invalid_argument(std::string(what) + " " + std::to_string(value) +
                            " is out of range: it must be in [1, " + std::to_string(max) +
                            "] (the server's " + flag + ")");
  }
  return ok_status();
}

Result<Tonemap> tonemap_from_proto(v1::Tonemap t) {
  switch (t) {
    case v1::TONEMAP_ACES:
      return Tonemap::kAces;
    case v1::TONEMAP_REINHARD:
      return Tonemap::kReinhard;
    case v1::TONEMAP_CLAMP:
      return Tonemap::kClamp;
    default:
      return invalid_argument("settings.tonemap " + std::to_string(int(t)) + " is not a Tonemap");
  }
}

Result<View> view_from_proto(v1::ViewMode v) {
  switch (v) {
    case v1::VIEW_MODE_FULL:
      return View::kFull;
    case v1::VIEW_MODE_DIRECT:
      return View::kDirect;
    case v1::VIEW_MODE_INDIRECT:
      return View::kIndirect;
    case v1::VIEW_MODE_ALBEDO:
      return View::kAlbedo;
    case v1::VIEW_MODE_NORMAL:
      return View::kNormal;
    case v1::VIEW_MODE_PROBES:
      return View::kProbes;
    default:
      return invalid_argument("settings.view_mode " + std::to_string(int(v)) +
                              " is not a ViewMode");
  }
}

}  // namespace

void to_proto(const glm::vec3& v, v1::Vec3* out) {
  out->set_x(v.x);
  out->set_y(v.y);
  out->set_z(v.z);
}

glm::vec3 from_proto(const v1::Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

Status apply_view_settings(const v1::ViewSettings& in, const ServiceLimits& limits,
                           ViewConfig& config) {
  ViewConfig next = config;
  if (in.has_width()) {
    DDGI_TRY(check_size(in.width(), limits.max_width, "width", "--max-width"));
    next.width = in.width();
  }
  if (in.has_height()) {
    DDGI_TRY(check_size(in.height(), limits.max_height, "height", "--max-height"));
    next.height = in.height();
  }
  if (in.has_exposure()) {
    if (!std::isfinite(in.exposure()) || !(in.exposure() > 0.0f) || in.exposure() > 1e9f) {
      return invalid_argument("settings.exposure must be finite and in (0, 1e9] (got " +
                              num(in.exposure()) + ")");
    }
    next.exposure = in.exposure();
  }
  if (in.has_tonemap() && in.tonemap() != v1::TONEMAP_UNSPECIFIED) {
    DDGI_ASSIGN_OR_RETURN(next.tonemap, tonemap_from_proto(in.tonemap()));
  }
  if (in.has_view_mode() && in.view_mode() != v1::VIEW_MODE_UNSPECIFIED) {
    DDGI_ASSIGN_OR_RETURN(next.view, view_from_proto(in.view_mode()));
  }
  if (in.has_jpeg_quality()) {
    if (in.jpeg_quality() < 1 || in.jpeg_quality() > 100) {
      return invalid_argument("settings.jpeg_quality must be in [1, 100] (got " +
                              std::to_string(in.jpeg_quality()) + ")");
    }
    next.jpeg_quality = static_cast<int>(in.jpeg_quality());
  }
  config = next;
  return ok_status();
}

void to_proto(const ViewConfig& config, v1::ViewSettings* out) {
  out->set_width(config.width);
  out->set_height(config.height);
  out->set_exposure(config.exposure);
  switch (config.tonemap) {
    case Tonemap::kAces:
      out->set_tonemap(v1::TONEMAP_ACES);
      break;
    case Tonemap::kReinhard:
      out->set_tonemap(v1::TONEMAP_REINHARD);
      break;
    case Tonemap::kClamp:
      out->set_tonemap(v1::TONEMAP_CLAMP);
      break;
  }
  // Indexed by View; the service never makes the atlas view (View::kAtlas), which has no mode.
  static const v1::ViewMode kModes[] = {v1::VIEW_MODE_FULL,     v1::VIEW_MODE_DIRECT,
                                        v1::VIEW_MODE_INDIRECT, v1::VIEW_MODE_ALBEDO,
                                        v1::VIEW_MODE_NORMAL,   v1::VIEW_MODE_PROBES};
  static_assert(std::size(kModes) == size_t(View::kProbes) + 1);
  out->set_view_mode(kModes[static_cast<uint32_t>(config.view)]);
  out->set_jpeg_quality(static_cast<uint32_t>(config.jpeg_quality));
}

Result<Camera> camera_from_proto(const v1::Camera& in, const Camera& base) {
  Camera camera = base;
  camera.position = from_proto(in.position());
  DDGI_TRY(check_position(camera.position, "camera.position"));
  glm::vec3 forward;
  switch (in.aim_case()) {
    case v1::Camera::kTarget: {
      const glm::vec3 target = from_proto(in.target());
      DDGI_TRY(check_position(target, "camera.target"));
      forward = target - camera.position;
      if (glm::length(forward) < 1e-6f * std::max(1.0f, glm::length(camera.position))) {
        return invalid_argument("camera.target must differ from camera.position");
      }
      break;
    }
    case v1::Camera::kForward:
      forward = from_proto(in.forward());
      DDGI_TRY(check_direction(forward, "camera.forward"));
      break;
    default:
      return invalid_argument("camera needs a target or a forward direction");
  }
  glm::vec3 up{0.0f, 1.0f, 0.0f};
  if (in.has_up()) {
    up = from_proto(in.up());
    DDGI_TRY(check_direction(up, "camera.up"));
  }
  forward = glm::normalize(forward);
  up = glm::normalize(up);
  const glm::vec3 side = glm::cross(forward, up);
  if (glm::length(side) < 1e-4f) {
    return invalid_argument("camera.up " + vec_text(up) + " is parallel to the viewing direction " +
                            vec_text(forward));
  }
  camera.forward = forward;
  camera.up = glm::normalize(glm::cross(side, forward));
  float fov = in.vertical_fov_degrees();
  if (fov == 0.0f) fov = 45.0f;
  if (!std::isfinite(fov) || !(fov > 0.0f) || fov > kMaxCameraYfovDegrees) {
    return invalid_argument("camera.vertical_fov_degrees must be finite and in (0, " +
                            num(kMaxCameraYfovDegrees) + "] (got " +
                            num(in.vertical_fov_degrees()) + ")");
  }
  camera.yfov = camera_yfov_radians(fov);
  return camera;
}

void to_proto(const Camera& camera, v1::Camera* out) {
  to_proto(camera.position, out->mutable_position());
  to_proto(camera.forward, out->mutable_forward());
  to_proto(camera.up, out->mutable_up());
  out->set_vertical_fov_degrees(camera.yfov * 180.0f / kPi);
}

Result<Light> light_from_proto(const v1::Light& in, const Light& base) {
  Light light = base;
  if (in.has_name()) {
    if (in.name().size() > 256) {
      return invalid_argument("light.name is " + std::to_string(in.name().size()) +
                              " bytes long; at most 256 are allowed");
    }
    light.name = in.name();
  }
  switch (in.type()) {
    case v1::LIGHT_TYPE_UNSPECIFIED:
      break;
    case v1::LIGHT_TYPE_POINT:
      light.type = LightType::kPoint;
      break;
    case v1::LIGHT_TYPE_SPOT:
      light.type = LightType::kSpot;
      break;
    case v1::LIGHT_TYPE_DIRECTIONAL:
      light.type = LightType::kDirectional;
      break;
    default:
      return invalid_argument("light.type " + std::to_string(int(in.type())) +
                              " is not a LightType");
  }
  if (in.has_color()) {
    const glm::vec3 color = from_proto(in.color());
    if (!finite(color) || glm::any(glm::lessThan(color, glm::vec3(0.0f))) ||
        glm::any(glm::greaterThan(color, glm::vec3(kMaxMagnitude)))) {
      return invalid_argument("light.color must be finite with each component in [0, 1e9] (got " +
                              vec_text(color) + ")");
    }
    light.color = color;
  }
  if (in.has_intensity()) {
    DDGI_TRY(check_scalar(in.intensity(), 0.0f, kMaxMagnitude, "light.intensity"));
    light.intensity = in.intensity();
  }
  if (in.has_range()) {
    DDGI_TRY(check_scalar(in.range(), 0.0f, kMaxMagnitude, "light.range"));
    light.range = in.range();
  }
  if (in.has_radius()) {
    DDGI_TRY(check_scalar(in.radius(), 0.0f, kMaxMagnitude, "light.radius"));
    light.radius = in.radius();
  }
  if (in.has_inner_cone_degrees()) {
    DDGI_TRY(check_scalar(in.inner_cone_degrees(), 0.0f, 90.0f, "light.inner_cone_degrees"));
    light.inner_cone_angle = in.inner_cone_degrees() * kPi / 180.0f;
  }
  if (in.has_outer_cone_degrees()) {
    DDGI_TRY(check_scalar(in.outer_cone_degrees(), 0.0f, 90.0f, "light.outer_cone_degrees"));
    light.outer_cone_angle = in.outer_cone_degrees() * kPi / 180.0f;
  }
  if (light.inner_cone_angle > light.outer_cone_angle) {
    return invalid_argument("light.inner_cone_degrees (" +
                            num(light.inner_cone_angle * 180.0f / kPi) +
                            ") must not exceed light.outer_cone_degrees (" +
                            num(light.outer_cone_angle * 180.0f / kPi) + ")");
  }
  if (in.has_position()) {
    const glm::vec3 position = from_proto(in.position());
    DDGI_TRY(check_position(position, "light.position"));
    light.position = position;
  }
  if (in.has_direction()) {
    const glm::vec3 direction = from_proto(in.direction());
    DDGI_TRY(check_direction(direction, "light.direction"));
    light.direction = glm::normalize(direction);
  }
  return light;
}

void to_proto(const Light& light, v1::Light* out) {
  out->set_name(light.name);
  switch (light.type) {
    case LightType::kPoint:
      out->set_type(v1::LIGHT_TYPE_POINT);
      break;
    case LightType::kSpot:
      out->set_type(v1::LIGHT_TYPE_SPOT);
      break;
    case LightType::kDirectional:
      out->set_type(v1::LIGHT_TYPE_DIRECTIONAL);
      break;
  }
  to_proto(light.color, out->mutable_color());
  out->set_intensity(light.intensity);
  out->set_range(light.range);
  out->set_inner_cone_degrees(light.inner_cone_angle * 180.0f / kPi);
  out->set_outer_cone_degrees(light.outer_cone_angle * 180.0f / kPi);
  to_proto(light.position, out->mutable_position());
  to_proto(light.direction, out->mutable_direction());
  out->set_radius(light.radius);
}

Result<glm::mat4> matrix_from_proto(const v1::Matrix4& in) {
  if (in.m_size() != 16) {
    return invalid_argument("transform must have 16 values (column-major 4x4), got " +
                            std::to_string(in.m_size()));
  }
  glm::mat4 m;
  for (int i = 0; i < 16; ++i) {
    const float value = in.m(i);
    if (!std::isfinite(value) || std::abs(value) > kMaxCoordinate) {
      return invalid_argument("transform value " + std::to_string(i) +
                              " must be finite and in [-1e12, 1e12] (got " + num(value) + ")");
    }
    m[i / 4][i % 4] = value;
  }
  if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f) {
    return invalid_argument(
        "transform must be affine: its last row (values 3, 7, 11, 15) must be 0 0 0 1");
  }
  const float det = glm::determinant(glm::mat3(m));
  if (!(std::abs(det) > 1e-12f) || !std::isfinite(det)) {
    return invalid_argument("transform's upper 3x3 is singular (determinant " + num(det) +
                            "); it must be invertible");
  }
  return m;
}

void to_proto(const glm::mat4& matrix, v1::Matrix4* out) {
  out->clear_m();
  for (int i = 0; i < 16; ++i) out->add_m(matrix[i / 4][i % 4]);
}

Result<IrradianceQuery> query_from_proto(const v1::QueryPoint& in, size_t index) {
  const std::string what = "points[" + std::to_string(index) + "]";
  IrradianceQuery query;
  query.position = from_proto(in.position());
  DDGI_TRY(check_position(query.position, what + ".position"));
  query.normal = from_proto(in.normal());
  DDGI_TRY(check_direction(query.normal, what + ".normal"));
  query.normal = glm::normalize(query.normal);
  query.to_viewer = query.normal;
  if (in.has_to_viewer()) {
    query.to_viewer = from_proto(in.to_viewer());
    DDGI_TRY(check_direction(query.to_viewer, what + ".to_viewer"));
    query.to_viewer = glm::normalize(query.to_viewer);
  }
  return query;
}

Result<DirectMode> direct_mode_from_proto(v1::DirectMode mode) {
  switch (mode) {
    case v1::DIRECT_MODE_UNSPECIFIED:
    case v1::DIRECT_MODE_SHADOW_RAYS:
      return DirectMode::kTracedShadows;
    case v1::DIRECT_MODE_UNSHADOWED:
      return DirectMode::kUnshadowed;
    case v1::DIRECT_MODE_SHADOW_FIELD:
      return DirectMode::kShadowField;
    case v1::DIRECT_MODE_AMBIENT_OCCLUSION:
      return DirectMode::kAmbientOcclusion;
    case v1::DIRECT_MODE_AO_TRACED:
      return DirectMode::kAoTraced;
    case v1::DIRECT_MODE_AO_CACHE:
      return DirectMode::kAoCache;
    default:
      return invalid_argument("direct_mode " + std::to_string(int(mode)) + " is not a DirectMode");
  }
}

// ---- The session's state, outbound -------------------------------------------------------------

void to_proto(const SessionView& view, v1::ViewInfo* out) {
  out->set_view_id(view.id);
  to_proto(view.config, out->mutable_settings());
  to_proto(view.camera, out->mutable_camera());
  out->set_command_seq(view.seq);
}

void to_proto(const LightSlot& slot, v1::LightEntry* out) {
  out->set_light_id(slot.id);
  to_proto(slot.light, out->mutable_light());
}

void to_proto(const LightSlot& slot, uint64_t command_seq, v1::LightReply* out) {
  to_proto(slot, out->mutable_light());
  out->set_command_seq(command_seq);
}

namespace {

void instance_to_proto(const GpuScene& scene, uint32_t index, v1::Instance* out) {
  const Instance& instance = scene.scene().instances[index];
  out->set_index(index);
  out->set_name(instance.name);
  to_proto(instance.transform, out->mutable_transform());
}

}  // namespace

namespace {

// Every parameter of `table` with its value in `values`.
template <typename P>
void add_param_values(const ParamTable<P>& table, const P& values, v1::FieldParams* params) {
  for (const ParamSpec<P>& spec : table.specs()) {
    auto* p = params->add_params();
    p->set_name(spec.name);
    p->set_value(spec.format(values));
  }
}

}  // namespace

void to_proto(const GpuScene& scene, uint32_t index, uint64_t command_seq, v1::InstanceReply* out) {
  instance_to_proto(scene, index, out->mutable_instance());
  out->set_command_seq(command_seq);
}

void to_proto(const IrradianceField& field, uint64_t command_seq, v1::FieldParams* out) {
  out->Clear();
  out->set_field(v1::FIELD_KIND_IRRADIANCE);
  add_param_values(field_param_table(), field.params(), out);
  out->set_probes(probe_count(field.params()));
  out->set_gpu_bytes(field.gpu_bytes());
  out->set_updates(field.updates());
  out->set_command_seq(command_seq);
  const ProbeStateCounts counts = field.probe_counts();
  v1::ProbeStateCounts* states = out->mutable_probe_states();
  states->set_vigilant(counts.vigilant);
  states->set_awake(counts.awake);
  states->set_sleeping(counts.sleeping);
  states->set_off(counts.off);
  for (const FieldVolume& volume : field.volumes()) {
    v1::FieldVolume* v = out->add_volumes();
    to_proto(volume.origin, v->mutable_origin());
    to_proto(volume.spacing, v->mutable_spacing());
    v->set_counts_x(volume.counts.x);
    v->set_counts_y(volume.counts.y);
    v->set_counts_z(volume.counts.z);
    if (volume.static_volume) {
      v->set_static_volume(*volume.static_volume);
    } else {
      v->set_cascade(volume.cascade);
    }
    v->set_tracks_camera(volume.tracks(field.params()));
  }
}

void to_proto(const SessionScene& scene, uint64_t command_seq, v1::FieldParams* out) {
  to_proto(*scene.field(), command_seq, out);
  if (scene.budget()) to_proto(*scene.budget(), scene.label(), out->mutable_budget());
  scene.calibration_to_proto(out->mutable_calibration());
}

void to_proto(const ShadowField& field, uint64_t command_seq, v1::FieldParams* out) {
  out->Clear();
  out->set_field(v1::FIELD_KIND_SHADOW);
  add_param_values(shadow_param_table(), field.params(), out);
  out->set_probes(probe_count(field.params()));
  out->set_gpu_bytes(field.gpu_bytes());
  out->set_updates(field.updates());
  out->set_command_seq(command_seq);
}

void to_proto(const SessionState& session, uint64_t frames, uint64_t command_seq,
              v1::SessionInfo* out) {
  out->Clear();
  out->set_session_id(session.id);
  out->set_frames(frames);
  out->set_command_seq(command_seq);
  const SessionScene* scene = session.scene.get();
  if (!scene) {
    to_proto(Camera{}, out->mutable_default_camera());
    return;
  }
  out->set_scene(scene->label());
  out->set_gi(scene->field() != nullptr);
  for (const std::string& warning : scene->warnings()) out->add_warnings(warning);
  to_proto(scene->default_camera(), out->mutable_default_camera());
  out->set_triangles(scene->gpu_scene().triangle_count());
  out->set_gpu_bytes(scene->gpu_bytes());
  const size_t instances = scene->gpu_scene().scene().instances.size();
  for (size_t i = 0; i < instances; ++i) {
    instance_to_proto(scene->gpu_scene(), static_cast<uint32_t>(i), out->add_instances());
  }
  for (const LightSlot& slot : scene->lights().slots()) to_proto(slot, out->add_lights());
  for (const auto& [view_id, view] : session.views.all()) to_proto(view, out->add_views());
  if (scene->field()) to_proto(*scene, command_seq, out->mutable_field());
  if (const WorldCache* cache = scene->world_cache()) {
    const WorldCacheCounters c = cache->counters();
    v1::WorldCacheInfo* info = out->mutable_world_cache();
    info->set_capacity(cache->capacity());
    info->set_occupied(c.live());
    info->set_inserted(c.inserted);
    info->set_evicted(c.evicted);
    info->set_dropped(c.dropped);
    info->set_checksum_rejects(c.checksum_rejects);
    info->set_gpu_bytes(cache->gpu_bytes());
  }
}

void to_proto(const SessionState& session, uint64_t frames, v1::SessionSummary* out) {
  out->set_session_id(session.id);
  out->set_created_unix_us(session.created_unix_us);
  out->set_scene(session.scene ? session.scene->label() : "");
  out->set_views(static_cast<uint32_t>(session.views.size()));
  out->set_streams(session.views.stream_count());
  out->set_frames(frames);
}

void to_proto(const FrameRecord& frame, v1::Frame* out) {
  out->set_session_id(frame.session_id);
  out->set_view_id(frame.view_id);
  out->set_frame_index(frame.index);
  out->set_width(frame.width);
  out->set_height(frame.height);
  to_proto(frame.camera, out->mutable_camera());
  double gpu_ms = 0.0;
  for (const auto* passes : {&frame.gi_passes, &frame.view_passes}) {
    for (const vk::PassTime& pass : *passes) {
      auto* p = out->add_passes();
      p->set_name(pass.name);
      p->set_milliseconds(pass.milliseconds);
      gpu_ms += pass.milliseconds;
    }
  }
  out->set_gpu_ms(gpu_ms);
  out->set_gi_update_ms(frame.gi_ms);
  out->set_last_command_seq(frame.last_applied.seq);
  out->set_last_command_arrival_unix_us(frame.last_applied.arrival_unix_us);
  out->set_rendered_unix_us(frame.rendered_unix_us);
  out->set_field_updates(frame.field_updates);
}

void to_proto(const std::vector<glm::vec3>& irradiance, uint64_t field_updates,
              v1::QueryIrradianceReply* out) {
  for (const glm::vec3& value : irradiance) to_proto(value, out->add_irradiance());
  out->set_field_updates(field_updates);
}

}  // namespace ddgi::service
