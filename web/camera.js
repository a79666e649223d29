// Orbit, pan, zoom and WASD movement of a pinhole camera (the service's Camera: position,
// target, up, vertical field of view), as plain vector math on [x, y, z] arrays.

const add = (a, b) => a.map((v, i) => v + b[i]);
const sub = (a, b) => a.map((v, i) => v - b[i]);
const scale = (a, s) => a.map((v) => v * s);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [
  a[1] * b[2] - a[2] * b[1],
  a[2] * b[0] - a[0] * b[2],
  a[0] * b[1] - a[1] * b[0],
];
const length = (a) => Math.sqrt(dot(a, a));
const normalize = (a) => scale(a, 1 / (length(a) || 1));

const vec = (v) => [v?.x ?? 0, v?.y ?? 0, v?.z ?? 0];
const message = (a) => ({ x: a[0], y: a[1], z: a[2] });

export class OrbitCamera {
  // From a Camera message (the frame's, which the server normalized: forward and up are unit).
  constructor(camera) {
    this.position = vec(camera.position);
    const forward = camera.forward ? normalize(vec(camera.forward))
      : normalize(sub(vec(camera.target), this.position));
    this.up = camera.up ? normalize(vec(camera.up)) : [0, 1, 0];
    this.fov = camera.verticalFovDegrees || 45;
    // Orbit around a point in front of the camera, as far as the scene's default target.
    const distance = camera.target ? length(sub(vec(camera.target), this.position)) : 3;
    this.target = add(this.position, scale(forward, distance));
  }

  toMessage() {
    return {
      position: message(this.position),
      target: message(this.target),
      up: message(this.up),
      verticalFovDegrees: this.fov,
    };
  }

  basis() {
    const forward = normalize(sub(this.target, this.position));
    const right = normalize(cross(forward, this.up));
    return { forward, right, up: cross(right, forward) };
  }

  // Turns the camera around its target: dx about the up axis, dy in elevation (radians).
  orbit(dx, dy) {
    const upAxis = normalize(this.up);
    const offset = sub(this.position, this.target);
    const radius = length(offset);
    const height = dot(offset, upAxis);
    const flat = sub(offset, scale(upAxis, height));
    // Straight above or below the target: the view's forward gives the horizontal direction.
    const horizontal = length(flat) > 1e-6 * radius ? normalize(flat)
      : scale(this.basis().forward, -1);
    const elevation = Math.atan2(height, length(flat));
    const pitch = Math.max(-1.5, Math.min(1.5, elevation + dy));
    const side = cross(upAxis, horizontal);
    const turned = add(scale(horizontal, Math.cos(dx)), scale(side, Math.sin(dx)));
    const direction = add(scale(turned, Math.cos(pitch)), scale(upAxis, Math.sin(pitch)));
    this.position = add(this.target, scale(direction, radius));
  }

  // Moves camera and target together in the view plane, by a fraction of the orbit radius.
  pan(dx, dy) {
    const { right, up } = this.basis();
    const radius = length(sub(this.position, this.target));
    const move = add(scale(right, -dx * radius), scale(up, dy * radius));
    this.position = add(this.position, move);
    this.target = add(this.target, move);
  }

  // Moves toward the target by a factor (< 1 closer, > 1 farther).
  zoom(factor) {
    const offset = sub(this.position, this.target);
    this.position = add(this.target, scale(offset, Math.max(1e-3, factor)));
  }

  // WASD QE: moves camera and target along forward, right and up, in world units.
  move(forwardAmount, rightAmount, upAmount) {
    const { forward, right, up } = this.basis();
    const move = add(add(scale(forward, forwardAmount), scale(right, rightAmount)),
      scale(up, upAmount));
    this.position = add(this.position, move);
    this.target = add(this.target, move);
  }
}
