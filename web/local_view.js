// Local rendering from streamed probes (the DDISH-GI split, docs/web.md): the page downloads the
// session's scene (GET /scene.glb, ExportScene), rasterizes it with three.js (WebGL2), lights
// it directly with the scene's punctual lights (shadow maps), and takes indirect diffuse light
// from the probes StreamProbes sends (probe_shader.js: the server's query in GLSL). The camera
// then moves with no network in the loop. Exposure 1, tone mapping (Narkowicz's ACES fit) and
// sRGB encoding are the server's defaults for a view (shaders/render/tonemap.comp; the page
// never asks for others), so a view here and the server's frame of the same view can be
// compared pixel for pixel.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { PROBE_GLSL, ProbeUniforms } from './probe_shader.js';

// three's CustomToneMapping hook, once per page: the server's ACES fit after its exposure.
THREE.ShaderChunk.tonemapping_pars_fragment = THREE.ShaderChunk.tonemapping_pars_fragment.replace(
  /vec3 CustomToneMapping\( vec3 color \) \{[^}]*\}/,
  `vec3 CustomToneMapping( vec3 color ) {
    color *= toneMappingExposure;
    return clamp((color * (2.51 * color + 0.03)) / (color * (2.43 * color + 0.59) + 0.14), 0.0, 1.0);
  }`,
);

// Reads a fetch response to its end, reporting (received, total) as bytes come.
async function readAll(response, onProgress) {
  const total = Number(response.headers.get('Content-Length')) || 0;
  const reader = response.body.getReader();
  const parts = [];
  let received = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    parts.push(value);
    received += value.length;
    onProgress?.(received, total);
  }
  if (total && received !== total) throw new Error(`the scene download ended at ${received} of ${total} bytes`);
  const bytes = new Uint8Array(received);
  let at = 0;
  for (const part of parts) {
    bytes.set(part, at);
    at += part.length;
  }
  return bytes.buffer;
}

// The session's scene as .glb, with the page's token; throws with the server's message.
export async function downloadScene(sessionId, token, onProgress) {
  const headers = token ? { Authorization: `Bearer ${token}` } : {};
  const response = await fetch(`/scene.glb?session=${encodeURIComponent(sessionId)}`, { headers });
  if (!response.ok) throw new Error((await response.text()).trim() || `HTTP ${response.status}`);
  return readAll(response, onProgress);
}

// A Lambertian copy of a glTF material (the server's surfaces are Lambertian) whose indirect
// light comes from the probes, and whose direct light and emission the indirect view drops.
function probeMaterial(source, probes) {
  const material = new THREE.MeshLambertMaterial({
    color: source.color,
    map: source.map,
    emissive: source.emissive,
    emissiveMap: source.emissiveMap,
    emissiveIntensity: source.emissiveIntensity,
    side: THREE.DoubleSide, // rays hit both sides of every triangle on the server
    alphaTest: source.alphaTest,
    transparent: source.transparent,
    opacity: source.opacity,
    flatShading: source.flatShading,
  });
  material.userData.indirectOnly = { value: false };
  material.onBeforeCompile = (shader) => {
    Object.assign(shader.uniforms, probes.uniforms, { ddgiIndirectOnly: material.userData.indirectOnly });
    shader.vertexShader = `varying vec3 vDdgiWorld;\n${shader.vertexShader}`.replace(
      '#include <project_vertex>',
      '#include <project_vertex>\n  vDdgiWorld = (modelMatrix * vec4(transformed, 1.0)).xyz;',
    );
    shader.fragmentShader = `varying vec3 vDdgiWorld;\nuniform bool ddgiIndirectOnly;\n${PROBE_GLSL}\n${shader.fragmentShader}`
      .replace('#include <lights_fragment_maps>', `#include <lights_fragment_maps>
  {
    vec3 ddgiNormal = normalize(inverseTransformDirection(normal, viewMatrix));
    vec3 ddgiToCamera = ddgiSafeNormalize(cameraPosition - vDdgiWorld, ddgiNormal);
    irradiance += PI * ddgiProbeIrradiance(vDdgiWorld, ddgiNormal, ddgiToCamera);
  }`)
      .replace('#include <aomap_fragment>', `#include <aomap_fragment>
  if (ddgiIndirectOnly) {
    reflectedLight.directDiffuse = vec3(0.0);
    totalEmissiveRadiance = vec3(0.0);
  }`);
  };
  return material;
}

