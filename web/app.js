// The web client's page logic: connect (with a token when the server asks for one), pick a
// scene or a running session, stream a view into the canvas, steer its camera with mouse and
// keys, change a few field parameters and move a light; live frames/s, latency and bandwidth.
// A second mode draws the scene here from streamed probes (local_mode.js).
// window.ddgi exposes the page's state for the browser tests (tests/web/).
import { CallError, DdgiSocket } from './socket.js';
import { LocalMode } from './local_mode.js';
import { OrbitCamera } from './camera.js';
import { StreamStats } from './stats.js';

const $ = (id) => document.getElementById(id);
const TOKEN_KEY = 'ddgi-token';

const state = {
  socket: null,
  serverInfo: null,
  session: null, // SessionInfo
  field: null, // the session's FieldParams as last shown
  viewId: null,
  camera: null, // OrbitCamera, once the first frame of a stream shows where it is
  cameraDirty: false,
  cameraBusy: false, // a SetCamera is in flight
  stats: new StreamStats(),
  frames: 0,
  lastFrame: null, // the newest frame's header
  decoding: false,
  pendingJpeg: null,
  lightRange: 1, // the scene's default view distance: light sliders' span, WASD step
  lights: [],
  token: '',
  local: null, // LocalMode while the page renders itself
};
window.ddgi = state;

function showError(text) {
  $('error').textContent = text;
  $('error').hidden = !text;
}

function setStatus(text) {
  $('status').textContent = text;
}

function describe(error) {
  if (error instanceof CallError && error.code === 'UNAUTHENTICATED') {
    return `The server refused the access token (${error.message}). Enter the token it was ` +
      'started with (--auth-token-file) and press Connect.';
  }
  return error.message;
}

// ---- Connection -------------------------------------------------------------------------------

function openSocket() {
  const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
  state.socket = new DdgiSocket(`${scheme}://${location.host}/ws`, {
    onFrame: showFrame,
    onStreamEnded: (ended) => {
      if (state.local) return; // the page stopped it to render itself
      setStatus(`stream ended: ${ended.code}${ended.message ? ` (${ended.message})` : ''}`);
      if (ended.code !== 'OK') showError(`The stream ended: ${ended.code}: ${ended.message}`);
      leaveView();
    },
    onClose: () => {
      setStatus('disconnected from the server');
      showError('The connection to the server closed. Reload the page to reconnect.');
    },
  });
}

async function hello() {
  const token = $('token').value || sessionStorage.getItem(TOKEN_KEY) || '';
  try {
    state.serverInfo = await state.socket.call('hello', { token });
  } catch (error) {
    $('auth').hidden = false;
    showError(describe(error));
    setStatus('not connected');
    return;
  }
  if (token) sessionStorage.setItem(TOKEN_KEY, token);
  state.token = token;
  $('auth').hidden = true;
  showError('');
  const info = state.serverInfo;
  setStatus(`connected: ${info.deviceName} (${info.backend})`);
  $('scene').replaceChildren(...info.scenes.map((name) => new Option(name, name)));
  if (info.scenes.includes('cornell_box')) $('scene').value = 'cornell_box';
  await refreshSessions();
}

async function refreshSessions() {
  const reply = await state.socket.call('listSessions', {});
  const sessions = reply.sessions ?? [];
  $('sessions').replaceChildren(...sessions.map((s) => new Option(
    `${s.scene} · ${s.sessionId.slice(0, 8)} · ${s.views} view(s)`, s.sessionId)));
  $('join').disabled = sessions.length === 0;
}

// ---- Sessions and the stream --------------------------------------------------------------------

async function createSession() {
  setStatus(`loading ${$('scene').value}…`);
  try {
    const session = await state.socket.call('createSession', {
      scene: { name: $('scene').value },
      directMode: $('direct-mode').value,
    });
    await startStream(session);
  } catch (error) {
    showError(describe(error));
    setStatus('connected');
  }
}

async function joinSession() {
  try {
    const session = await state.socket.call('getSession', { sessionId: $('sessions').value });
    await startStream(session);
  } catch (error) {
    showError(describe(error));
  }
}

function frameSize() {
  const canvas = $('frame');
  const limits = state.serverInfo.limits;
  const ratio = Math.min(window.devicePixelRatio || 1, 2);
  return {
    width: Math.max(16, Math.min(limits.maxWidth, Math.round(canvas.clientWidth * ratio))),
    height: Math.max(16, Math.min(limits.maxHeight, Math.round(canvas.clientHeight * ratio))),
  };
}

