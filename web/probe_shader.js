// The irradiance field's query in GLSL ES 3.0, for the local-rendering mode (local_view.js):
// the same cage of eight probes, weights and decoding as the server's shader
// (shaders/common/field.glsl, sample_irradiance; shaders/common/sh.glsl) and as probes.js in
// JavaScript, fed from a field of the shape probe_stream.js keeps (SH coefficients, or the
// octahedral irradiance and distance atlases, plus probe states) through float textures read
// with texelFetch (bilinear filtering done here, clamp to edge, as Vulkan's sampler does).
import * as THREE from 'three';

const SH_TEXELS_PER_ROW = 64 * 9; // 64 probes of 9 RGB texels each per row
const STATE_TEXELS_PER_ROW = 256;

export const PROBE_GLSL = /* glsl */ `
uniform highp sampler2D ddgiStates;      // per probe: offset xyz, state (3 = off)
uniform highp sampler2D ddgiIrradiance;  // octahedral irradiance atlas (gamma-encoded RGB)
uniform highp sampler2D ddgiDistance;    // octahedral distance atlas (mean, mean of squares)
uniform highp sampler2D ddgiSh;          // 9 RGB coefficients per probe, 64 probes per row
uniform ivec3 ddgiCounts;
uniform vec3 ddgiOrigin;
uniform vec3 ddgiSpacing;
uniform float ddgiSelfShadowBias;
uniform float ddgiCrush;
uniform float ddgiGamma;
uniform int ddgiBasis;  // 0 octahedral, 1 SH, -1 no field yet
uniform int ddgiBorder;
uniform int ddgiTilesPerRow;
uniform int ddgiIrradianceTexels;
uniform int ddgiDistanceTexels;
uniform vec2 ddgiShBands;  // band 1 and band 2 factors (cosine lobe, window)

vec3 ddgiSafeNormalize(vec3 v, vec3 fallback) {
  float length2 = dot(v, v);
  return length2 > 1e-30 ? v * inversesqrt(length2) : fallback;
}

vec2 ddgiOctEncode(vec3 n) {
  vec2 p = n.xy * (1.0 / (abs(n.x) + abs(n.y) + abs(n.z)));
  vec2 s = vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
  return n.z <= 0.0 ? (1.0 - abs(p.yx)) * s : p;
}

vec4 ddgiBilinear(highp sampler2D atlas, vec2 uv) {
  ivec2 size = textureSize(atlas, 0);
  vec2 t = uv * vec2(size) - 0.5;
  vec2 f = floor(t);
  vec2 a = t - f;
  ivec2 p = ivec2(f);
  ivec2 last = size - 1;
  vec4 v00 = texelFetch(atlas, clamp(p, ivec2(0), last), 0);
  vec4 v10 = texelFetch(atlas, clamp(p + ivec2(1, 0), ivec2(0), last), 0);
  vec4 v01 = texelFetch(atlas, clamp(p + ivec2(0, 1), ivec2(0), last), 0);
  vec4 v11 = texelFetch(atlas, clamp(p + ivec2(1, 1), ivec2(0), last), 0);
  return (1.0 - a.x) * (1.0 - a.y) * v00 + a.x * (1.0 - a.y) * v10 + (1.0 - a.x) * a.y * v01 +
         a.x * a.y * v11;
}

vec2 ddgiAtlasUv(int probe, vec3 d, int texels, highp sampler2D atlas) {
  vec2 o = ddgiOctEncode(d);
  int tile = texels + 2 * ddgiBorder;
  vec2 origin = vec2(float((probe % ddgiTilesPerRow) * tile), float((probe / ddgiTilesPerRow) * tile));
  vec2 texel = origin + float(ddgiBorder) + (o * 0.5 + 0.5) * float(texels);
  return texel / vec2(textureSize(atlas, 0));
}

vec3 ddgiShCoefficient(int probe, int k) {
  int texel = probe * 9 + k;
  return texelFetch(ddgiSh, ivec2(texel % ${SH_TEXELS_PER_ROW}, texel / ${SH_TEXELS_PER_ROW}), 0).rgb;
}

// M (= E / pi) around unit d from an SH probe (sh.glsl, sh_irradiance).
vec3 ddgiShIrradiance(int probe, vec3 d) {
  float basis[9] = float[9](0.282094792, 0.488602512 * d.y, 0.488602512 * d.z, 0.488602512 * d.x,
                            1.092548431 * d.x * d.y, 1.092548431 * d.y * d.z,
                            0.315391565 * (3.0 * d.z * d.z - 1.0), 1.092548431 * d.x * d.z,
                            0.546274215 * (d.x * d.x - d.y * d.y));
  vec3 band1 = vec3(0.0);
  vec3 band2 = vec3(0.0);
  for (int k = 1; k < 4; ++k) band1 += ddgiShCoefficient(probe, k) * basis[k];
  for (int k = 4; k < 9; ++k) band2 += ddgiShCoefficient(probe, k) * basis[k];
  vec3 m = ddgiShCoefficient(probe, 0) * basis[0] + ddgiShBands.x * band1 + ddgiShBands.y * band2;
  return max(m, vec3(0.0));
}

vec3 ddgiProbeValue(int probe, vec3 n) {
  if (ddgiBasis == 1) return ddgiShIrradiance(probe, n);
  vec3 encoded = ddgiBilinear(ddgiIrradiance,
                              ddgiAtlasUv(probe, n, ddgiIrradianceTexels, ddgiIrradiance)).rgb;
  return pow(max(encoded, vec3(0.0)), vec3(ddgiGamma * 0.5));  // gamma 2 for the blend
}

float ddgiChebyshev(int probe, vec3 probePosition, vec3 biased, vec3 n) {
  vec3 probeToPoint = biased - probePosition;
  float r = length(probeToPoint);
  vec2 uv = ddgiAtlasUv(probe, ddgiSafeNormalize(probeToPoint, n), ddgiDistanceTexels, ddgiDistance);
  vec2 moments = ddgiBilinear(ddgiDistance, uv).rg;
  if (r <= moments.x) return 1.0;
  float variance = abs(moments.y - moments.x * moments.x);
  float d = r - moments.x;
  float chebyshev = variance / max(variance + d * d, 1e-30);
  return chebyshev * chebyshev * chebyshev;
}

// E / pi at a world-space point around unit normal n, the self-shadow bias leaning toward the
// viewer (field.glsl, sample_irradiance).
vec3 ddgiProbeIrradiance(vec3 p, vec3 n, vec3 toViewer) {
  if (ddgiBasis < 0) return vec3(0.0);
  float minSpacing = min(ddgiSpacing.x, min(ddgiSpacing.y, ddgiSpacing.z));
  vec3 biased = p + (n * 0.2 + toViewer * 0.8) * (0.75 * minSpacing) * ddgiSelfShadowBias;
  vec3 grid = (biased - ddgiOrigin) / ddgiSpacing;
  ivec3 base = clamp(ivec3(floor(grid)), ivec3(0), max(ddgiCounts - 2, ivec3(0)));
  vec3 alpha = clamp(grid - vec3(base), 0.0, 1.0);
  vec3 sum = vec3(0.0);
  float weightSum = 0.0;
  for (int i = 0; i < 8; ++i) {
    ivec3 offset = ivec3(i & 1, (i >> 1) & 1, (i >> 2) & 1);
    ivec3 coord = min(base + offset, ddgiCounts - 1);
    int probe = coord.x + ddgiCounts.x * (coord.y + ddgiCounts.y * coord.z);
    vec4 state = texelFetch(ddgiStates, ivec2(probe % ${STATE_TEXELS_PER_ROW}, probe / ${STATE_TEXELS_PER_ROW}), 0);
    if (state.w == 3.0) continue;  // off
    vec3 probePosition = ddgiOrigin + ddgiSpacing * vec3(coord) + state.xyz;
    vec3 t = mix(1.0 - alpha, alpha, vec3(offset));
    float trilinear = t.x * t.y * t.z;
    vec3 toProbe = ddgiSafeNormalize(probePosition - p, n);
    float wrap = (dot(toProbe, n) + 1.0) * 0.5;
    float weight = wrap * wrap + 0.2;
    if (ddgiBasis == 0) weight *= ddgiChebyshev(probe, probePosition, biased, n);
    weight = max(weight, 1e-6);
    if (weight < ddgiCrush) weight *= weight * weight / (ddgiCrush * ddgiCrush);
    weight *= max(trilinear, 0.0);
    sum += ddgiProbeValue(probe, n) * weight;
    weightSum += weight;
  }
  if (!(weightSum > 0.0)) return vec3(0.0);
  vec3 blended = sum / weightSum;
  return max(ddgiBasis == 1 ? blended : blended * blended, vec3(0.0));
}
`;

