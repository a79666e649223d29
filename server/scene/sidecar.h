// Scene sidecar files (`*.ddgi.json`, docs/sidecar-format.md): what glTF cannot say (the
// environment, extra lights, a camera, material fixes, the probe grid). Parsing is strict:
// unknown or repeated keys are errors, and every error names the file, the key path and what
// was expected.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <vector>

#include "core/result.h"
#include "scene/material_override.h"
#include "scene/scene.h"
#include "scene/scene_limits.h"

namespace ddgi {

struct SidecarEnvironment {
  std::optional<glm::vec3> color;
  std::optional<std::filesystem::path> image;  // resolved against the sidecar's folder
  float intensity = 1.0f;
  float rotation_radians = 0.0f;
};

struct Sidecar {
  std::filesystem::path file;                  // the sidecar itself, for messages
  std::optional<std::filesystem::path> scene;  // resolved against the sidecar's folder
  std::optional<Camera> camera;
  std::optional<SidecarEnvironment> environment;
  std::vector<Light> lights;
  MaterialOverrides materials;
  std::optional<GridPlacement> probe_grid;
  std::vector<GridPlacement> probe_volumes;
};

// `file` locates relative paths and prefixes error messages; nothing is read from it.
Result<Sidecar> parse_sidecar(std::span<const uint8_t> text, const std::filesystem::path& file,
                              const SceneLimits& limits);
Result<Sidecar> read_sidecar(const std::filesystem::path& file, const SceneLimits& limits);

// The sidecar path beside a glTF: "dir/name.gltf" -> "dir/name.ddgi.json".
std::filesystem::path sidecar_beside(const std::filesystem::path& gltf);

// Applies camera, environment (loading its image), lights and probe grid to a scene whose
// materials were already converted with `sidecar.materials`; fails when a material name in
// the sidecar matches no material.
Status apply_sidecar(const Sidecar& sidecar, const SceneLimits& limits, Scene* scene);

}  // namespace ddgi
