// Payloads and ray types of the pipeline backend (shared by ray-generation and hit shaders).
#ifndef DDGI_COMMON_RAY_PAYLOADS_GLSL
#define DDGI_COMMON_RAY_PAYLOADS_GLSL

const uint kRayTypeClosest = 0u;  // SBT hit group 0, miss shader 0
const uint kRayTypeShadow = 1u;   // SBT hit group 1, miss shader 1
const int kPayloadClosest = 0;
const int kPayloadShadow = 1;

// Thin glass a closest-hit ray passes, folded into that ray (no second traversal): candidates
// arrive in no particular order and some lie beyond the surface finally found, so each layer
// is kept with its distance and only those in front of the hit count (glass_before). More
// layers than fit are counted, and the ray's transmittance is then traced exactly.
const uint kMaxGlassLayers = 3u;
struct GlassLayers {
  uint count;                     // layers seen, also those that did not fit
  vec4 layer[kMaxGlassLayers];    // (transmittance rgb, distance)
};

void add_glass_layer(inout GlassLayers g, float t, vec3 passed) {
  if (g.count < kMaxGlassLayers) g.layer[g.count] = vec4(passed, t);
  ++g.count;
}

// Transmittance of the layers in front of distance t; false when some did not fit.
bool glass_before(GlassLayers g, float t, out vec3 transmittance) {
  transmittance = vec3(1.0);
  for (uint i = 0u; i < min(g.count, kMaxGlassLayers); ++i) {
    if (g.layer[i].w < t) transmittance *= g.layer[i].rgb;
  }
  return g.count <= kMaxGlassLayers;
}

struct ClosestPayload {
  float t;  // < 0: miss
  uint instance;
  uint geometry;
  uint primitive;
  vec2 barycentrics;
  GlassLayers glass;
};

struct ShadowPayload {
  vec3 transmittance;  // starts at 1; 0 once an opaque surface is hit
};

#endif