function floatTexture(data, width, height, format) {
  const texture = new THREE.DataTexture(data, width, height, format, THREE.FloatType);
  texture.minFilter = THREE.NearestFilter;
  texture.magFilter = THREE.NearestFilter;
  texture.generateMipmaps = false;
  texture.needsUpdate = true;
  return texture;
}

// `count` texels of `channels` floats from `values` in rows of `perRow` texels, RGBA.
function rowsOfTexels(values, count, channels, perRow) {
  const rows = Math.max(1, Math.ceil(count / perRow));
  const data = new Float32Array(perRow * rows * 4);
  for (let i = 0; i < count; i += 1) {
    for (let c = 0; c < channels; c += 1) data[i * 4 + c] = values[i * channels + c];
  }
  return floatTexture(data, perRow, rows, THREE.RGBAFormat);
}

const placeholder = () => floatTexture(new Float32Array(4), 1, 1, THREE.RGBAFormat);

// The uniforms PROBE_GLSL reads, shared by every material; update(field) refills them.
export class ProbeUniforms {
  constructor() {
    this.uniforms = {
      ddgiStates: { value: placeholder() },
      ddgiIrradiance: { value: placeholder() },
      ddgiDistance: { value: placeholder() },
      ddgiSh: { value: placeholder() },
      ddgiCounts: { value: new THREE.Vector3(1, 1, 1) },
      ddgiOrigin: { value: new THREE.Vector3() },
      ddgiSpacing: { value: new THREE.Vector3(1, 1, 1) },
      ddgiSelfShadowBias: { value: 0 },
      ddgiCrush: { value: 0 },
      ddgiGamma: { value: 5 },
      ddgiBasis: { value: -1 },
      ddgiBorder: { value: 1 },
      ddgiTilesPerRow: { value: 1 },
      ddgiIrradianceTexels: { value: 1 },
      ddgiDistanceTexels: { value: 1 },
      ddgiShBands: { value: new THREE.Vector2(1, 1) },
    };
  }

