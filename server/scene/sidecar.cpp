#include "scene/sidecar.h"

#include <cmath>
#include <string>
#include <vector>

#include "scene/exr_image.h"
#include "scene/json_fields.h"
#include "scene/json_precheck.h"
#include "scene/scene_files.h"

namespace ddgi {
namespace {

namespace fs = std::filesystem;
using namespace json_fields;

constexpr float kDegrees = static_cast<float>(M_PI / 180.0);

// A path relative to the sidecar's folder.
Result<fs::path> read_relative_path(const json& value, const std::string& path,
                                    const fs::path& folder) {
  DDGI_ASSIGN_OR_RETURN(const std::string text, read_string(value, path));
  if (text.empty() || fs::path(text).is_absolute()) {
    return expected(path, "a path relative to the sidecar's folder", value);
  }
  return folder / text;
}

Result<Camera> read_camera(const json& value) {
  const std::string path = "camera";
  DDGI_TRY(check_object(value, path, {"position", "target", "up", "yfov_degrees"}));
  if (!value.contains("position") || !value.contains("target")) {
    return invalid_argument(path + ": 'position' and 'target' are required");
  }
  DDGI_ASSIGN_OR_RETURN(const glm::vec3 position,
                        read_vector<3>(value["position"], path + ".position", kAny));
  DDGI_ASSIGN_OR_RETURN(const glm::vec3 target,
                        read_vector<3>(value["target"], path + ".target", kAny));
  glm::vec3 up(0.0f, 1.0f, 0.0f);
  if (value.contains("up")) {
    DDGI_ASSIGN_OR_RETURN(up, read_direction(value["up"], path + ".up"));
  }
  float yfov = camera_yfov_radians(45.0f);
  if (value.contains("yfov_degrees")) {
    DDGI_ASSIGN_OR_RETURN(const float degrees,
                          read_number(value["yfov_degrees"], path + ".yfov_degrees",
                                      Range{0.0, kMaxCameraYfovDegrees, true, false}));
    yfov = camera_yfov_radians(degrees);
  }
  Result<Camera> camera = look_at_camera(position, target, up, yfov);
  if (!camera.ok()) return camera.error().with_context(path);
  camera->name = "sidecar";
  return camera;
}

Result<SidecarEnvironment> read_environment(const json& value, const fs::path& folder) {
  const std::string path = "environment";
  DDGI_TRY(check_object(value, path, {"color", "image", "intensity", "rotation_degrees"}));
  SidecarEnvironment env;
  if (value.contains("color") && value.contains("image")) {
    return invalid_argument(path + ": give 'color' or 'image', not both");
  }
  if (value.contains("color")) {
    DDGI_ASSIGN_OR_RETURN(env.color, read_vector<3>(value["color"], path + ".color", kNonNegative));
  }
  if (value.contains("image")) {
    DDGI_ASSIGN_OR_RETURN(env.image, read_relative_path(value["image"], path + ".image", folder));
    std::string extension = env.image->extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (extension != ".exr") return expected(path + ".image", "an .exr file", value["image"]);
  }
  if (value.contains("intensity")) {
    DDGI_ASSIGN_OR_RETURN(env.intensity,
                          read_number(value["intensity"], path + ".intensity", kNonNegative));
  }
  if (value.contains("rotation_degrees")) {
    DDGI_ASSIGN_OR_RETURN(const float degrees,
                          read_number(value["rotation_degrees"], path + ".rotation_degrees", kAny));
    env.rotation_radians = degrees * kDegrees;
  }
  return env;
}

Result<Light> read_light(const json& value, const std::string& path) {
  if (!value.is_object() || !value.contains("type")) {
    return expected(path, "an object with a 'type'", value);
  }
  DDGI_ASSIGN_OR_RETURN(const std::string type, read_string(value["type"], path + ".type"));
  Light light;
  if (type == "point") {
    light.type = LightType::kPoint;
    DDGI_TRY(check_object(value, path,
                          {"type", "name", "position", "color", "intensity", "range", "radius"}));
  } else if (type == "spot") {
    light.type = LightType::kSpot;
    DDGI_TRY(check_object(value, path,
                          {"type", "name", "position", "direction", "color", "intensity", "range",
                           "radius", "inner_cone_degrees", "outer_cone_degrees"}));
  } else if (type == "directional") {
    light.type = LightType::kDirectional;
    DDGI_TRY(check_object(value, path, {"type", "name", "direction", "color", "intensity"}));
  } else {
    return expected(path + ".type", "\"point\", \"spot\" or \"directional\"", value["type"]);
  }
  const bool positioned = light.type != LightType::kDirectional;
  const bool directed = light.type != LightType::kPoint;
  if (positioned && !value.contains("position")) {
    return invalid_argument(path + ": 'position' is required for a " + type + " light");
  }
  if (directed && !value.contains("direction")) {
    return invalid_argument(path + ": 'direction' is required for a " + type + " light");
  }
  if (value.contains("name")) {
    DDGI_ASSIGN_OR_RETURN(light.name, read_string(value["name"], path + ".name"));
  }
  if (positioned) {
    DDGI_ASSIGN_OR_RETURN(light.position,
                          read_vector<3>(value["position"], path + ".position", kAny));
  }
  if (directed) {
    DDGI_ASSIGN_OR_RETURN(light.direction, read_direction(value["direction"], path + ".direction"));
  }
  if (value.contains("color")) {
    DDGI_ASSIGN_OR_RETURN(light.color,
                          read_vector<3>(value["color"], path + ".color", kNonNegative));
  }
  if (value.contains("intensity")) {
    DDGI_ASSIGN_OR_RETURN(light.intensity,
                          read_number(value["intensity"], path + ".intensity", kNonNegative));
  }
  if (value.contains("range")) {
    DDGI_ASSIGN_OR_RETURN(light.range, read_number(value["range"], path + ".range", kNonNegative));
  }
  if (value.contains("radius")) {
    DDGI_ASSIGN_OR_RETURN(light.radius,
                          read_number(value["radius"], path + ".radius", kNonNegative));
  }
  if (light.type == LightType::kSpot) {
    float inner = 0.0f;
    float outer = 45.0f;
    if (value.contains("inner_cone_degrees")) {
      DDGI_ASSIGN_OR_RETURN(inner, read_number(value["inner_cone_degrees"],
                                               path + ".inner_cone_degrees", Range{0.0, 90.0}));
    }
    if (value.contains("outer_cone_degrees")) {
      DDGI_ASSIGN_OR_RETURN(outer,
                            read_number(value["outer_cone_degrees"], path + ".outer_cone_degrees",
                                        Range{0.0, 90.0, true, false}));
    }
    if (!(inner < outer)) {
      return invalid_argument(path + ": inner_cone_degrees (" + number_text(inner) +
                              ") must be less than outer_cone_degrees (" + number_text(outer) +
                              ")");
    }
    light.inner_cone_angle = inner * kDegrees;
    light.outer_cone_angle = outer * kDegrees;
  }
  return light;
}

Result<MaterialOverride> read_material(const json& value, const std::string& path) {
  DDGI_TRY(check_object(
      value, path,
      {"base_color", "emissive", "emissive_strength", "transmission", "double_sided"}));
  MaterialOverride o;
  if (value.contains("base_color")) {
    DDGI_ASSIGN_OR_RETURN(o.base_color,
                          read_vector<4>(value["base_color"], path + ".base_color", kUnit));
  }
  if (value.contains("emissive")) {
    DDGI_ASSIGN_OR_RETURN(o.emissive,
                          read_vector<3>(value["emissive"], path + ".emissive", kNonNegative));
  }
  if (value.contains("emissive_strength")) {
    DDGI_ASSIGN_OR_RETURN(
        o.emissive_strength,
        read_number(value["emissive_strength"], path + ".emissive_strength", kNonNegative));
  }
  if (value.contains("transmission")) {
    DDGI_ASSIGN_OR_RETURN(o.transmission,
                          read_number(value["transmission"], path + ".transmission", kUnit));
  }
  if (value.contains("double_sided")) {
    const json& flag = value["double_sided"];
    if (!flag.is_boolean()) return expected(path + ".double_sided", "true or false", flag);
    o.double_sided = flag.get<bool>();
  }
  return o;
}

Result<GridPlacement> read_probe_grid(const json& value, const std::string& path) {
  DDGI_TRY(check_object(value, path, {"origin", "spacing", "counts"}));
  if (!value.contains("origin") || !value.contains("spacing") || !value.contains("counts")) {
    return invalid_argument(path + ": 'origin', 'spacing' and 'counts' are all required");
  }
  GridPlacement grid;
  DDGI_ASSIGN_OR_RETURN(grid.origin, read_vector<3>(value["origin"], path + ".origin", kAny));
  DDGI_ASSIGN_OR_RETURN(grid.spacing,
                        read_vector<3>(value["spacing"], path + ".spacing", kPositive));
  const json& counts = value["counts"];
  const std::string what = "an array of 3 integers, each in [1, 512]";
  if (!counts.is_array() || counts.size() != 3) return expected(path + ".counts", what, counts);
  for (int i = 0; i < 3; ++i) {
    const json& c = counts[static_cast<size_t>(i)];
    if (!c.is_number_integer() || c.get<int64_t>() < 1 || c.get<int64_t>() > 512) {
      return expected(path + ".counts", what, counts);
    }
    grid.counts[i] = static_cast<int>(c.get<int64_t>());
  }
  return grid;
}

Result<Sidecar> parse_document(const json& root, const fs::path& file) {
  DDGI_TRY(check_object(
      root, "",
      {"scene", "camera", "environment", "lights", "materials", "probe_grid", "probe_volumes"}));
  const fs::path folder = file.parent_path();
  Sidecar sidecar;
  sidecar.file = file;
  if (root.contains("scene")) {
    DDGI_ASSIGN_OR_RETURN(sidecar.scene, read_relative_path(root["scene"], "scene", folder));
  }
  if (root.contains("camera")) {
    DDGI_ASSIGN_OR_RETURN(sidecar.camera, read_camera(root["camera"]));
  }
  if (root.contains("environment")) {
    DDGI_ASSIGN_OR_RETURN(sidecar.environment, read_environment(root["environment"], folder));
  }
  if (root.contains("lights")) {
    const json& lights = root["lights"];
    if (!lights.is_array()) return expected("lights", "an array of lights", lights);
    for (size_t i = 0; i < lights.size(); ++i) {
      DDGI_ASSIGN_OR_RETURN(Light light,
                            read_light(lights[i], "lights[" + std::to_string(i) + "]"));
      sidecar.lights.push_back(std::move(light));
    }
  }
  if (root.contains("materials")) {
    const json& materials = root["materials"];
    if (!materials.is_object()) {
      return expected("materials", "an object of material names", materials);
    }
    for (const auto& [name, value] : materials.items()) {
      DDGI_ASSIGN_OR_RETURN(sidecar.materials[name], read_material(value, "materials." + name));
    }
  }
  if (root.contains("probe_grid")) {
    DDGI_ASSIGN_OR_RETURN(sidecar.probe_grid, read_probe_grid(root["probe_grid"], "probe_grid"));
  }
  if (root.contains("probe_volumes")) {
    const json& volumes = root["probe_volumes"];
    const std::string what = "an array of at most " + std::to_string(kMaxSceneProbeVolumes) +
                             " grids (the field holds one more: its own grid)";
    if (!volumes.is_array() || volumes.size() > kMaxSceneProbeVolumes) {
      return expected("probe_volumes", what, volumes);
    }
    for (size_t i = 0; i < volumes.size(); ++i) {
      DDGI_ASSIGN_OR_RETURN(
          GridPlacement volume,
          read_probe_grid(volumes[i], "probe_volumes[" + std::to_string(i) + "]"));
      sidecar.probe_volumes.push_back(volume);
    }
  }
  return sidecar;
}

}  // namespace

Result<Sidecar> parse_sidecar(std::span<const uint8_t> text, const fs::path& file,
                              const SceneLimits& limits) {
  const std::string context = file.string();
  Status nesting = precheck_json(text, limits.max_json_depth);
  if (!nesting.ok()) return nesting.error().with_context(context);
  Result<json> root = parse_json_strict(text);
  if (!root.ok()) return root.error().with_context(context);
  Result<Sidecar> sidecar = parse_document(*root, file);
  if (!sidecar.ok()) return sidecar.error().with_context(context);
  return sidecar;
}

Result<Sidecar> read_sidecar(const fs::path& file, const SceneLimits& limits) {
  // A sidecar is small; a large one is a mistake, not a scene.
  constexpr uint64_t kMaxSidecarBytes = 16ull << 20;
  DDGI_ASSIGN_OR_RETURN(const std::vector<uint8_t> text, read_file(file, kMaxSidecarBytes));
  return parse_sidecar(text, file, limits);
}

fs::path sidecar_beside(const fs::path& gltf) {
  return gltf.parent_path() / (gltf.stem().string() + ".ddgi.json");
}

Status apply_sidecar(const Sidecar& sidecar, const SceneLimits& limits, Scene* scene) {
  const std::string context = sidecar.file.string();
  for (const auto& [name, unused] : sidecar.materials) {
    bool found = false;
    for (const Material& m : scene->materials) found = found || m.name == name;
    if (!found) {
      return invalid_argument(context + ": materials." + name +
                              ": no material with this name in the scene");
    }
  }
  if (sidecar.camera) scene->cameras.insert(scene->cameras.begin(), *sidecar.camera);
  if (sidecar.environment) {
    const SidecarEnvironment& env = *sidecar.environment;
    scene->environment.color = env.color.value_or(glm::vec3(0.0f));
    scene->environment.intensity = env.intensity;
    scene->environment.rotation_y = env.rotation_radians;
    if (env.image) {
      Result<EnvironmentImage> image = load_exr_environment(*env.image, limits, &scene->warnings);
      if (!image.ok()) return image.error().with_context(context + ": environment.image");
      scene->environment.image = std::move(image).value();
    }
  }
  if (scene->lights.size() + sidecar.lights.size() > limits.max_lights) {
    return resource_exhausted(context + ": lights: the scene would have more than the limit of " +
                              std::to_string(limits.max_lights) + " lights");
  }
  scene->lights.insert(scene->lights.end(), sidecar.lights.begin(), sidecar.lights.end());
  if (sidecar.probe_grid) scene->probe_grid = sidecar.probe_grid;
  if (!sidecar.probe_volumes.empty()) scene->probe_volumes = sidecar.probe_volumes;
  return ok_status();
}

}  // namespace ddgi
