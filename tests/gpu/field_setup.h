// A GI stack (the scene on the GPU and an irradiance field over it) for tests that update a
// field and read it back, built the way the service and tools build theirs.
#pragma once

#include <memory>

#include "gi/gi_stack.h"
#include "render/renderer.h"

namespace ddgi::test {

struct FieldSetup {
  std::unique_ptr<GiStack> gi;
  GpuScene* scene = nullptr;
  IrradianceField* field = nullptr;  // null (and the test failed) when anything failed
};

// On the test binary's context (gpu_context()).
FieldSetup make_field_setup(const Scene& scene, const IrradianceFieldParams& params,
                            vk::TraceBackend backend = vk::TraceBackend::kRayQuery);

// A frame after `updates` of these fields (either may be null), recorded in one submission the
// way the service and tools do (gi_update_passes, then the frame).
Result<FrameResult> render_updated(Renderer& renderer, const FrameSettings& settings,
                                   IrradianceField* field, ShadowField* shadow_field = nullptr,
                                   GiUpdates updates = {});

}  // namespace ddgi::test
