// Mean luminance of frames and of path-traced references, for the tests that compare a field's
// light with the path tracer's (default_energy_test.cpp, session_choice_test.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "render/path_tracer.h"
#include "scene/scene.h"

namespace ddgi::test {

// Mean Rec. 709 luminance of linear RGBA.
double mean_luminance(const std::vector<float>& rgba);

// The path tracer's mean luminance of `view` of `scene` seen by `camera` at width x height, `spp`
// samples at pixel centres (as frames trace); -1 and the test failed when anything failed.
double path_traced_mean(const Scene& scene, const Camera& camera, uint32_t width, uint32_t height,
                        PathTraceView view, uint32_t spp);

}  // namespace ddgi::test