  replace(name, texture) {
    this.uniforms[name].value.dispose();
    this.uniforms[name].value = texture;
  }

  // From a field as probe_stream.js (or parseProbeFile) gives it.
  update(field) {
    const u = this.uniforms;
    const probes = field.counts[0] * field.counts[1] * field.counts[2];
    u.ddgiCounts.value.set(...field.counts);
    u.ddgiOrigin.value.set(...field.origin);
    u.ddgiSpacing.value.set(...field.spacing);
    u.ddgiSelfShadowBias.value = field.self_shadow_bias;
    u.ddgiCrush.value = field.weight_crush_threshold;
    this.replace('ddgiStates', rowsOfTexels(field.probeStates, probes, 4, STATE_TEXELS_PER_ROW));
    if (field.basis === 'sh') {
      u.ddgiBasis.value = 1;
      u.ddgiShBands.value.set(field.sh_band_scales[1], field.sh_band_scales[2]);
      this.replace('ddgiSh', rowsOfTexels(field.sh, probes * 9, 3, SH_TEXELS_PER_ROW));
      return;
    }
    u.ddgiBasis.value = 0;
    u.ddgiGamma.value = field.irradiance_gamma;
    u.ddgiBorder.value = field.border_texels;
    u.ddgiTilesPerRow.value = field.tiles_per_row;
    u.ddgiIrradianceTexels.value = field.irradiance_texels;
    u.ddgiDistanceTexels.value = field.distance_texels;
    const [iw, ih] = field.irradiance_size;
    const [dw, dh] = field.distance_size;
    this.replace('ddgiIrradiance', floatTexture(field.irradiance, iw, ih, THREE.RGBAFormat));
    this.replace('ddgiDistance', floatTexture(field.distance, dw, dh, THREE.RGFormat));
  }
}
