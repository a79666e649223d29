// The web client's modules without a browser (node --test): the camera math against what it
// must preserve, the frame message parser against a message built by hand, and the latency
// bookkeeping against made-up times.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { OrbitCamera } from '../../web/camera.js';
import { parseFrameMessage } from '../../web/socket.js';
import { StreamStats } from '../../web/stats.js';

const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
const close = (a, b, tolerance = 1e-9) => distance(a, b) <= tolerance;

function camera() {
  return new OrbitCamera({
    position: { x: 0, y: 1, z: 3.4 },
    target: { x: 0, y: 1, z: 0 },
    verticalFovDegrees: 40,
  });
}

test('orbiting keeps the distance to the target and a full turn comes back', () => {
  const c = camera();
  const start = [...c.position];
  c.orbit(0.7, 0.2);
  assert.ok(Math.abs(distance(c.position, c.target) - 3.4) < 1e-9);
  assert.ok(!close(c.position, start, 1e-3), 'the camera moved');
  c.orbit(-0.7, -0.2);
  assert.ok(close(c.position, start, 1e-9), `back at the start: ${c.position}`);
  for (let i = 0; i < 8; i += 1) c.orbit(Math.PI / 4, 0);
  assert.ok(close(c.position, start, 1e-9), 'eight eighth turns are a full turn');
});

test('orbiting stops short of the poles', () => {
  const c = camera();
  c.orbit(0, 10);
  const up = (c.position[1] - c.target[1]) / distance(c.position, c.target);
  assert.ok(up < Math.sin(1.5) + 1e-9 && up > 0.99, `elevation clamped: ${up}`);
});

test('panning and moving shift camera and target alike; zoom scales the distance', () => {
  const c = camera();
  const before = { position: [...c.position], target: [...c.target] };
  c.pan(0.1, -0.05);
  const shift = c.position.map((v, i) => v - before.position[i]);
  const targetShift = c.target.map((v, i) => v - before.target[i]);
  assert.ok(close(shift, targetShift), 'same shift');
  assert.ok(Math.hypot(...shift) > 0.1, 'it moved');
  c.move(1, 0, 0);
  assert.ok(Math.abs(distance(c.position, c.target) - 3.4) < 1e-9);
  c.zoom(0.5);
  assert.ok(Math.abs(distance(c.position, c.target) - 1.7) < 1e-9);
  const message = c.toMessage();
  assert.equal(message.verticalFovDegrees, 40);
  assert.deepEqual(Object.keys(message.position), ['x', 'y', 'z']);
});

test('a camera given by forward orbits a point in front of it', () => {
  const c = new OrbitCamera({ position: { x: 1, y: 2, z: 3 }, forward: { x: 0, y: 0, z: -2 } });
  assert.ok(close(c.target, [1, 2, 0]), `target ${c.target}`);
  assert.equal(c.fov, 45);
});

test('a frame message splits into its header and JPEG', () => {
  const header = new TextEncoder().encode(JSON.stringify({ frameIndex: '12', width: 64 }));
  const jpeg = [0xff, 0xd8, 0x01, 0x02, 0xff, 0xd9];
  const bytes = new Uint8Array(4 + header.length + jpeg.length);
  new DataView(bytes.buffer).setUint32(0, header.length, true);
  bytes.set(header, 4);
  bytes.set(jpeg, 4 + header.length);
  const frame = parseFrameMessage(bytes.buffer);
  assert.equal(frame.header.frameIndex, '12');
  assert.equal(frame.header.width, 64);
  assert.deepEqual([...frame.jpeg], jpeg);
  new DataView(bytes.buffer).setUint32(0, bytes.length, true);
  assert.throws(() => parseFrameMessage(bytes.buffer), /longer than the message/);
  assert.throws(() => parseFrameMessage(new ArrayBuffer(2)), /shorter/);
});

test('latency runs from a command to the first frame that carries it', () => {
  const stats = new StreamStats();
  stats.frame(1000, 100, 3);
  stats.commandApplied(5, 1010);
  stats.frame(1020, 100, 4);
  assert.equal(stats.latencyMs, null, 'seq 4 does not show command 5');
  stats.frame(1050, 100, 5);
  assert.equal(stats.latencyMs, 40);
  stats.frame(1900, 100, 5);
  assert.equal(stats.framesPerSecond(), 4, 'the frames of the last second (1000..1900)');
  assert.equal(stats.bytesPerSecond(), 400);
  stats.frame(2600, 50, 5);
  assert.equal(stats.framesPerSecond(), 2, 'older frames leave the window');
});
