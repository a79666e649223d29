// Browser tests of the web client (web/, docs/web.md) in Debian's headless chromium, driven by
// puppeteer-core, against a real ddgi-server process (lavapipe in CI, Vulkan validation on: a
// validation message makes the server exit non-zero, which fails the test).
//
//   node tests/web/browser_test.mjs DDGI_SERVER SCENE_ROOT [CHROMIUM]
//   DDGI_WEB_SCREENSHOT=page.png ... also saves the page as it is at the end (the README's).
//
// What a person does, checked the way they would see it: the page asks for a token and shows
// the server's refusal of a wrong one; with the right one it lists the scenes; "Create session"
// shows a frame within a deadline, and a drag on the frame moves the camera: the next frames
// carry the camera command (lastCommandSeq) and differ from the one before the drag by far more
// than frames of a still camera differ from each other (the control). Then, on a second server
// pacing its sessions at 2 updates a second: the page follows an SH field with StreamProbes
// (web/probe_stream.js) and shades from it with web/probes.js; at the same field update that
// matches the server's QueryIrradiance to fp16 precision, and the stream's first message alone
// (the control) does not. Local rendering: the page downloads the scene, draws the same view's
// indirect light with three.js from the streamed probes, and that image matches the server's
// frame of the view within a stated tolerance (the server's full image is the control).
import { spawn } from 'node:child_process';
import { mkdtempSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { createInterface } from 'node:readline';

const [serverPath, sceneRoot, chromiumPath = '/usr/bin/chromium'] = process.argv.slice(2);
if (!serverPath || !sceneRoot) {
  console.error('usage: node browser_test.mjs DDGI_SERVER SCENE_ROOT [CHROMIUM]');
  process.exit(2);
}

// puppeteer-core comes from npm (tests/web/package-lock.json), installed by tests/run_all.sh.
const puppeteer = await import('puppeteer-core').then((module) => module.default, () => {
  console.error('puppeteer-core is not installed: run `npm ci --prefix tests/web` ' +
    '(tests/run_all.sh does)');
  process.exit(2);
});

const TOKEN = 'browser-test-token-4711';
const FIRST_FRAME_DEADLINE_MS = 180_000; // session load + warm-up on lavapipe
const COMMAND_DEADLINE_MS = 60_000;
// Mean absolute difference of RGB in [0, 255]: a drag must change the image by more than this,
// and by more than 4x what two frames of a still camera differ by.
const MIN_DRAG_CHANGE = 4.0;

function check(condition, what) {
  if (!condition) throw new Error(`FAILED: ${what}`);
  console.log(`ok: ${what}`);
}

// Starts ddgi-server with the web front on a free port; resolves once it prints the page's URL.
function startServer(args) {
  const server = spawn(serverPath, [
    '--listen', '127.0.0.1:0', '--metrics-port', '-1', '--web-port', '0',
    '--web-address', '127.0.0.1', '--scene-root', sceneRoot, '--validation', ...args,
  ], { stdio: ['ignore', 'pipe', 'inherit'] });
  const exited = new Promise((resolve) => server.on('exit', (code, signal) => resolve({ code, signal })));
  const url = new Promise((resolve, reject) => {
    createInterface({ input: server.stdout }).on('line', (line) => {
      console.log(`[server] ${line}`);
      const match = line.match(/web client at (http:\/\/\S+)/);
      if (match) resolve(match[1]);
    });
    exited.then(({ code }) => reject(new Error(`ddgi-server exited (${code}) before serving`)));
  });
  return { server, url, exited };
}

async function stopServer({ server, exited }) {
  server.kill('SIGTERM');
  const { code, signal } = await exited;
  check(code === 0, `ddgi-server stopped cleanly (exit ${code}${signal ? `, ${signal}` : ''}; ` +
    'non-zero after Vulkan validation messages)');
}

// The canvas's pixels as RGB means: [mean brightness, pixels].
async function canvasPixels(page) {
  return page.evaluate(() => {
    const canvas = document.getElementById('frame');
    const data = canvas.getContext('2d').getImageData(0, 0, canvas.width, canvas.height).data;
    const rgb = [];
    for (let i = 0; i < data.length; i += 4) rgb.push(data[i], data[i + 1], data[i + 2]);
    return rgb;
  });
}

function meanAbsDifference(a, b) {
  if (a.length !== b.length) return Infinity;
  let sum = 0;
  for (let i = 0; i < a.length; i += 1) sum += Math.abs(a[i] - b[i]);
  return sum / a.length;
}

const mean = (a) => a.reduce((s, v) => s + v, 0) / a.length;

async function waitForFrames(page, count, deadline) {
  await page.waitForFunction((n) => window.ddgi.frames >= n, { timeout: deadline, polling: 100 },
    count);
}

async function tokenIsAskedForAndChecked(page) {
  await page.waitForSelector('#error:not([hidden])', { timeout: 30_000 });
  const first = await page.$eval('#error', (e) => e.textContent);
  check(first.includes('refused the access token'), `without a token the page says so: "${first.slice(0, 80)}…"`);
  check(await page.$eval('#auth', (e) => !e.hidden), 'the token field is shown');

  await page.type('#token', 'not-the-token');
  await page.click('#connect');
  await page.waitForFunction(() => document.getElementById('error').textContent.includes('wrong')
    || document.getElementById('error').textContent.includes('refused'), { timeout: 30_000 });
  check(!(await page.$eval('#auth', (e) => e.hidden)), 'a wrong token is refused, the field stays');

  await page.$eval('#token', (e) => { e.value = ''; });
  await page.type('#token', TOKEN);
  await page.click('#connect');
  await page.waitForFunction(() => document.getElementById('status').textContent.startsWith('connected'),
    { timeout: 30_000 });
  const scenes = await page.$$eval('#scene option', (options) => options.map((o) => o.value));
  check(scenes.includes('cornell_box'), `with the token the scene library is listed (${scenes.length} scenes)`);
  check(await page.$eval('#error', (e) => e.hidden), 'the error is gone');
}

async function streamShowsAndDragMovesTheCamera(page) {
  await page.select('#scene', 'cornell_box');
  const created = Date.now();
  await page.click('#create');
  await waitForFrames(page, 1, FIRST_FRAME_DEADLINE_MS);
  console.log(`first frame after ${Date.now() - created} ms`);
  // Frames of a still camera: the control for what a drag changes.
  await waitForFrames(page, (await page.evaluate(() => window.ddgi.frames)) + 3, COMMAND_DEADLINE_MS);
  const still1 = await canvasPixels(page);
  await waitForFrames(page, (await page.evaluate(() => window.ddgi.frames)) + 2, COMMAND_DEADLINE_MS);
  const still2 = await canvasPixels(page);
  const brightness = mean(still1);
  check(brightness > 10, `the frame is not black (mean ${brightness.toFixed(1)} of 255)`);
  const stillChange = meanAbsDifference(still1, still2);
  const before = await page.evaluate(() => ({
    seq: Number(window.ddgi.lastFrame.lastCommandSeq),
    position: window.ddgi.lastFrame.camera.position,
  }));

  const box = await (await page.$('#frame')).boundingBox();
  const x = box.x + box.width / 2;
  const y = box.y + box.height / 2;
  await page.mouse.move(x, y);
  await page.mouse.down();
  await page.mouse.move(x + box.width * 0.1, y + box.height * 0.05, { steps: 5 });
  await page.mouse.up();
  // The frame that shows the drag carries its command (the page's latency measurement).
  await page.waitForFunction(() => window.ddgi.stats.commands.length === 0 && window.ddgi.stats.latencyMs !== null,
    { timeout: COMMAND_DEADLINE_MS, polling: 50 });
  await waitForFrames(page, (await page.evaluate(() => window.ddgi.frames)) + 2, COMMAND_DEADLINE_MS);
  const after = await page.evaluate(() => ({
    seq: Number(window.ddgi.lastFrame.lastCommandSeq),
    position: window.ddgi.lastFrame.camera.position,
    latency: window.ddgi.stats.latencyMs,
  }));
  const moved = await canvasPixels(page);
  const dragChange = meanAbsDifference(still2, moved);
  check(after.seq > before.seq, `the frames after the drag carry its command (seq ${before.seq} -> ${after.seq}, latency ${after.latency.toFixed(0)} ms)`);
  check(JSON.stringify(after.position) !== JSON.stringify(before.position), 'the camera moved');
  check(dragChange > MIN_DRAG_CHANGE && dragChange > 4 * stillChange,
    `the image changed with the drag: mean |diff| ${dragChange.toFixed(2)} (> ${MIN_DRAG_CHANGE} and > 4x the still camera's ${stillChange.toFixed(2)})`);
  const shown = await page.$eval('#fps', (e) => e.textContent);
  check(Number(shown) > 0, `the page shows frames/s (${shown})`);
  if (process.env.DDGI_WEB_SCREENSHOT) {
    await page.screenshot({ path: process.env.DDGI_WEB_SCREENSHOT });
    console.log(`wrote ${process.env.DDGI_WEB_SCREENSHOT}`);
  }
}

// The session's configuration on the page: the calibration line says why a CPU server calibrates
// nothing (lavapipe: minutes per scene; the background calibration and the switch are tested
// over RPC in tests/service/calibration_test.cpp), and a budget set from the page is the
// session's budget; an empty one returns to the server's default (4 ms). Planted: the page
// leaving the budget out of the line fails it.
async function timeBudgetIsChosenAndShown(page) {
  const calibration = () => page.$eval('#calibration-info', (e) => e.textContent);
  await page.waitForFunction(() => document.querySelector('#calibration-info').textContent !== '',
    { timeout: COMMAND_DEADLINE_MS, polling: 100 });
  const off = await calibration();
  check(/^No calibration: no calibration on a CPU device .*--calibration on; budget 4 ms$/.test(off),
    `the page says why nothing is calibrated ("${off}")`);
  const setBudget = async (value) => {
    await page.$eval('#budget', (input, v) => { input.value = v; }, value);
    await page.click('#apply-budget');
  };
  await setBudget('2');
  await page.waitForFunction(() => document.querySelector('#calibration-info').textContent.includes('budget 2 ms'),
    { timeout: COMMAND_DEADLINE_MS, polling: 100 });
  check((await page.$eval('#error', (e) => e.hidden)), 'a budget is never refused');
  await setBudget('');
  await page.waitForFunction(() => document.querySelector('#calibration-info').textContent.includes('budget 4 ms'),
    { timeout: COMMAND_DEADLINE_MS, polling: 100 });
  check(true, `an empty budget returns to the server's default ("${await calibration()}")`);
}

// Mean absolute RGB difference (of 255) allowed between the page's own indirect image and the
// server's frame of the same view: JPEG (quality 85, 4:2:0) and rasterized vs ray-traced edges.
const LOCAL_TOLERANCE = 2.5;

// The local canvas (WebGL, drawing buffer kept) as RGB values, like canvasPixels.
async function localPixels(page) {
  return page.evaluate(() => {
    const local = document.getElementById('local');
    const copy = document.createElement('canvas');
    copy.width = local.width;
    copy.height = local.height;
    const context = copy.getContext('2d');
    context.drawImage(local, 0, 0);
    const data = context.getImageData(0, 0, copy.width, copy.height).data;
    const rgb = [];
    for (let i = 0; i < data.length; i += 4) rgb.push(data[i], data[i + 1], data[i + 2]);
    return rgb;
  });
}

// Largest relative difference allowed between the page's GLSL field query (web/probe_shader.js,
// on the GPU through WebGL2) and web/probes.js (float32 arithmetic, equal to the server's query
// to 2e-5 by clients_test): float rounding in a different order.
const GLSL_TOLERANCE = 2e-5;

// Evaluates the field `which` ('local': the local mode's streamed field; 'sh': window.shField)
// at 256 random points inside its grid with the GLSL query (a 256x1 float render target) and
// with probes.js. Returns { max, mean, control } (control: probes.js on the field with every
// probe's first value doubled, i.e. what a wrong input would give).
async function glslAgainstJs(page, which) {
  return page.evaluate(async (which, count) => {
    const THREE = await import('three');
    const { PROBE_GLSL, ProbeUniforms } = await import('/probe_shader.js');
    const { probeIrradiance } = await import('/probes.js');
    const field = which === 'local' ? window.ddgi.local.probes.field : window.shField;
    let seed = 11;
    const random = () => { seed = (seed * 16807) % 2147483647; return seed / 2147483647; };
    const data = new Float32Array(count * 2 * 4);
    const points = [];
    for (let i = 0; i < count; i += 1) {
      const p = [0, 1, 2].map((a) => field.origin[a] + field.spacing[a] * (field.counts[a] - 1) * random());
      const d = [random() - 0.5, random() - 0.5, random() - 0.5];
      const length = Math.hypot(...d);
      const n = d.map((v) => Math.fround(v / length));
      points.push({ p: p.map(Math.fround), n });
      data.set([...p, 1], i * 4);
      data.set([...n, 1], (count + i) * 4);
    }
    const pointTexture = new THREE.DataTexture(data, count, 2, THREE.RGBAFormat, THREE.FloatType);
    pointTexture.needsUpdate = true;
    const probes = new ProbeUniforms();
    probes.update(field);
    const material = new THREE.RawShaderMaterial({
      glslVersion: THREE.GLSL3,
      uniforms: { ...probes.uniforms, ddgiPoints: { value: pointTexture } },
      vertexShader: 'in vec3 position; void main() { gl_Position = vec4(position.xy, 0.0, 1.0); }',
      fragmentShader: `precision highp float; precision highp int;
        uniform highp sampler2D ddgiPoints;
        ${PROBE_GLSL}
        out vec4 color;
        void main() {
          int i = int(gl_FragCoord.x);
          vec3 p = texelFetch(ddgiPoints, ivec2(i, 0), 0).xyz;
          vec3 n = texelFetch(ddgiPoints, ivec2(i, 1), 0).xyz;
          color = vec4(ddgiProbeIrradiance(p, n, n), 1.0);
        }`,
    });
    const scene = new THREE.Scene();
    scene.add(new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material));
    const renderer = new THREE.WebGLRenderer({ canvas: document.createElement('canvas') });
    const target = new THREE.WebGLRenderTarget(count, 1, { type: THREE.FloatType });
    renderer.setRenderTarget(target);
    renderer.render(scene, new THREE.Camera());
    const out = new Float32Array(count * 4);
    renderer.readRenderTargetPixels(target, 0, 0, count, 1, out);
    renderer.dispose();
    const wrong = structuredClone(field);
    const values = field.basis === 'sh' ? wrong.sh : wrong.irradiance;
    for (let i = 0; i < values.length; i += field.basis === 'sh' ? 27 : 4) values[i] *= 2;
    let max = 0;
    let control = 0;
    let mean = 0;
    points.forEach(({ p, n }, i) => {
      const js = probeIrradiance(field, p, n);
      const bad = probeIrradiance(wrong, p, n);
      for (let c = 0; c < 3; c += 1) {
        const scale = Math.max(js[c], 0.01);
        max = Math.max(max, Math.abs(out[i * 4 + c] - js[c]) / scale);
        control = Math.max(control, Math.abs(out[i * 4 + c] - bad[c]) / scale);
        mean += js[c] / (3 * count);
      }
    });
    return { max, mean, control };
  }, which, 256);
}

