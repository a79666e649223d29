// Bilinear upscaling of a path-traced image to the frame's size: how ddgi-eval --pareto scores
// the path tracer below one sample per pixel (traced at a fraction of the resolution each way,
// then stretched, as a stream would show it) against the full-size reference.
#pragma once

#include <cstdint>
#include <vector>

#include "render/path_tracer.h"

namespace ddgi::tools {

// `image` (radiance and tone-mapped pixels) resampled to width x height: each output pixel's
// centre mapped into the source and interpolated between the four nearest source pixels
// (edges clamped). Tone-mapped pixels are interpolated as stored (sRGB), as a display would.
PathTraceImage upscaled(const PathTraceImage& image, uint32_t width, uint32_t height);

}  // namespace ddgi::tools
