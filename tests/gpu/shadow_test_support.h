// What the shadow-field tests share: the repo's test scenes, point sets on them, and the error
// of the field's visibility against traced visibility.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "gi/shadow_field.h"
#include "gpu_scene/gpu_scene.h"
#include "scene/scene.h"
#include "vk/context.h"

namespace ddgi::test {

// scenes/NAME, loaded (the test fails if it does not load).
Scene load_repo_scene(const std::string& name);

struct ShadowSetup {
  std::unique_ptr<GpuScene> scene;
  std::unique_ptr<ShadowField> field;
};
ShadowSetup make_shadow_setup(vk::Context& context, const Scene& scene,
                              const ShadowFieldParams& params, vk::TraceBackend backend);

// box_on_floor.gltf's grid: 0.5 m probes over x, z in [-2.75, 3.25] (the light, the cube and
// its shadow), two layers at y = 0.25 and 0.75 and one above the cube at 1.25.
ShadowFieldParams box_on_floor_grid();

// Floor points (normal +y, seen from above) on a regular grid over x in [x0, x1], z in
// [z0, z1] with `step`, skipping the cube's footprint |x|, |z| <= 0.55.
std::vector<ShadowFieldQuery> box_floor_points(float x0, float x1, float z0, float z1, float step);

// Mean |field - traced| visibility of light `light` over the answers.
float mean_abs_visibility_error(const std::vector<ShadowFieldAnswer>& answers, uint32_t light);

// True when every field and traced value is finite.
bool all_finite(const std::vector<ShadowFieldAnswer>& answers);

}  // namespace ddgi::test