function checkGlsl(result, what) {
  check(result.mean > 0.01, `the ${what} field is lit (mean ${result.mean.toFixed(4)})`);
  check(result.max < GLSL_TOLERANCE,
    `the page's GLSL query on the ${what} field equals web/probes.js: max relative ${result.max.toExponential(2)} (< ${GLSL_TOLERANCE})`);
  check(result.control > 100 * GLSL_TOLERANCE,
    `and differs from it on a wrong field (control: ${result.control.toExponential(2)})`);
}

async function waitForLocalFrames(page, count) {
  await page.waitForFunction((n) => window.ddgi.local.view.frames >= n,
    { timeout: COMMAND_DEADLINE_MS, polling: 50 }, count);
}

// In local mode, a second client (another WebSocket) moves an object: the page's scene follows
// (its session poll) and its own full image changes, far more than it does meanwhile without.
async function anotherClientMovesAnObject(page) {
  await page.select('#view-mode', 'VIEW_MODE_FULL');
  await waitForLocalFrames(page, (await page.evaluate(() => window.ddgi.local.view.frames)) + 2);
  const still1 = await localPixels(page);
  await new Promise((resolve) => setTimeout(resolve, 1500));
  await waitForLocalFrames(page, (await page.evaluate(() => window.ddgi.local.view.frames)) + 1);
  const still2 = await localPixels(page);
  const moved = await page.evaluate(async (token) => {
    const { DdgiSocket } = await import('/socket.js');
    const other = new DdgiSocket(`${location.origin.replace(/^http/, 'ws')}/ws`,
      { onFrame() {}, onStreamEnded() {}, onClose() {} });
    await other.call('hello', { token });
    const { sessionId } = window.ddgi.session;
    const info = await other.call('getSession', { sessionId });
    const instance = info.instances[info.instances.length - 1];
    const m = instance.transform.m.slice();
    m[12] += 0.3;
    await other.call('setInstanceTransform', { sessionId, instanceIndex: instance.index ?? 0, transform: { m } });
    other.close();
    return { index: instance.index ?? 0, x: m[12] };
  }, TOKEN);
  await page.waitForFunction(({ index, x }) =>
    Math.abs(window.ddgi.local.view.instances.get(index).position.x - x) < 1e-5,
  { timeout: COMMAND_DEADLINE_MS, polling: 100 }, moved);
  await waitForLocalFrames(page, (await page.evaluate(() => window.ddgi.local.view.frames)) + 2);
  const after = await localPixels(page);
  const stillChange = meanAbsDifference(still1, still2);
  const change = meanAbsDifference(still2, after);
  check(change > MIN_DRAG_CHANGE / 2 && change > 4 * stillChange,
    `an object another client moved moves in the page's own image: mean |diff| ${change.toFixed(2)} (> ${MIN_DRAG_CHANGE / 2} and > 4x the ${stillChange.toFixed(2)} of 1.5 s without)`);
}

