// The stream's live figures: frames per second and bandwidth over the last second, and the
// latency from a camera command to the first frame that shows it (the frame's
// lastCommandSeq reaching the command's seq).

const WINDOW_MS = 1000;

export class StreamStats {
  constructor() {
    this.arrivals = []; // [time, bytes]
    this.commands = []; // [seq, sent time], oldest first
    this.latencyMs = null;
  }

  // A command was sent at `sentAt` and applied as `seq` (its reply's commandSeq).
  commandApplied(seq, sentAt) {
    this.commands.push([seq, sentAt]);
  }

  frame(now, bytes, lastCommandSeq) {
    this.arrivals.push([now, bytes]);
    while (this.arrivals.length && now - this.arrivals[0][0] > WINDOW_MS) this.arrivals.shift();
    while (this.commands.length && this.commands[0][0] <= lastCommandSeq) {
      this.latencyMs = now - this.commands.shift()[1];
    }
  }

  framesPerSecond() {
    return this.arrivals.length * (1000 / WINDOW_MS);
  }

  bytesPerSecond() {
    return this.arrivals.reduce((sum, [, bytes]) => sum + bytes, 0) * (1000 / WINDOW_MS);
  }
}
