// Payloads and ray types of the pipeline backend (shared by ray-generation and hit shaders).
#ifndef DDGI_COMMON_RAY_PAYLOADS_GLSL
#define DDGI_COMMON_RAY_PAYLOADS_GLSL

const uint kRayTypeClosest = 0u;  // SBT hit group 0, miss shader 0
const uint kRayTypeShadow = 1u;   // SBT hit group 1, miss shader 1
const int kPayloadClosest = 0;
const int kPayloadShadow = 1;

struct ClosestPayload {
  float t;  // < 0: miss
  uint instance;
  uint geometry;
  uint primitive;
  vec2 barycentrics;
};

struct ShadowPayload {
  vec3 transmittance;  // starts at 1; 0 once an opaque surface is hit
};

#endif