// `camera` (a Camera message) keeps the view where the page had it; absent: the scene's.
async function startStream(session, camera = undefined) {
  state.session = session;
  state.camera = null;
  state.viewId = null;
  state.stats = new StreamStats();
  showError('');
  await state.socket.call('streamFrames', {
    sessionId: session.sessionId,
    settings: { ...frameSize(), viewMode: $('view-mode').value },
    camera,
  });
  setStatus(`session ${session.sessionId.slice(0, 8)} on ${session.scene}`);
  $('choose').hidden = true;
  $('controls').hidden = false;
  showField(session.field);
  showLights(session);
  $('frame').focus();
}

function leaveView() {
  state.viewId = null;
  state.camera = null;
  $('choose').hidden = false;
  $('controls').hidden = true;
  refreshSessions().catch(() => {});
}

async function leave() {
  if (state.local) await leaveLocal();
  await state.socket.call('stopFrames', {});
  leaveView();
  $('render-mode').value = 'server';
}

// ---- Local rendering ------------------------------------------------------------------------------

function showCanvas(local) {
  $('frame').hidden = local;
  $('local').hidden = !local;
  (local ? $('local') : $('frame')).focus();
}

async function enterLocal() {
  if (!state.camera) throw new Error('wait for the first frame: it tells where the camera is');
  const { width, height } = $('frame');
  state.local = new LocalMode(state.socket, $('local'), {
    onStatus: setStatus,
    onError: (error) => showError(describe(error)),
  });
  await state.socket.call('stopFrames', {});
  state.viewId = null;
  showCanvas(true);
  await state.local.start(state.session, state.token, state.camera, width, height,
    $('view-mode').value === 'VIEW_MODE_INDIRECT');
  setStatus(`local rendering of ${state.session.scene} (ready in ` +
    `${(state.local.loadMs / 1000).toFixed(1)} s)`);
}

async function leaveLocal() {
  const local = state.local;
  state.local = null;
  await local.stop();
  showCanvas(false);
}

async function changeRenderMode() {
  try {
    if ($('render-mode').value === 'local') {
      await enterLocal();
    } else if (state.local) {
      const camera = state.camera.toMessage();
      await leaveLocal();
      await startStream(state.session, camera);
    }
  } catch (error) {
    showError(describe(error));
    setStatus('local rendering failed');
    if (state.local) {
      await leaveLocal();
      await startStream(state.session, state.camera?.toMessage()).catch(() => {});
    }
    $('render-mode').value = 'server';
  }
}

// Frames: latest wins here too; a frame that comes while one decodes replaces the waiting one.
function showFrame(header, jpeg, bytes) {
  state.frames += 1;
  state.lastFrame = header;
  state.viewId = header.viewId;
  state.stats.frame(performance.now(), bytes, Number(header.lastCommandSeq));
  if (!state.camera) state.camera = new OrbitCamera(header.camera);
  state.pendingJpeg = jpeg;
  if (!state.decoding) drawLatest();
  $('gpu').textContent = `${Number(header.gpuMs).toFixed(2)} ms`;
  $('dropped').textContent = header.framesDropped;
}

async function drawLatest() {
  state.decoding = true;
  while (state.pendingJpeg) {
    const jpeg = state.pendingJpeg;
    state.pendingJpeg = null;
    const image = await createImageBitmap(new Blob([jpeg], { type: 'image/jpeg' }));
    const canvas = $('frame');
    canvas.width = image.width;
    canvas.height = image.height;
    canvas.getContext('2d').drawImage(image, 0, 0);
    image.close();
  }
  state.decoding = false;
}

// ---- Camera -------------------------------------------------------------------------------------

// At most one SetCamera in flight: moves made meanwhile are sent together when it returns.
async function sendCamera() {
  if (!state.cameraDirty || state.cameraBusy || !state.viewId) return;
  state.cameraDirty = false;
  state.cameraBusy = true;
  const sentAt = performance.now();
  try {
    const view = await state.socket.call('setCamera', {
      sessionId: state.session.sessionId,
      viewId: state.viewId,
      camera: state.camera.toMessage(),
    });
    state.stats.commandApplied(Number(view.commandSeq), sentAt);
  } catch (error) {
    showError(describe(error));
  } finally {
    state.cameraBusy = false;
  }
  sendCamera();
}

function cameraChanged() {
  if (state.local) {
    state.local.cameraChanged();
    return;
  }
  state.cameraDirty = true;
  sendCamera();
}

function bindMouse(canvas) {
  let last = null;
  canvas.addEventListener('contextmenu', (event) => event.preventDefault());
  canvas.addEventListener('pointerdown', (event) => {
    canvas.setPointerCapture(event.pointerId);
    last = { x: event.clientX, y: event.clientY, pan: event.shiftKey || event.button === 2 };
  });
  canvas.addEventListener('pointerup', () => { last = null; });
  canvas.addEventListener('pointermove', (event) => {
    if (!last || !state.camera) return;
    const dx = (event.clientX - last.x) / canvas.clientHeight;
    const dy = (event.clientY - last.y) / canvas.clientHeight;
    last.x = event.clientX;
    last.y = event.clientY;
    if (last.pan) state.camera.pan(dx, dy);
    else state.camera.orbit(-dx * Math.PI, dy * Math.PI);
    cameraChanged();
  });
  canvas.addEventListener('wheel', (event) => {
    event.preventDefault();
    if (!state.camera) return;
    state.camera.zoom(Math.exp(event.deltaY * 0.001));
    cameraChanged();
  }, { passive: false });
}