async function localModeMatchesTheServersFrame(page) {
  const full = await canvasPixels(page);
  await page.select('#view-mode', 'VIEW_MODE_INDIRECT');
  await waitForFrames(page, (await page.evaluate(() => window.ddgi.frames)) + 4, COMMAND_DEADLINE_MS);
  const server = await canvasPixels(page);
  await page.select('#render-mode', 'local');
  await page.waitForFunction(() => window.ddgi.local?.view?.frames > 0
    && window.ddgi.local.probes.messages >= 2, { timeout: COMMAND_DEADLINE_MS, polling: 100 })
    .catch(async (error) => {
      const shown = await page.evaluate(() => `${document.getElementById('status').textContent} / `
        + `${document.getElementById('error').textContent}`);
      throw new Error(`${error.message}; the page says: ${shown}`);
    });
  const info = await page.evaluate(() => ({
    loadMs: window.ddgi.local.loadMs,
    size: [document.getElementById('local').width, document.getElementById('local').height],
    status: document.getElementById('status').textContent,
  }));
  const local = await localPixels(page);
  checkGlsl(await glslAgainstJs(page, 'local'), 'streamed octahedral');
  const difference = meanAbsDifference(local, server);
  const control = meanAbsDifference(local, full);
  console.log(`local view ${info.size.join('x')}, ready in ${info.loadMs.toFixed(0)} ms: "${info.status}"`);
  check(mean(local) > 5, `the local indirect image is lit (mean ${mean(local).toFixed(1)} of 255; the server's ${mean(server).toFixed(1)})`);
  check(difference < LOCAL_TOLERANCE,
    `the page's own indirect image matches the server's frame of the view: mean |diff| ${difference.toFixed(2)} (< ${LOCAL_TOLERANCE})`);
  check(control > 4 * LOCAL_TOLERANCE,
    `the server's full image does not (control: ${control.toFixed(2)})`);
  await anotherClientMovesAnObject(page);
  if (process.env.DDGI_WEB_LOCAL_SCREENSHOT) {
    await page.screenshot({ path: process.env.DDGI_WEB_LOCAL_SCREENSHOT });
  }
  await page.select('#render-mode', 'server');
  await waitForFrames(page, (await page.evaluate(() => window.ddgi.frames)) + 2, COMMAND_DEADLINE_MS);
  check(!(await page.evaluate(() => window.ddgi.local)), 'back to the server\'s frames');
}

