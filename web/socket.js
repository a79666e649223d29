// The page's side of the web protocol (proto/ddgi/v1/web.proto): one WebSocket, calls as JSON
// WebRequests answered by WebReplies with the same id, frames as binary messages (a 4-byte
// little-endian header length, the Frame's JSON without its JPEG, then the JPEG).

export class CallError extends Error {
  constructor(code, message) {
    super(`${code}: ${message}`);
    this.code = code;
  }
}

// Splits a binary frame message into its header (the Frame's JSON) and JPEG bytes.
export function parseFrameMessage(buffer) {
  const view = new DataView(buffer);
  if (buffer.byteLength < 4) throw new Error('frame message shorter than its length field');
  const length = view.getUint32(0, true);
  if (4 + length > buffer.byteLength) throw new Error('frame header longer than the message');
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, length)));
  return { header, jpeg: new Uint8Array(buffer, 4 + length) };
}

export class DdgiSocket {
  // onFrame(header, jpegBytes, messageBytes); onStreamEnded(status) for the current stream
  // (the newest streamFrames call; an older one's end is old news); onClose(event)
  constructor(url, { onFrame, onStreamEnded, onClose }) {
    this.nextId = 1;
    this.pending = new Map();
    this.onFrame = onFrame;
    this.onStreamEnded = onStreamEnded;
    this.ws = new WebSocket(url);
    this.ws.binaryType = 'arraybuffer';
    this.opened = new Promise((resolve, reject) => {
      this.ws.onopen = () => resolve();
      this.ws.onerror = () => reject(new Error(`cannot open ${url}`));
    });
    this.ws.onmessage = (event) => this.receive(event.data);
    this.ws.onclose = (event) => {
      for (const { reject } of this.pending.values()) {
        reject(new CallError('UNAVAILABLE', 'the connection to the server closed'));
      }
      this.pending.clear();
      onClose(event);
    };
  }

  // Sends one call, e.g. call('setCamera', {...}); resolves with the reply's result object.
  async call(name, request = {}) {
    await this.opened;
    const id = this.nextId++;
    if (name === 'streamFrames') this.streamId = id;
    if (name === 'streamProbes') this.probeStreamId = id;
    const reply = new Promise((resolve, reject) => this.pending.set(id, { resolve, reject, name }));
    this.ws.send(JSON.stringify({ id: String(id), [name]: request }));
    return reply;
  }

  receive(data) {
    if (data instanceof ArrayBuffer) {
      const { header, jpeg } = parseFrameMessage(data);
      this.onFrame(header, jpeg, data.byteLength);
      return;
    }
    const reply = JSON.parse(data);
    const id = Number(reply.id);
    const waiting = this.pending.get(id);
    // Probe updates (StreamProbes, docs/probe-stream.md) go to onProbeUpdate(update, bytes), set by
    // whoever started the probe stream; its end to onProbeStreamEnded(status).
    if (reply.probeUpdate) {
      if (id === this.probeStreamId) this.onProbeUpdate?.(reply.probeUpdate, data.length);
      return;
    }
    const stopping = waiting && (waiting.name === 'stopFrames' || waiting.name === 'stopProbes');
    if (reply.streamEnded && !stopping) {
      if (id === this.streamId) this.onStreamEnded(reply.streamEnded);
      if (id === this.probeStreamId) this.onProbeStreamEnded?.(reply.streamEnded);
      return;
    }
    if (!waiting) {
      // A refusal of a message the server could not read (id 0): nothing waits for it.
      if (reply.error) console.error('server:', reply.error.code, reply.error.message);
      return;
    }
    this.pending.delete(id);
    if (reply.error) {
      waiting.reject(new CallError(reply.error.code, reply.error.message));
    } else {
      const { id: _, ...result } = reply;
      waiting.resolve(Object.values(result)[0]);
    }
  }

  close() {
    this.ws.close();
  }
}