export class LocalView {
  constructor(canvas) {
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    this.renderer.shadowMap.enabled = true;
    this.renderer.shadowMap.type = THREE.PCFShadowMap;
    this.renderer.toneMapping = THREE.CustomToneMapping;
    this.renderer.outputColorSpace = THREE.SRGBColorSpace;
    this.probes = new ProbeUniforms();
    this.scene = null;
    this.materials = [];
    this.lights = new Map(); // light id -> { light, node }
    this.instances = new Map(); // instance index -> node
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.01, 100);
    this.frames = 0;
  }

  // Builds the three.js scene from .glb bytes (replacing one built before).
  async load(glb) {
    const gltf = await new GLTFLoader().parseAsync(glb, '');
    this.disposeScene();
    this.scene = gltf.scene;
    this.scene.background = new THREE.Color(0, 0, 0);
    this.renderer.toneMappingExposure = 1;
    const bounds = new THREE.Box3().setFromObject(this.scene);
    this.size = bounds.getSize(new THREE.Vector3()).length() || 1;
    this.scene.traverse((object) => {
      if (object.userData.ddgi_instance !== undefined) {
        this.instances.set(Number(object.userData.ddgi_instance), object);
      }
      if (object.isMesh) {
        object.material = probeMaterial(object.material, this.probes);
        object.castShadow = true;
        object.receiveShadow = true;
        this.materials.push(object.material);
      }
      if (object.isLight) this.addLight(object, bounds);
    });
    this.camera.near = this.size * 1e-3;
    this.camera.far = this.size * 10;
  }

  addLight(light, bounds) {
    // The node that carries the light's id (the light itself when the node holds nothing else)
    // is what moves it.
    const node = light.userData?.ddgi_light_id !== undefined ? light : light.parent;
    const id = node?.userData?.ddgi_light_id;
    if (id !== undefined) this.lights.set(Number(id), { light, node });
    light.castShadow = true;
    light.shadow.mapSize.set(1024, 1024);
    // No normal bias: three offsets along the vertex normal, which need not face the light on
    // double-sided surfaces (the server's rays take either side).
    light.shadow.bias = -5e-4;
    light.shadow.camera.near = this.size * 1e-3;
    light.shadow.camera.far = this.size * 4;
    if (light.isDirectionalLight) {
      const radius = this.size / 2;
      Object.assign(light.shadow.camera, { left: -radius, right: radius, top: radius, bottom: -radius });
      light.target.position.copy(bounds.getCenter(new THREE.Vector3()));
    }
  }

  // A light as the API reports it (LightEntry.light): position, direction, colour, intensity.
  updateLight(id, message) {
    const entry = this.lights.get(id);
    if (!entry) return;
    const { light, node } = entry;
    const vector = (v) => new THREE.Vector3(v?.x ?? 0, v?.y ?? 0, v?.z ?? 0);
    node.position.copy(vector(message.position));
    const direction = vector(message.direction);
    if (direction.lengthSq() > 0) {
      node.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, -1), direction.normalize());
    }
    if (message.color) light.color.setRGB(message.color.x ?? 0, message.color.y ?? 0, message.color.z ?? 0);
    if (message.intensity !== undefined) light.intensity = message.intensity;
  }

  // An Instance as the API reports it: its column-major object-to-world matrix.
  updateInstance(instance) {
    const node = this.instances.get(Number(instance.index ?? 0));
    const m = instance.transform?.m;
    if (!node || m?.length !== 16) return;
    new THREE.Matrix4().fromArray(m).decompose(node.position, node.quaternion, node.scale);
  }

  setField(field) {
    this.probes.update(field);
  }

  setIndirectOnly(on) {
    for (const material of this.materials) material.userData.indirectOnly.value = on;
  }

  // An OrbitCamera (camera.js): position, target, up, vertical field of view in degrees.
  setCamera(orbit, width, height) {
    if (this.canvas.width !== width || this.canvas.height !== height) {
      this.renderer.setSize(width, height, false);
    }
    this.camera.fov = orbit.fov;
    this.camera.aspect = width / height;
    this.camera.position.set(...orbit.position);
    this.camera.up.set(...orbit.up);
    this.camera.lookAt(...orbit.target);
    this.camera.updateProjectionMatrix();
  }

  render() {
    if (!this.scene) return;
    this.renderer.render(this.scene, this.camera);
    this.frames += 1;
  }

  disposeScene() {
    this.scene?.traverse((object) => {
      object.geometry?.dispose();
      object.material?.map?.dispose();
      object.material?.emissiveMap?.dispose();
      object.material?.dispose();
      object.shadow?.map?.dispose();
    });
    this.scene = null;
    this.materials = [];
    this.lights.clear();
    this.instances.clear();
  }

  dispose() {
    this.disposeScene();
    this.renderer.dispose();
  }
}