// Tolerance of the page's streamed-field irradiance against the server's query: fp16 values
// (4.9e-4 relative each), as ProbeStreamTest allows in C++.
const STREAMED_TOLERANCE = 5e-3;

async function probesStreamToThePage(page) {
  const result = await page.evaluate(async () => {
    const { DdgiSocket } = await import('/socket.js');
    const { applyProbeUpdate } = await import('/probe_stream.js');
    const { probeIrradiance } = await import('/probes.js');
    const socket = new DdgiSocket(`${location.origin.replace(/^http/, 'ws')}/ws`,
      { onFrame() {}, onStreamEnded() {}, onClose() {} });
    await socket.call('hello', { token: '' });
    const session = await socket.call('createSession', {
      scene: { name: 'cornell_box' },
      warmupUpdates: 4,
      fieldParams: [{ name: 'counts', value: '4,4,4' }, { name: 'rays_per_probe', value: '64' },
        { name: 'hysteresis', value: '0.5' }, { name: 'basis', value: 'sh' }],
    });
    const stream = {};
    const first = {};
    const sizes = [];
    const threeMessages = new Promise((resolve, reject) => {
      socket.onProbeUpdate = (update) => {
        try {
          if (!stream.messages) applyProbeUpdate(first, update);
          applyProbeUpdate(stream, update);
          sizes.push({ full: update.full, values: update.values.length });
          if (stream.messages === 3) resolve();
        } catch (error) {
          reject(error);
        }
      };
    });
    await socket.call('streamProbes', { sessionId: session.sessionId, changeThreshold: 1e-6 });
    await threeMessages;
    await socket.call('stopProbes', {});
    window.shField = stream.field;
    // Points inside the grid, normals all around.
    const points = [];
    let seed = 7;
    const random = () => { seed = (seed * 16807) % 2147483647; return seed / 2147483647; };
    for (let i = 0; i < 128; i += 1) {
      const n = [random() - 0.5, random() - 0.5, random() - 0.5];
      const length = Math.hypot(...n);
      points.push({
        position: { x: -0.7 + 1.4 * random(), y: 0.2 + 1.6 * random(), z: -0.7 + 1.4 * random() },
        normal: { x: n[0] / length, y: n[1] / length, z: n[2] / length },
      });
    }
    const reply = await socket.call('queryIrradiance', { sessionId: session.sessionId, points });
    const worst = (field) => {
      let max = 0;
      let mean = 0;
      points.forEach((point, i) => {
        const p = [point.position.x, point.position.y, point.position.z];
        const n = [point.normal.x, point.normal.y, point.normal.z];
        const ours = probeIrradiance(field, p, n);
        const theirs = [reply.irradiance[i].x ?? 0, reply.irradiance[i].y ?? 0,
          reply.irradiance[i].z ?? 0];
        for (let c = 0; c < 3; c += 1) {
          max = Math.max(max, Math.abs(ours[c] - theirs[c]) / Math.max(theirs[c], 0.01));
          mean += theirs[c] / (3 * points.length);
        }
      });
      return { max, mean };
    };
    await socket.call('closeSession', { sessionId: session.sessionId });
    socket.close();
    return {
      streamed: worst(stream.field),
      control: worst(first.field),
      streamUpdates: stream.fieldUpdates,
      queryUpdates: Number(reply.fieldUpdates),
      sizes,
    };
  });
  check(result.sizes[0].full && !result.sizes[1].full && !result.sizes[2].full,
    'the probe stream starts with a full message, then deltas');
  check(result.streamUpdates === result.queryUpdates,
    `the page's field and the query come from one update (${result.streamUpdates})`);
  check(result.streamed.mean > 0.01, `the streamed field is lit (mean ${result.streamed.mean.toFixed(4)})`);
  check(result.streamed.max < STREAMED_TOLERANCE,
    `web/probes.js on the streamed SH field matches QueryIrradiance: max relative ${result.streamed.max.toExponential(2)} (< ${STREAMED_TOLERANCE})`);
  check(result.control.max > 10 * STREAMED_TOLERANCE,
    `the first message alone does not (control: ${result.control.max.toExponential(2)})`);
  checkGlsl(await glslAgainstJs(page, 'sh'), 'streamed SH');
}

