// Small math helpers shared by every kernel.
#ifndef DDGI_COMMON_MATH_GLSL
#define DDGI_COMMON_MATH_GLSL

const float kPi = 3.14159265358979;
const float kInvPi = 0.318309886183791;
const float kFloatMax = 3.402823e38;

vec3 safe_normalize(vec3 v, vec3 fallback) {
  const float len2 = dot(v, v);
  return len2 > 1e-30 && !isinf(len2) ? v * inversesqrt(len2) : fallback;
}

// Zero for NaN/Inf and negative values: radiance that may enter accumulations.
vec3 sanitize_radiance(vec3 c) {
  return vec3(isnan(c.x) || isinf(c.x) ? 0.0 : max(c.x, 0.0),
              isnan(c.y) || isinf(c.y) ? 0.0 : max(c.y, 0.0),
              isnan(c.z) || isinf(c.z) ? 0.0 : max(c.z, 0.0));
}

// Octahedral mapping of unit vectors to [-1, 1]^2 (Cigolle et al. 2014).
vec2 sign_not_zero(vec2 v) { return vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0); }

vec2 octahedral_encode(vec3 n) {
  const vec2 p = n.xy * (1.0 / (abs(n.x) + abs(n.y) + abs(n.z)));
  return n.z <= 0.0 ? (1.0 - abs(p.yx)) * sign_not_zero(p) : p;
}

vec3 octahedral_decode(vec2 e) {
  vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (v.z < 0.0) v.xy = (1.0 - abs(v.yx)) * sign_not_zero(v.xy);
  return normalize(v);
}

uint pack_normal(vec3 n) { return packSnorm2x16(octahedral_encode(n)); }
vec3 unpack_normal(uint packed) { return octahedral_decode(unpackSnorm2x16(packed)); }

// Offsets a ray origin off a surface so the new ray cannot hit that surface again, at any
// scale: a fixed number of float ULPs away from the surface along the geometric normal, and
// an absolute offset near the origin where ULPs become tiny (Waechter and Binder, "A Fast and
// Robust Method for Avoiding Self-Intersection", Ray Tracing Gems, 2019).
vec3 offset_ray_origin(vec3 p, vec3 n) {
  const float kOrigin = 1.0 / 32.0;
  const float kFloatScale = 1.0 / 65536.0;
  const float kIntScale = 256.0;
  const ivec3 of_i = ivec3(kIntScale * n);
  const vec3 p_i = vec3(intBitsToFloat(floatBitsToInt(p.x) + (p.x < 0.0 ? -of_i.x : of_i.x)),
                        intBitsToFloat(floatBitsToInt(p.y) + (p.y < 0.0 ? -of_i.y : of_i.y)),
                        intBitsToFloat(floatBitsToInt(p.z) + (p.z < 0.0 ? -of_i.z : of_i.z)));
  return vec3(abs(p.x) < kOrigin ? p.x + kFloatScale * n.x : p_i.x,
              abs(p.y) < kOrigin ? p.y + kFloatScale * n.y : p_i.y,
              abs(p.z) < kOrigin ? p.z + kFloatScale * n.z : p_i.z);
}

// Linear RGB (0..1) to 8-bit sRGB-encoded values.
float linear_to_srgb(float c) {
  c = clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

// PCG hash (O'Neill 2014, as evaluated by Jarzynski and Olano 2020): one 32-bit random value.
uint pcg_hash(uint v) {
  const uint state = v * 747796405u + 2891336453u;
  const uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// A random sequence per (pixel/probe, frame): state advanced by each draw.
struct Rng {
  uint state;
};
Rng rng_seed(uint a, uint b, uint c) {
  Rng r;
  r.state = pcg_hash(a ^ pcg_hash(b ^ pcg_hash(c)));
  return r;
}
float rng_next(inout Rng r) {
  r.state = pcg_hash(r.state);
  return float(r.state >> 8) * (1.0 / 16777216.0);
}

// Builds an orthonormal basis around unit n (Duff et al. 2017).
void orthonormal_basis(vec3 n, out vec3 t, out vec3 b) {
  const float s = n.z >= 0.0 ? 1.0 : -1.0;
  const float a = -1.0 / (s + n.z);
  const float d = n.x * n.y * a;
  t = vec3(1.0 + s * n.x * n.x * a, s * d, -s * n.x);
  b = vec3(d, s + n.y * n.y * a, -n.y);
}

#endif
