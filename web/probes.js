// The irradiance field from a probes file (`ddgi-client probes`, docs/probe-files.md), with
// octahedral or SH probes, and its irradiance query, written as the server's shader writes it
// (shaders/common/field.glsl, sample_irradiance; shaders/common/sh.glsl) and as
// proto/rpc/probe_field.cpp does in C++: so a page can shade from probes itself. Arithmetic is rounded to float32 (Math.fround) where the shader's order
// matters, so results agree with the server's to float rounding.

const f32 = Math.fround;
const PROBE_OFF = 3; // probe states: 0 vigilant, 1 awake, 2 sleeping, 3 off

// ArrayBuffer -> { counts, origin, spacing, ..., irradiance, distance, probeStates }
export function parseProbeFile(buffer) {
  const bytes = new Uint8Array(buffer);
  const magic = new TextDecoder().decode(bytes.subarray(0, 8));
  if (buffer.byteLength < 12 || magic !== 'DDGIPRB1') throw new Error('not a probe file');
  const length = new DataView(buffer).getUint32(8, true);
  const header = JSON.parse(new TextDecoder().decode(bytes.subarray(12, 12 + length)));
  let at = 12 + length;
  const take = (count, what) => {
    if (at + count * 4 > buffer.byteLength) throw new Error(`probe file: ${what} runs past the end`);
    const values = new Float32Array(buffer, at, count);
    at += count * 4;
    return values;
  };
  const probes = header.counts[0] * header.counts[1] * header.counts[2];
  if (header.basis === 'sh') {
    return {
      ...header,
      sh: take(probes * 27, 'the SH coefficients'),
      probeStates: take(probes * 4, 'the probe states'),
    };
  }
  const [iw, ih] = header.irradiance_size;
  const [dw, dh] = header.distance_size;
  return {
    ...header,
    basis: 'octahedral',
    irradiance: take(iw * ih * 4, 'the irradiance atlas'),
    distance: take(dw * dh * 2, 'the distance atlas'),
    probeStates: take(probes * 4, 'the probe states'),
  };
}

const dot = (a, b) => f32(f32(f32(a[0] * b[0]) + f32(a[1] * b[1])) + f32(a[2] * b[2]));
const scaled = (a, s) => a.map((v) => f32(v * s));
const plus = (a, b) => a.map((v, i) => f32(v + b[i]));
const minus = (a, b) => a.map((v, i) => f32(v - b[i]));

function safeNormalize(v, fallback) {
  const length2 = dot(v, v);
  return length2 > 1e-30 && Number.isFinite(length2) ? scaled(v, f32(1 / Math.sqrt(length2)))
    : fallback;
}

function octahedralEncode(n) {
  const scale = f32(1 / f32(f32(Math.abs(n[0]) + Math.abs(n[1])) + Math.abs(n[2])));
  const px = f32(n[0] * scale);
  const py = f32(n[1] * scale);
  const sign = (v) => (v >= 0 ? 1 : -1);
  if (n[2] <= 0) return [f32((1 - Math.abs(py)) * sign(px)), f32((1 - Math.abs(px)) * sign(py))];
  return [px, py];
}

// A linear, clamp-to-edge texture read at normalized (s, t), as Vulkan defines it.
function bilinear(texels, width, height, channels, s, t) {
  const u = f32(f32(s * width) - 0.5);
  const v = f32(f32(t * height) - 0.5);
  const x0 = Math.floor(u);
  const y0 = Math.floor(v);
  const a = f32(u - x0);
  const b = f32(v - y0);
  const at = (x, y, c) => {
    const cx = Math.min(Math.max(x, 0), width - 1);
    const cy = Math.min(Math.max(y, 0), height - 1);
    return texels[(cy * width + cx) * channels + c];
  };
  const out = [];
  for (let c = 0; c < channels; c += 1) {
    out.push(f32(f32(f32(f32(f32((1 - a) * (1 - b)) * at(x0, y0, c)) +
      f32(f32(a * f32(1 - b)) * at(x0 + 1, y0, c))) +
      f32(f32(f32(1 - a) * b) * at(x0, y0 + 1, c))) + f32(f32(a * b) * at(x0 + 1, y0 + 1, c))));
  }
  return out;
}

function atlasUv(field, probe, d, texels, width, height) {
  const [ou, ov] = octahedralEncode(d);
  const tile = texels + 2 * field.border_texels;
  const originX = (probe % field.tiles_per_row) * tile;
  const originY = Math.floor(probe / field.tiles_per_row) * tile;
  return [
    f32(f32(f32(originX + field.border_texels) + f32(f32(f32(ou * 0.5) + 0.5) * texels)) / width),
    f32(f32(f32(originY + field.border_texels) + f32(f32(f32(ov * 0.5) + 0.5) * texels)) / height),
  ];
}

// M (= E / pi) around unit d from SH probe `probe`'s coefficients (sh.glsl, sh_irradiance).
function shIrradiance(field, probe, d) {
  const [x, y, z] = d;
  const [k0, k1, k2, k20, k22] = [0.282094792, 0.488602512, 1.092548431, 0.315391565,
    0.546274215].map(f32);
  const basis = [
    k0, f32(k1 * y), f32(k1 * z), f32(k1 * x), f32(f32(k2 * x) * y), f32(f32(k2 * y) * z),
    f32(k20 * f32(f32(f32(3 * z) * z) - 1)), f32(f32(k2 * x) * z),
    f32(k22 * f32(f32(x * x) - f32(y * y))),
  ];
  const c = field.sh.subarray(probe * 27, probe * 27 + 27);
  const [, band1Scale, band2Scale] = field.sh_band_scales.map(f32);
  const out = [];
  for (let ch = 0; ch < 3; ch += 1) {
    let band1 = 0;
    let band2 = 0;
    for (let k = 1; k < 4; k += 1) band1 = f32(band1 + f32(c[k * 3 + ch] * basis[k]));
    for (let k = 4; k < 9; k += 1) band2 = f32(band2 + f32(c[k * 3 + ch] * basis[k]));
    const m = f32(f32(f32(c[ch] * basis[0]) + f32(band1Scale * band1)) + f32(band2Scale * band2));
    out.push(Math.max(m, 0));
  }
  return out;
}