async function main() {
  const dir = mkdtempSync(join(tmpdir(), 'ddgi-web-'));
  const tokenFile = join(dir, 'token');
  writeFileSync(tokenFile, `${TOKEN}\n`);
  const server = startServer(['--auth-token-file', tokenFile, '--budget-frame', '64x36']);
  const url = await server.url;
  const browser = await puppeteer.launch({
    executablePath: chromiumPath,
    headless: true,
    args: ['--no-sandbox', '--headless=new'],
  });
  let failed = null;
  try {
    const page = await browser.newPage();
    // Small frames keep lavapipe quick; the README's screenshot is taken larger.
    await page.setViewport(process.env.DDGI_WEB_SCREENSHOT ? { width: 1100, height: 640 }
      : { width: 640, height: 320 });
    page.on('pageerror', (error) => { failed ??= new Error(`page error: ${error.message}`); });
    await page.goto(url);
    await tokenIsAskedForAndChecked(page);
    await streamShowsAndDragMovesTheCamera(page);
    await localModeMatchesTheServersFrame(page);
    await timeBudgetIsChosenAndShown(page);
    if (failed) throw failed;
  } finally {
    await stopServer(server);
  }
  const paced = startServer(['--max-fps', '2']);
  try {
    const page = await browser.newPage();
    page.on('pageerror', (error) => { failed ??= new Error(`page error: ${error.message}`); });
    await page.goto(await paced.url);
    await probesStreamToThePage(page);
    if (failed) throw failed;
  } finally {
    await browser.close();
    await stopServer(paced);
  }
}

main().then(() => console.log('all browser tests passed'), (error) => {
  console.error(error.stack || error.message);
  process.exit(1);
});
