// The three.js package's page (three.html): the sphere in a three.js scene lit by a directional
// light, with three.js's MeshStandardMaterial four ways: its own MIPs of the map's normals
// ("three-default"), leanStandardMaterial in WebGLRenderer ("standard-webgl"), leanStandardNodes
// in WebGPURenderer ("standard-webgpu"), and the truth: level 0's normals, 8 x 8 samples a pixel
// averaged in linear radiance ("truth"). With ?capture=CELLS ("NAME@distance") it posts each
// cell's linear floats (rows bottom first) to the server and reports when done.
import * as THREE from 'three';
import * as GPU from 'three/webgpu';
import {
  fromHalf, leanfadeCamera, leanMapTexture, leanStandardMaterial, meshGeometry, parseLeanMap, toHalf,
} from '@leanfade/three';
import { leanStandardNodes } from '@leanfade/three/webgpu';

import { makeSphere, viewAtDistance } from './leanfade_webgl.js';
import { pageParams } from './page.js';

const { params, dataUrl, mapName, size, capture } = pageParams(256, 512);
const kSupersampling = 8;
const kRoughness = Number(params.get('roughness') ?? 0.25);  // the material's perceptual roughness (α0 = r²)
const kBackground = [0.05, 0.05, 0.06];

// The normals of the map's finest level, normalize(B.x, B.y, 1), as an RGBA half-float texture
// (v up, as the LEAN map), with three.js making its MIPs (`mips`) or with level 0 alone.
function normalTexture(map, mips) {
  const level = map.levels[0];
  const texels = level.width * level.height;
  const data = new Uint16Array(texels * 4);
  const o = map.leanOffset, gain = 1 + o;
  for (let y = 0; y < level.height; ++y)
    for (let x = 0; x < level.width; ++x) {
      const src = (y * level.width + x) * 4 + texels * 4;  // lean2
      const bx = (gain * fromHalf(level.data[src]) - o) * map.scale;
      const by = (gain * fromHalf(level.data[src + 1]) - o) * map.scale;
      const l = Math.hypot(bx, by, 1);
      const dst = ((level.height - 1 - y) * level.width + x) * 4;
      data[dst] = toHalf(0.5 * bx / l + 0.5);
      data[dst + 1] = toHalf(0.5 * by / l + 0.5);
      data[dst + 2] = toHalf(0.5 / l + 0.5);
      data[dst + 3] = toHalf(1);
    }
  const texture = new THREE.DataTexture(data, level.width, level.height, THREE.RGBAFormat, THREE.HalfFloatType);
  texture.wrapS = texture.wrapT = THREE.RepeatWrapping;
  texture.magFilter = THREE.LinearFilter;
  texture.minFilter = mips ? THREE.LinearMipmapLinearFilter : THREE.LinearFilter;
  texture.generateMipmaps = mips;
  texture.colorSpace = THREE.NoColorSpace;
  texture.needsUpdate = true;
  return texture;
}

// leanfade's sphere with three.js's attribute names, scaled to its unit bounding sphere as
// `leanfade render` draws it.
function sphereMesh(mesh, material, ThreeMesh) {
  const geometry = new THREE.BufferGeometry();
  const g = meshGeometry(mesh);
  for (const [from, to] of [['a_position', 'position'], ['a_normal', 'normal'], ['a_uv', 'uv'], ['a_tangent', 'tangent']])
    geometry.setAttribute(to, g.getAttribute(from));
  geometry.setIndex(g.getIndex());
  const object = new ThreeMesh(geometry, material);
  const radius = 0.5 * Math.hypot(...[0, 1, 2].map((c) => mesh.bounds.max[c] - mesh.bounds.min[c]));
  object.scale.setScalar(1 / radius);
  return object;
}

function lights(scene, Three) {
  const sun = new Three.DirectionalLight(0xffffff, 3);
  sun.position.set(-1, 1, 1);
  scene.add(sun);
  scene.add(new Three.AmbientLight(0xffffff, 0.1));
}

function standard(Three, extra = {}) {
  return new Three.MeshStandardMaterial({ color: 0xb08060, roughness: kRoughness, metalness: 0, ...extra });
}

