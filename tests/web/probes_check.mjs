// The web client's probe evaluator (web/probes.js) against the server's QueryIrradiance:
//   node tests/web/probes_check.mjs PROBES.bin POINTS.txt SERVER.json
// POINTS: "px,py,pz,nx,ny,nz" lines (what `ddgi-client query --points-file` sent); SERVER.json:
// its reply. Fails when any component differs by more than 5e-5 relative (against at least
// 1e-3), or when the irradiance is trivially dark.
import { readFileSync } from 'node:fs';
import { parseProbeFile, probeIrradiance } from '../../web/probes.js';

const [probesPath, pointsPath, serverPath] = process.argv.slice(2);
if (!serverPath) {
  console.error('usage: node probes_check.mjs PROBES.bin POINTS.txt SERVER.json');
  process.exit(2);
}
const file = readFileSync(probesPath);
const field = parseProbeFile(file.buffer.slice(file.byteOffset, file.byteOffset + file.length));
const points = readFileSync(pointsPath, 'utf8').split('\n').filter((l) => l.trim())
  .map((l) => l.split(',').map(Number));
const server = JSON.parse(readFileSync(serverPath, 'utf8'));
if (server.irradiance.length !== points.length) throw new Error('points and replies differ in number');
if (String(server.field_updates) !== String(field.field_updates)) {
  throw new Error(`the field changed: probes at update ${field.field_updates}, query at ${server.field_updates}`);
}
let maxRelative = 0;
let mean = 0;
points.forEach((v, i) => {
  const ours = probeIrradiance(field, v.slice(0, 3), v.slice(3, 6));
  const theirs = [server.irradiance[i].x ?? 0, server.irradiance[i].y ?? 0, server.irradiance[i].z ?? 0];
  for (let c = 0; c < 3; c += 1) {
    maxRelative = Math.max(maxRelative, Math.abs(ours[c] - theirs[c]) / Math.max(theirs[c], 1e-3));
    mean += theirs[c] / (3 * points.length);
  }
});
console.log(`web/probes.js vs QueryIrradiance: ${points.length} points, mean ${mean.toFixed(4)}, ` +
  `max relative difference ${maxRelative.toExponential(2)} (tolerance 5e-5)`);
if (!(mean > 0.01)) throw new Error('the field is dark: the comparison proves little');
if (!(maxRelative <= 5e-5)) throw new Error('web/probes.js disagrees with the server');
