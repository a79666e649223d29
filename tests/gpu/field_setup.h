// A scene on the GPU and an irradiance field over it, for tests that update a field and read
// it back.
#pragma once

#include <memory>

#include "gi/irradiance_field.h"
#include "gpu_scene/gpu_scene.h"

namespace ddgi::test {

struct FieldSetup {
  std::unique_ptr<GpuScene> scene;
  std::unique_ptr<IrradianceField> field;  // null (and the test failed) when anything failed
};

// On the test binary's context (gpu_context()).
FieldSetup make_field_setup(const Scene& scene, const IrradianceFieldParams& params,
                            vk::TraceBackend backend = vk::TraceBackend::kRayQuery);

}  // namespace ddgi::test
