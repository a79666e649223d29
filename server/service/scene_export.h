// The session's scene as one binary glTF 2.0 file (ExportScene, docs/web.md): what a client
// needs to draw it itself and shade it from streamed probes. Geometry, materials (base colour,
// emission, alpha, thin transmission) and images as the server uses them, every instance in its
// current world placement, and the session's current lights as KHR_lights_punctual. Written
// here from the CPU scene (not the uploaded file: library scenes may be .gltf with side files,
// and transforms and lights change after loading) through tinygltf.
#pragma once

#include <cstdint>
#include <vector>

#include "core/result.h"
#include "ddgi/v1/render_service.pb.h"
#include "scene/scene.h"
#include "service/light_set.h"

namespace ddgi::service {

struct ExportedScene {
  v1::SceneMetadata metadata;  // total_bytes and the counts; the caller sets the label
  std::vector<uint8_t> glb;
};

// `scene` with the session's `lights` in place of its own. Nodes carry what the API calls them
// by: extras.ddgi_instance (SetInstanceTransform's index), extras.ddgi_light_id. Base colour and
// emissive images go as JPEG (quality 92) unless their alpha is used (mask or blend materials):
// PNG.
Result<ExportedScene> export_glb(const Scene& scene, const std::vector<LightSlot>& lights);

}  // namespace ddgi::service