const KEYS = { w: [1, 0, 0], s: [-1, 0, 0], d: [0, 1, 0], a: [0, -1, 0], e: [0, 0, 1], q: [0, 0, -1] };

function bindKeys(canvas) {
  canvas.addEventListener('keydown', (event) => {
    const move = KEYS[event.key.toLowerCase()];
    if (!move || !state.camera) return;
    const step = 0.05 * Math.max(state.lightRange, 1e-3);
    state.camera.move(move[0] * step, move[1] * step, move[2] * step);
    cameraChanged();
  });
}

// ---- Field parameters, view mode, lights ----------------------------------------------------------

function paramValue(field, name) {
  return field?.params?.find((p) => p.name === name)?.value ?? '';
}

// Floats come as the server prints them (0.970000029): shown to 4 significant digits.
const shortNumber = (text) => (text === '' ? '' : String(Number(Number(text).toPrecision(4))));

function showField(field) {
  state.field = field;
  $('hysteresis').value = shortNumber(paramValue(field, 'hysteresis'));
  $('rays').value = paramValue(field, 'rays_per_probe');
  $('field-info').textContent = field?.probes
    ? `${field.probes} probes, ${(Number(field.gpuBytes) / 2 ** 20).toFixed(1)} MiB, ` +
      `${field.updates} updates`
    : 'no irradiance field';
  // The rule's choice (FieldParams.budget), while the field follows it, and what it misses.
  const budget = field?.budget;
  const fixed = (value, digits) => Number(value ?? 0).toFixed(digits);
  $('budget-info').textContent = budget
    ? `Budget ${budget.budgetMs} ms at ${budget.width}x${budget.height}: ${budget.configuration}, ` +
      `measured ${fixed(budget.costMs, 2)} ms, FLIP ${fixed(budget.flip, 3)} ` +
      `± ${fixed(budget.flipNoise, 3)}, light ${fixed(budget.meanRatio, 3)} of the reference ` +
      `(${budget.candidates} configurations${budget.fromCache ? ', calibrated before' : ''})` +
      (budget.note ? `. ${budget.note}` : '')
    : '';
  $('calibration-info').textContent = describeCalibration(field?.calibration);
}

// FieldParams.calibration as a line: its state, progress and the switch (proto3 JSON leaves
// zeros and false out).
function describeCalibration(calibration) {
  if (!calibration) return '';
  const seconds = Number(calibration.seconds ?? 0).toFixed(1);
  const budget = `budget ${calibration.budgetMs ?? 0} ms`;
  switch (calibration.state) {
    case 'STATE_QUEUED':
      return `Calibration queued (${seconds} s); streaming the static default, ${budget}`;
    case 'STATE_RUNNING':
      return `Calibrating: ${calibration.candidatesDone ?? 0}/${calibration.candidates} ` +
        `configurations measured (${seconds} s); streaming the static default, ${budget}`;
    case 'STATE_DONE':
      if (calibration.fromCache) return `Calibrated before: chosen at load, ${budget}`;
      return calibration.switched
        ? `Calibrated: switched to the choice ${seconds} s after the load, ${budget}`
        : `Calibrated; ${calibration.message ?? ''}`;
    case 'STATE_FAILED':
      return `Calibration failed: ${calibration.message ?? ''}; streaming the static default`;
    case 'STATE_OFF':
      return `No calibration: ${calibration.message ?? ''}; ${budget}`;
    default:
      return '';
  }
}

// Asks the server for its best field configuration within the budget (field parameter
// budget_ms; empty or 0 returns to the server's default budget). The choice comes from the
// scene's calibration, which runs in the background after a load.
async function applyBudget() {
  const value = $('budget').value.trim() === '' ? '0' : $('budget').value.trim();
  try {
    const field = await state.socket.call('setFieldParams', {
      sessionId: state.session.sessionId,
      params: [{ name: 'budget_ms', value }],
    });
    showField(field);
    showError('');
  } catch (error) {
    $('budget-info').textContent = '';
    showError(describe(error));
  }
}

async function applyField() {
  try {
    const field = await state.socket.call('setFieldParams', {
      sessionId: state.session.sessionId,
      params: [
        { name: 'hysteresis', value: $('hysteresis').value },
        { name: 'rays_per_probe', value: $('rays').value },
      ],
    });
    showField(field);
    showError('');
  } catch (error) {
    showError(describe(error));
  }
}