async function main() {
  const response = await fetch(`${dataUrl}/${mapName}.ktx2`);
  if (!response.ok) throw new Error(`${mapName}.ktx2: ${response.status}`);
  const map = await parseLeanMap(await response.arrayBuffer(), `${mapName}.ktx2`);
  const mesh = makeSphere();
  const camera = (await (await fetch(`${dataUrl}/shaders/shaders.json`)).json()).defaults.camera;
  THREE.ColorManagement.enabled = false;

  // WebGLRenderer: three.js's MIPs, LEAN, and the truth's supersampled frame.
  const glCanvas = document.createElement('canvas');
  const gl = new THREE.WebGLRenderer({ canvas: glCanvas, antialias: false });
  gl.setPixelRatio(1);
  gl.outputColorSpace = THREE.LinearSRGBColorSpace;
  const errors = [];
  gl.debug.onShaderError = (context, program, vertex, fragment) => {
    const log = (shader) => context.getShaderInfoLog(shader)?.trim();
    errors.push(`WebGL: ${log(fragment) || log(vertex) || context.getProgramInfoLog(program)}`);
  };
  const scenes = {};
  for (const name of ['three-default', 'standard-webgl', 'truth']) {
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(...kBackground);
    lights(scene, THREE);
    const material = name === 'standard-webgl'
      ? leanStandardMaterial(standard(THREE), leanMapTexture(map))
      : standard(THREE, { normalMap: normalTexture(map, name === 'three-default') });
    scene.add(sphereMesh(mesh, material, THREE.Mesh));
    scenes[name] = scene;
  }
  const glTarget = (n) => new THREE.WebGLRenderTarget(n, n, { type: THREE.FloatType, depthBuffer: true });
  const targets = { small: glTarget(size), large: glTarget(size * kSupersampling) };

  // WebGPURenderer with TSL nodes.
  const gpuCanvas = document.createElement('canvas');
  const gpu = new GPU.WebGPURenderer({ canvas: gpuCanvas, antialias: false });
  await gpu.init();
  gpu.setPixelRatio(1);
  gpu.outputColorSpace = GPU.LinearSRGBColorSpace;
  const gpuScene = new GPU.Scene();
  gpuScene.background = new GPU.Color(...kBackground);
  lights(gpuScene, GPU);
  const nodeMaterial = new GPU.MeshStandardNodeMaterial({ color: 0xb08060, metalness: 0 });
  Object.assign(nodeMaterial, leanStandardNodes(leanMapTexture(map), { roughness: kRoughness }));
  gpuScene.add(sphereMesh(mesh, nodeMaterial, GPU.Mesh));
  const gpuTarget = new GPU.RenderTarget(size, size, { type: GPU.FloatType, depthBuffer: true });

  // A cell's linear floats, rows bottom first.
  const draw = async (name, distance) => {
    const view = viewAtDistance(distance, camera);
    const cam = leanfadeCamera(view, 1);
    if (name === 'standard-webgpu') {
      gpu.setRenderTarget(gpuTarget);
      await gpu.renderAsync(gpuScene, cam);
      gpu.setRenderTarget(null);
      const rows = await gpu.readRenderTargetPixelsAsync(gpuTarget, 0, 0, size, size);
      // three.js reads WebGPU targets top row first: reversed to match readPixels.
      const out = new Float32Array(size * size * 4);
      for (let y = 0; y < size; ++y) out.set(rows.subarray(y * size * 4, (y + 1) * size * 4), (size - 1 - y) * size * 4);
      return out;
    }
    const n = name === 'truth' ? size * kSupersampling : size;
    const target = name === 'truth' ? targets.large : targets.small;
    gl.setRenderTarget(target);
    gl.render(scenes[name], cam);
    gl.setRenderTarget(null);
    const pixels = new Float32Array(n * n * 4);
    gl.readRenderTargetPixels(target, 0, 0, n, n, pixels);
    if (name !== 'truth') return pixels;
    const k = kSupersampling, out = new Float32Array(size * size * 4);
    for (let y = 0; y < n; ++y)
      for (let x = 0; x < n; ++x)
        for (let c = 0; c < 4; ++c)
          out[(Math.floor(y / k) * size + Math.floor(x / k)) * 4 + c] += pixels[(y * n + x) * 4 + c] / (k * k);
    return out;
  };

  if (capture) {
    for (const cell of capture.split(',')) {
      const [name, distanceText] = cell.split('@');
      const pixels = await draw(name, Number(distanceText));
      await fetch(`/capture/${name}_d${distanceText}.f32`, { method: 'POST', body: pixels });
    }
    await fetch('/capture/done', { method: 'POST', body: JSON.stringify({ errors, renderer: 'three.js r' + THREE.REVISION, size, background: kBackground }) });
    return;
  }

  const names = ['three-default', 'standard-webgl', 'standard-webgpu', 'truth'];
  const canvases = names.map(() => {
    const c = document.createElement('canvas');
    c.width = c.height = size;
    document.getElementById('views').appendChild(c);
    return c;
  });
  const slider = document.getElementById('distance');
  const label = document.getElementById('distance-label');
  const encode = (v) => Math.round(255 * (v <= 0.0031308 ? 12.92 * v : 1.055 * Math.pow(Math.min(v, 1), 1 / 2.4) - 0.055));
  const redraw = async () => {
    const distance = Math.pow(2, Number(slider.value));
    label.textContent = `${distance.toFixed(1)} radii`;
    for (let i = 0; i < names.length; ++i) {
      const pixels = await draw(names[i], distance);
      const image = new ImageData(size, size);
      for (let y = 0; y < size; ++y)
        for (let x = 0; x < size; ++x)
          for (let c = 0; c < 4; ++c)
            image.data[(y * size + x) * 4 + c] = c === 3 ? 255 : encode(Math.max(0, pixels[((size - 1 - y) * size + x) * 4 + c]));
      canvases[i].getContext('2d').putImageData(image, 0, 0);
    }
  };
  slider.addEventListener('input', redraw);
  await redraw();
}

main().catch(async (error) => {
  document.getElementById('status').textContent = String(error);
  if (capture) await fetch('/capture/done', { method: 'POST', body: JSON.stringify({ errors: [String(error.stack ?? error)] }) });
});