// What the cage blends of one probe around n (field.glsl, probe_blend_value).
function probeBlendValue(field, probe, n) {
  if (field.basis === 'sh') return shIrradiance(field, probe, n);
  const [is, it] = atlasUv(field, probe, n, field.irradiance_texels, field.irradiance_size[0],
    field.irradiance_size[1]);
  const encoded = bilinear(field.irradiance, field.irradiance_size[0],
    field.irradiance_size[1], 4, is, it);
  // 2021 paper, fig. 3: decode to gamma 2 for the blend, square after.
  const exponent = f32(field.irradiance_gamma * 0.5);
  return encoded.slice(0, 3).map((v) => f32(Math.pow(Math.max(v, 0), exponent)));
}

// Chebyshev visibility of `biased` from octahedral probe `probe` (field.glsl).
function chebyshevVisibility(field, probe, probePosition, biased, n) {
  const probeToPoint = minus(biased, probePosition);
  const r = f32(Math.sqrt(dot(probeToPoint, probeToPoint)));
  const [ds, dt] = atlasUv(field, probe, safeNormalize(probeToPoint, n), field.distance_texels,
    field.distance_size[0], field.distance_size[1]);
  const [mean, mean2] = bilinear(field.distance, field.distance_size[0],
    field.distance_size[1], 2, ds, dt);
  if (r <= mean) return 1;
  const variance = Math.abs(f32(mean2 - f32(mean * mean)));
  const d = f32(r - mean);
  const chebyshev = f32(variance / Math.max(f32(variance + f32(d * d)), 1e-30));
  return f32(f32(chebyshev * chebyshev) * chebyshev);
}

// Cosine-weighted mean radiance E / pi at `position` around unit `normal` ([x, y, z] arrays),
// as the server's QueryIrradiance returns it; `toViewer` defaults to the normal.
export function probeIrradiance(field, position, normal, toViewer = normal) {
  const p = position.map(f32);
  const n = normal.map(f32);
  const spacing = field.spacing.map(f32);
  const origin = field.origin.map(f32);
  const minSpacing = Math.min(...spacing);
  const lean = plus(scaled(n, 0.2), scaled(toViewer.map(f32), 0.8));
  const biased = plus(p, scaled(scaled(lean, f32(0.75 * minSpacing)), field.self_shadow_bias));
  const base = [];
  const alpha = [];
  for (let axis = 0; axis < 3; axis += 1) {
    const grid = f32(f32(biased[axis] - origin[axis]) / spacing[axis]);
    const last = field.counts[axis] - 1;
    base.push(Math.min(Math.max(Math.floor(grid), 0), Math.max(last - 1, 0)));
    alpha.push(Math.min(Math.max(f32(grid - base[axis]), 0), 1));
  }
  const sum = [0, 0, 0];
  let weightSum = 0;
  for (let i = 0; i < 8; i += 1) {
    const offset = [i & 1, (i >> 1) & 1, (i >> 2) & 1];
    const coord = offset.map((o, axis) => Math.min(base[axis] + o, field.counts[axis] - 1));
    const probe = coord[0] + field.counts[0] * (coord[1] + field.counts[1] * coord[2]);
    const state = field.probeStates.subarray(probe * 4, probe * 4 + 4);
    if (state[3] === PROBE_OFF) continue;
    const probePosition = coord.map((c, axis) =>
      f32(f32(origin[axis] + f32(spacing[axis] * c)) + state[axis]));
    let trilinear = 1;
    for (let axis = 0; axis < 3; axis += 1) {
      trilinear = f32(trilinear * (offset[axis] ? alpha[axis] : f32(1 - alpha[axis])));
    }
    const toProbe = safeNormalize(minus(probePosition, p), n);
    const wrap = f32(f32(dot(toProbe, n) + 1) * 0.5);
    let weight = f32(f32(wrap * wrap) + 0.2);

    // Octahedral probes know what they see (their distance moments); SH probes do not.
    if (field.basis !== 'sh') {
      weight = f32(weight * chebyshevVisibility(field, probe, probePosition, biased, n));
    }
    weight = Math.max(weight, f32(1e-6));
    const crush = f32(field.weight_crush_threshold);
    if (weight < crush) weight = f32(weight * f32(f32(weight * weight) / f32(crush * crush)));
    weight = f32(weight * Math.max(trilinear, 0));

    const value = probeBlendValue(field, probe, n);
    for (let c = 0; c < 3; c += 1) sum[c] = f32(sum[c] + f32(value[c] * weight));
    weightSum = f32(weightSum + weight);
  }
  if (!(weightSum > 0)) return [0, 0, 0];
  return sum.map((v) => {
    const blended = f32(v / weightSum);
    const value = field.basis === 'sh' ? blended : f32(blended * blended);
    return Number.isFinite(value) ? Math.max(value, 0) : 0;
  });
}