async function changeViewMode() {
  if (state.local) {
    state.local.setIndirectOnly($('view-mode').value === 'VIEW_MODE_INDIRECT');
    return;
  }
  if (!state.viewId) return;
  try {
    await state.socket.call('updateView', {
      sessionId: state.session.sessionId,
      viewId: state.viewId,
      settings: { viewMode: $('view-mode').value },
    });
  } catch (error) {
    showError(describe(error));
  }
}

// The sliders span the scene's default view distance around each light's position.
function showLights(session) {
  const lights = (session.lights ?? []).filter((entry) => entry.light.type !== 'LIGHT_TYPE_DIRECTIONAL');
  const camera = session.defaultCamera;
  const target = camera.target ?? camera.position;
  const dx = (camera.position.x ?? 0) - (target.x ?? 0);
  const dy = (camera.position.y ?? 0) - (target.y ?? 0);
  const dz = (camera.position.z ?? 0) - (target.z ?? 0);
  state.lightRange = Math.hypot(dx, dy, dz) || 1;
  state.lights = lights;
  $('light').replaceChildren(...lights.map((entry) =>
    new Option(entry.light.name || `light ${entry.lightId}`, entry.lightId)));
  $('light-axes').hidden = lights.length === 0;
  selectLight();
}

function selectLight() {
  const entry = state.lights?.find((e) => String(e.lightId) === $('light').value);
  if (!entry) return;
  for (const axis of ['x', 'y', 'z']) {
    const input = $(`light-${axis}`);
    const value = entry.light.position?.[axis] ?? 0;
    input.min = value - state.lightRange;
    input.max = value + state.lightRange;
    input.step = state.lightRange / 200;
    input.value = value;
  }
}

async function moveLight() {
  const lightId = Number($('light').value);
  const position = { x: +$('light-x').value, y: +$('light-y').value, z: +$('light-z').value };
  try {
    await state.socket.call('updateLight', {
      sessionId: state.session.sessionId, lightId, light: { position },
    });
  } catch (error) {
    showError(describe(error));
  }
}

// A resized window gets frames of its new size (once it has been still for a moment).
let resizeTimer = null;
function resized() {
  clearTimeout(resizeTimer);
  resizeTimer = setTimeout(async () => {
    if (!state.viewId) return;
    try {
      await state.socket.call('updateView', {
        sessionId: state.session.sessionId, viewId: state.viewId, settings: frameSize(),
      });
    } catch (error) {
      showError(describe(error));
    }
  }, 300);
}

// ---- Start --------------------------------------------------------------------------------------

function updateStats() {
  if (state.local) {
    $('fps').textContent = `${state.local.framesPerSecond()} drawn here`;
    $('latency').textContent = 'none (drawn here)';
    $('bandwidth').textContent = `${(state.local.bytesPerSecond() * 8 / 1e6).toFixed(2)} Mbit/s of probes`;
    $('gpu').textContent = '–';
    $('dropped').textContent = '–';
    return;
  }
  $('fps').textContent = state.stats.framesPerSecond().toFixed(0);
  $('bandwidth').textContent = `${(state.stats.bytesPerSecond() * 8 / 1e6).toFixed(1)} Mbit/s`;
  $('latency').textContent = state.stats.latencyMs === null ? '–'
    : `${state.stats.latencyMs.toFixed(0)} ms`;
}

function bindControls() {
  $('connect').addEventListener('click', hello);
  $('create').addEventListener('click', createSession);
  $('join').addEventListener('click', joinSession);
  $('refresh').addEventListener('click', () => refreshSessions().catch((e) => showError(describe(e))));
  $('leave').addEventListener('click', leave);
  $('apply-field').addEventListener('click', applyField);
  $('apply-budget').addEventListener('click', applyBudget);
  $('view-mode').addEventListener('change', changeViewMode);
  $('light').addEventListener('change', selectLight);
  for (const axis of ['x', 'y', 'z']) $(`light-${axis}`).addEventListener('input', moveLight);
  $('render-mode').addEventListener('change', changeRenderMode);
  for (const canvas of [$('frame'), $('local')]) {
    bindMouse(canvas);
    bindKeys(canvas);
  }
  window.addEventListener('resize', resized);
  setInterval(updateStats, 250);
  setInterval(followCalibration, 1000);
}

// While the session's calibration is queued or running, its field is asked for once a second,
// so that the page shows the progress and the switch to the calibrated choice.
async function followCalibration() {
  const calibration = state.field?.calibration;
  if (!state.session || !['STATE_QUEUED', 'STATE_RUNNING'].includes(calibration?.state)) return;
  try {
    showField(await state.socket.call('getFieldParams', { sessionId: state.session.sessionId }));
  } catch (error) {
    showError(describe(error));
  }
}

bindControls();
openSocket();
hello();
