#include "scene/gltf_loader.h"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <system_error>

#include "scene/glb_container.h"
#include "scene/gltf_convert.h"
#include "scene/gltf_parse.h"
#include "scene/gltf_validate.h"
#include "scene/scene_files.h"
#include "scene/sidecar.h"

namespace ddgi {
namespace {

namespace fs = std::filesystem;

bool ends_with_lowercase(const std::string& text, const std::string& suffix) {
  if (text.size() < suffix.size()) return false;
  std::string tail = text.substr(text.size() - suffix.size());
  std::transform(tail.begin(), tail.end(), tail.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return tail == suffix;
}

Result<Scene> load_model(std::span<const uint8_t> bytes, const SceneFolder& folder,
                         const MaterialOverrides& overrides, const SceneLimits& limits) {
  DDGI_ASSIGN_OR_RETURN(const tinygltf::Model model, parse_gltf(bytes, folder, limits));
  DDGI_TRY(validate_gltf(model));
  return convert_gltf(model, overrides, limits);
}

void finish(const std::string& source, Scene* scene) {
  scene->source = source;
  if (!scene->has_any_light()) {
    scene->warnings.push_back(
        "the scene has no light: no punctual light, no emissive material in use and no "
        "environment (add one with a sidecar, docs/sidecar-format.md)");
  }
}

Result<Scene> load_from_memory(std::span<const uint8_t> bytes, const std::string& name,
                               const SceneLimits& limits) {
  DDGI_TRY(validate_limits(limits));
  if (bytes.size() > limits.max_file_bytes) {
    return resource_exhausted(name + ": " + std::to_string(bytes.size()) +
                              " bytes, more than the limit of " +
                              std::to_string(limits.max_file_bytes));
  }
  Result<Scene> scene = load_model(bytes, SceneFolder(), {}, limits);
  if (!scene.ok()) return scene.error().with_context(name);
  finish(name, &*scene);
  return scene;
}

// A glTF file on disk with an optional sidecar already parsed.
Result<Scene> load_gltf_file(const fs::path& path, const Sidecar* sidecar,
                             const SceneLimits& limits) {
  DDGI_ASSIGN_OR_RETURN(const std::vector<uint8_t> bytes, read_file(path, limits.max_file_bytes));
  Result<SceneFolder> folder = SceneFolder::at(path.parent_path());
  if (!folder.ok()) return folder.error().with_context(path.string());
  const MaterialOverrides no_overrides;
  Result<Scene> scene =
      load_model(bytes, *folder, sidecar ? sidecar->materials : no_overrides, limits);
  if (!scene.ok()) return scene.error().with_context(path.string());
  if (sidecar) DDGI_TRY(apply_sidecar(*sidecar, limits, &*scene));
  finish(path.string(), &*scene);
  return scene;
}

// A sidecar beside a glTF may name a scene only if it names that glTF.
Status check_sidecar_scene(const Sidecar& sidecar, const fs::path& gltf) {
  if (!sidecar.scene) return ok_status();
  std::error_code ec;
  if (!fs::equivalent(*sidecar.scene, gltf, ec)) {
    return invalid_argument(sidecar.file.string() + ": scene: names " + sidecar.scene->string() +
                            ", but this sidecar sits beside " + gltf.string() +
                            " (only a sidecar loaded directly may name another scene)");
  }
  return ok_status();
}

}  // namespace

Result<Scene> load_scene(const std::string& path, const SceneLimits& limits) {
  DDGI_TRY(validate_limits(limits));
  const fs::path file(path);
  if (ends_with_lowercase(path, ".ddgi.json")) {
    DDGI_ASSIGN_OR_RETURN(const Sidecar sidecar, read_sidecar(file, limits));
    if (!sidecar.scene) {
      return invalid_argument(path + ": scene: required when the sidecar is loaded directly");
    }
    if (!ends_with_lowercase(sidecar.scene->string(), ".gltf") &&
        !ends_with_lowercase(sidecar.scene->string(), ".glb")) {
      return invalid_argument(path + ": scene: expected a .gltf or .glb file, got " +
                              sidecar.scene->string());
    }
    return load_gltf_file(*sidecar.scene, &sidecar, limits);
  }
  if (!ends_with_lowercase(path, ".gltf") && !ends_with_lowercase(path, ".glb")) {
    return invalid_argument(path + ": not a scene file (expected .gltf, .glb or .ddgi.json)");
  }
  const fs::path beside = sidecar_beside(file);
  std::error_code ec;
  if (fs::exists(beside, ec)) {
    DDGI_ASSIGN_OR_RETURN(const Sidecar sidecar, read_sidecar(beside, limits));
    DDGI_TRY(check_sidecar_scene(sidecar, file));
    return load_gltf_file(file, &sidecar, limits);
  }
  return load_gltf_file(file, nullptr, limits);
}

Result<Scene> load_glb_from_memory(std::span<const uint8_t> bytes, const std::string& name,
                                   const SceneLimits& limits) {
  if (!has_glb_magic(bytes)) return invalid_argument(name + ": not a GLB file (no 'glTF' magic)");
  return load_from_memory(bytes, name, limits);
}

Result<Scene> load_gltf_from_memory(std::span<const uint8_t> bytes, const std::string& name,
                                    const SceneLimits& limits) {
  if (has_glb_magic(bytes)) {
    return invalid_argument(name + ": is a GLB file; expected glTF JSON text");
  }
  return load_from_memory(bytes, name, limits);
}

}  // namespace ddgi
