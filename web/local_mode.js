// The page's local-rendering mode (docs/web.md): the server's frame stream stops, the scene is
// downloaded once (progress shown), the field comes through StreamProbes, and every camera move
// is drawn here at once (local_view.js). Lights and objects moved by any client reach the page
// through the probes (indirect) and a poll of the session every second (direct light, object
// placement; a scene loaded meanwhile is downloaded again). three.js is loaded only when this
// mode starts, so the remote mode works without it.
import { applyProbeUpdate } from './probe_stream.js';

const SESSION_POLL_MS = 1000;

export class LocalMode {
  // socket: DdgiSocket; canvas: the WebGL canvas; onStatus(text) shows progress; onError(error).
  constructor(socket, canvas, { onStatus, onError }) {
    this.socket = socket;
    this.canvas = canvas;
    this.onStatus = onStatus;
    this.onError = onError;
    this.view = null;
    this.probes = {}; // { field, fieldUpdates, messages } (probe_stream.js)
    this.dirty = false;
    this.running = false;
    this.loadMs = null;
    this.frameTimes = [];
    this.probeMessages = []; // [time, bytes] of the last second's probe updates
  }

  // Starts on `session` at `camera` (an OrbitCamera) and `width` x `height` pixels.
  async start(session, token, camera, width, height, indirectOnly) {
    this.session = session;
    this.camera = camera;
    this.size = { width, height };
    const started = performance.now();
    let LocalView;
    let downloadScene;
    try {
      ({ LocalView, downloadScene } = await import('./local_view.js'));
    } catch (error) {
      throw new Error('local rendering needs three.js: run `npm ci --prefix web` on the server ' +
        `host (${error.message})`);
    }
    this.token = token;
    this.LocalView = LocalView;
    this.downloadScene = downloadScene;
    this.indirectOnly = indirectOnly;
    await this.loadScene();
    this.socket.onProbeUpdate = (update, bytes) => this.probeUpdate(update, bytes);
    this.socket.onProbeStreamEnded = (ended) => {
      if (this.running && ended.code !== 'OK') this.onError(new Error(`probe stream: ${ended.code}: ${ended.message}`));
    };
    await this.socket.call('streamProbes', { sessionId: session.sessionId });
    this.loadMs = performance.now() - started;
    this.running = true;
    this.pollSession();
    this.cameraChanged();
    requestAnimationFrame(() => this.draw());
  }

  async loadScene() {
    const glb = await this.downloadScene(this.session.sessionId, this.token, (received, total) => {
      const percent = total ? ` (${Math.round((100 * received) / total)}%)` : '';
      this.onStatus(`downloading the scene: ${(received / 1e6).toFixed(1)} MB${percent}`);
    });
    this.onStatus('building the scene');
    this.view ??= new this.LocalView(this.canvas);
    await this.view.load(glb);
    this.view.setIndirectOnly(this.indirectOnly);
    this.cameraChanged();
  }

  probeUpdate(update, bytes) {
    const now = performance.now();
    this.probeMessages.push([now, bytes]);
    while (this.probeMessages[0][0] < now - 1000) this.probeMessages.shift();
    try {
      applyProbeUpdate(this.probes, update);
      this.view.setField(this.probes.field);
      this.dirty = true;
    } catch (error) {
      this.onError(error);
    }
  }

  // Follows what other clients change: lights, object placement, the scene itself.
  async pollSession() {
    let seen = this.session.commandSeq;
    while (this.running) {
      try {
        const info = await this.socket.call('getSession', { sessionId: this.session.sessionId });
        if (info.scene !== this.session.scene || info.triangles !== this.session.triangles) {
          this.session = info;
          await this.loadScene();
        } else if (info.commandSeq !== seen) {
          for (const entry of info.lights ?? []) this.view.updateLight(Number(entry.lightId), entry.light);
          for (const instance of info.instances ?? []) this.view.updateInstance(instance);
          this.dirty = true;
        }
        seen = info.commandSeq;
      } catch (error) {
        if (this.running) this.onError(error);
      }
      await new Promise((resolve) => setTimeout(resolve, SESSION_POLL_MS));
    }
  }

  cameraChanged() {
    if (!this.view) return;
    this.view.setCamera(this.camera, this.size.width, this.size.height);
    this.dirty = true;
  }

  setIndirectOnly(on) {
    this.indirectOnly = on;
    this.view?.setIndirectOnly(on);
    this.dirty = true;
  }

  // Draws when something changed; frames/s counts drawn frames over the last second.
  draw() {
    if (!this.running) return;
    if (this.dirty && this.probes.field) {
      this.dirty = false;
      this.view.render();
      const now = performance.now();
      this.frameTimes.push(now);
      while (this.frameTimes[0] < now - 1000) this.frameTimes.shift();
    }
    requestAnimationFrame(() => this.draw());
  }

  // Frames drawn here over the last second (only when the camera, a light or the probes moved).
  framesPerSecond() {
    return this.frameTimes.length;
  }

  // The probe stream's bytes over the last second.
  bytesPerSecond() {
    return this.probeMessages.reduce((sum, [, bytes]) => sum + bytes, 0);
  }

  async stop() {
    this.running = false;
    this.socket.onProbeUpdate = null;
    await this.socket.call('stopProbes', {}).catch(() => {});
    this.view?.dispose();
    this.view = null;
  }
}
