// The page's side of StreamProbes (docs/probe-stream.md): applies ProbeUpdate messages, as the
// web front forwards them (protobuf JSON: camelCase names, bytes in base64), to a field of the
// shape parseProbeFile (probes.js) returns, so probeIrradiance shades from it. The same decoding
// as proto/rpc/probe_stream.cpp (apply_probe_update) in C++.

// IEEE binary16 -> number (exact).
export function halfToFloat(h) {
  const sign = h & 0x8000 ? -1 : 1;
  const exponent = (h >> 10) & 0x1f;
  const mantissa = h & 0x3ff;
  if (exponent === 0) return sign * mantissa * 2 ** -24;
  if (exponent === 31) return mantissa ? 0 : sign * 65504; // never sent: read as the limits
  return sign * (1 + mantissa / 1024) * 2 ** (exponent - 15);
}

function base64Bytes(text) {
  const binary = atob(text ?? '');
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i += 1) bytes[i] = binary.charCodeAt(i);
  return bytes;
}

function halves(text) {
  const bytes = base64Bytes(text);
  const out = new Float32Array(bytes.length / 2);
  for (let i = 0; i < out.length; i += 1) out[i] = halfToFloat(bytes[2 * i] | (bytes[2 * i + 1] << 8));
  return out;
}

const bit = (mask, p) => (p >> 3) < mask.length && ((mask[p >> 3] >> (p & 7)) & 1) === 1;

// A zeroed field of the grid's shape (the keys parseProbeFile gives).
function fieldOfGrid(grid) {
  const counts = [grid.countsX, grid.countsY, grid.countsZ];
  const probes = counts[0] * counts[1] * counts[2];
  if (!(counts.every((c) => c > 0) && probes <= 2 ** 24)) throw new Error('probe grid: bad counts');
  const field = {
    basis: grid.basis,
    counts,
    origin: [grid.origin?.x ?? 0, grid.origin?.y ?? 0, grid.origin?.z ?? 0],
    spacing: [grid.spacing?.x ?? 0, grid.spacing?.y ?? 0, grid.spacing?.z ?? 0],
    self_shadow_bias: grid.selfShadowBias,
    weight_crush_threshold: grid.weightCrushThreshold,
    probeStates: new Float32Array(probes * 4),
  };
  if (grid.basis === 'sh') {
    field.sh_band_scales = grid.shBandScales;
    field.sh = new Float32Array(probes * 27);
    field.stride = 27;
    return field;
  }
  const border = grid.borderTexels;
  const it = grid.irradianceTexels + 2 * border;
  const dt = grid.distanceTexels + 2 * border;
  const rows = Math.ceil(probes / grid.tilesPerRow);
  Object.assign(field, {
    irradiance_texels: grid.irradianceTexels,
    distance_texels: grid.distanceTexels,
    border_texels: border,
    tiles_per_row: grid.tilesPerRow,
    irradiance_gamma: grid.irradianceGamma,
    irradiance_size: [grid.tilesPerRow * it, rows * it],
    distance_size: [grid.tilesPerRow * dt, rows * dt],
    stride: it * it * 3 + dt * dt * 2,
  });
  field.irradiance = new Float32Array(field.irradiance_size[0] * field.irradiance_size[1] * 4);
  field.distance = new Float32Array(field.distance_size[0] * field.distance_size[1] * 2);
  return field;
}

// Puts probe p's values (field.stride of them, from `values` at `at`) where the field keeps
// them: SH coefficients, or the two tiles (the stream's distance tile holds mean and variance;
// the field keeps mean and mean of squares).
function storeProbe(field, p, values, at) {
  if (field.basis === 'sh') {
    field.sh.set(values.subarray(at, at + 27), p * 27);
    return;
  }
  let next = at;
  const place = (atlas, width, texels, channels, stored, toStored) => {
    const tile = texels + 2 * field.border_texels;
    const x0 = (p % field.tiles_per_row) * tile;
    const y0 = Math.floor(p / field.tiles_per_row) * tile;
    for (let y = 0; y < tile; y += 1) {
      for (let x = 0; x < tile; x += 1) {
        const texel = ((y0 + y) * width + x0 + x) * channels;
        toStored(atlas, texel, values, next);
        next += stored;
      }
    }
  };
  place(field.irradiance, field.irradiance_size[0], field.irradiance_texels, 4, 3, (a, t, v, i) => {
    a[t] = v[i];
    a[t + 1] = v[i + 1];
    a[t + 2] = v[i + 2];
  });
  place(field.distance, field.distance_size[0], field.distance_texels, 2, 2, (a, t, v, i) => {
    a[t] = v[i];
    a[t + 1] = Math.fround(v[i + 1] + Math.fround(v[i] * v[i]));
  });
}

// Applies one ProbeUpdate to `stream` ({ field, fieldUpdates, messages }); returns it. Throws
// when a message does not fit (a delta before any full message, sizes that disagree).
export function applyProbeUpdate(stream, update) {
  if (update.full) {
    stream.field = fieldOfGrid(update.grid);
  } else if (!stream.field) {
    throw new Error('a probe update that is not full came before any full one');
  }
  const { field } = stream;
  const probes = field.probeStates.length / 4;
  const values = halves(update.values);
  const changed = base64Bytes(update.changed);
  let at = 0;
  for (let p = 0; p < probes; p += 1) {
    if (!update.full && !bit(changed, p)) continue;
    if (at + field.stride > values.length) throw new Error(`probe update: values end before probe ${p}`);
    storeProbe(field, p, values, at);
    at += field.stride;
  }
  if (at !== values.length) throw new Error('probe update: values left over');
  const states = halves(update.states);
  const stateChanged = base64Bytes(update.stateChanged);
  at = 0;
  for (let p = 0; p < probes; p += 1) {
    if (!update.full && !bit(stateChanged, p)) continue;
    if (at + 4 > states.length) throw new Error(`probe update: states end before probe ${p}`);
    field.probeStates.set(states.subarray(at, at + 4), p * 4);
    at += 4;
  }
  if (at !== states.length) throw new Error('probe update: states left over');
  field.field_updates = update.fieldUpdates;
  stream.fieldUpdates = Number(update.fieldUpdates);
  stream.messages = (stream.messages ?? 0) + 1;
  return stream;
}
