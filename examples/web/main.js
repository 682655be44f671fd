// The example page: bump | LEAN | two-lobe drawn with the exported shaders in plain WebGL2, and
// LEAN through the three.js material, at the distance the slider sets. With ?capture=CELLS it
// draws each cell ("technique@distance", "three-lean@distance") once, posts its linear floats to
// the server (serve.mjs --capture) and reports when done: the suite's WebGL2 test.
import * as THREE from 'three';
import { leanfadeCamera, LeanMaterial, leanMesh } from '@leanfade/three';

import {
  createFloatTarget, LeanfadeScene, loadShaders, makeSphere, parseLeanMap, parseTexture,
  readFloats, viewAtDistance,
} from './leanfade_webgl.js';
import { fetchBytes, pageParams } from './page.js';

const { dataUrl, mapName, size, capture } = pageParams();
const techniques = ['bump', 'lean', 'two-lobe'];


// Linear radiance to sRGB, as `leanfade render` encodes its figures.
const PRESENT_VERTEX = `#version 300 es
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}`;
const PRESENT_FRAGMENT = `#version 300 es
precision highp float;
uniform highp sampler2D u_linear;
uniform ivec2 u_origin;
out vec4 o_color;
vec3 encode_srgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
void main() {
  vec4 linear = texelFetch(u_linear, ivec2(gl_FragCoord.xy) - u_origin, 0);
  o_color = vec4(encode_srgb(linear.rgb), 1.0);
}`;

function presenter(gl) {
  const shader = (type, source) => {
    const s = gl.createShader(type);
    gl.shaderSource(s, source);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  };
  const program = gl.createProgram();
  gl.attachShader(program, shader(gl.VERTEX_SHADER, PRESENT_VERTEX));
  gl.attachShader(program, shader(gl.FRAGMENT_SHADER, PRESENT_FRAGMENT));
  gl.linkProgram(program);
  const vao = gl.createVertexArray();
  return (target, x) => {
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.disable(gl.DEPTH_TEST);
    gl.viewport(x, 0, target.width, target.height);
    gl.useProgram(program);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, target.color);
    gl.uniform1i(gl.getUniformLocation(program, 'u_linear'), 0);
    gl.uniform2i(gl.getUniformLocation(program, 'u_origin'), x, 0);
    gl.bindVertexArray(vao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    gl.bindVertexArray(null);
  };
}

async function main() {
  const [leanMap, plateau, shadersIndexUrl] = [
    await parseLeanMap(await fetchBytes(`${dataUrl}/${mapName}.ktx2`), `${mapName}.ktx2`),
    await parseTexture(await fetchBytes(`${dataUrl}/${mapName}.plateau.ktx2`), `${mapName}.plateau.ktx2`),
    `${dataUrl}/shaders`,
  ];
  const index = await (await fetch(`${shadersIndexUrl}/shaders.json`)).json();
  const shaders = await loadShaders(shadersIndexUrl, techniques.map((t) => index.defaults.variants[t]));
  const mesh = makeSphere();
  const background = shaders.index.defaults.camera.background;

  // Plain WebGL2: the three techniques side by side.
  const canvas = document.getElementById('views');
  canvas.width = size * techniques.length;
  canvas.height = size;
  document.querySelector('.labels').style.width = `${canvas.width}px`;
  const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true });
  if (!gl) throw new Error('this browser has no WebGL2');
  const scene = new LeanfadeScene(gl, shaders, { leanMap, plateau, mesh });
  const target = createFloatTarget(gl, size, size);
  const present = presenter(gl);
  const drawRaw = (technique, distance) => {
    gl.bindFramebuffer(gl.FRAMEBUFFER, target.framebuffer);
    gl.viewport(0, 0, size, size);
    gl.clearColor(...background, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    scene.draw(technique, distance, [0, 0, size, size]);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  };

  // three.js: the LEAN variant as a RawShaderMaterial on the same sphere.
  const threeCanvas = document.getElementById('three');
  threeCanvas.width = size;
  threeCanvas.height = size;
  THREE.ColorManagement.enabled = false;
  const renderer = new THREE.WebGLRenderer({ canvas: threeCanvas, antialias: false });
  renderer.setPixelRatio(1);
  renderer.setSize(size, size, false);
  const threeScene = new THREE.Scene();
  const material = new LeanMaterial(shaders, shaders.index.defaults.variants.lean, leanMap);
  threeScene.add(leanMesh(mesh, material));
  // The light of `leanfade render` as a three.js DirectionalLight, which LeanMaterial follows.
  const blockValue = (block, name) => shaders.index.defaults.blocks[block].find((v) => v.name === name).value;
  const sun = new THREE.DirectionalLight(new THREE.Color(...blockValue('LfShadingBlock', 'u_shading.params.light_color')), 1);
  sun.position.set(...blockValue('LfObjectBlock', 'u_light_world'));
  threeScene.add(sun);
  const threeTarget = new THREE.WebGLRenderTarget(size, size, { type: THREE.FloatType, depthBuffer: true });
  const presentScene = new THREE.Scene();
  const presentMaterial = new THREE.RawShaderMaterial({
    vertexShader: PRESENT_VERTEX.replace('#version 300 es\n', ''),
    fragmentShader: PRESENT_FRAGMENT.replace('#version 300 es\n', ''),
    glslVersion: THREE.GLSL3,
    uniforms: { u_linear: { value: threeTarget.texture }, u_origin: { value: new THREE.Vector2(0, 0) } },
    depthTest: false,
  });
  const quad = new THREE.Mesh(new THREE.BufferGeometry(), presentMaterial);
  quad.geometry.setDrawRange(0, 3);
  // Three vertices for three.js's draw count; the shader makes the triangle from gl_VertexID.
  quad.geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(9), 3));
  quad.frustumCulled = false;
  presentScene.add(quad);
  const presentCamera = new THREE.Camera();
  const drawThree = (distance) => {
    const view = viewAtDistance(distance, shaders.index.defaults.camera);
    renderer.setRenderTarget(threeTarget);
    renderer.setClearColor(new THREE.Color(...background), 1);
    renderer.clear();
    renderer.render(threeScene, leanfadeCamera(view, 1));
    renderer.setRenderTarget(null);
  };

  if (capture) {
    const errors = [];
    for (const cell of capture.split(',')) {
      const [technique, distanceText] = cell.split('@');
      const distance = Number(distanceText);
      let pixels;
      if (technique === 'three-lean') {
        drawThree(distance);
        pixels = new Float32Array(size * size * 4);
        renderer.readRenderTargetPixels(threeTarget, 0, 0, size, size, pixels);
        errors.push(...material.checkBlockOffsets());
      } else {
        drawRaw(technique, distance);
        pixels = readFloats(gl, target, [0, 0, size, size]);
      }
      const glError = gl.getError();
      if (glError !== gl.NO_ERROR) errors.push(`${cell}: WebGL error ${glError}`);
      await fetch(`/capture/${technique}_d${distanceText}.f32`, { method: 'POST', body: pixels });
    }
    const info = gl.getExtension('WEBGL_debug_renderer_info');
    const rendererName = info ? gl.getParameter(info.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
    await fetch('/capture/done', { method: 'POST', body: JSON.stringify({ errors, renderer: rendererName, size }) });
    return;
  }

  const slider = document.getElementById('distance');
  const label = document.getElementById('distance-label');
  const redraw = () => {
    const distance = Math.pow(2, Number(slider.value));
    label.textContent = `${distance.toFixed(1)} radii`;
    techniques.forEach((technique, i) => {
      drawRaw(technique, distance);
      present(target, i * size);
    });
    drawThree(distance);
    renderer.render(presentScene, presentCamera);
  };
  slider.addEventListener('input', redraw);
  redraw();
}

main().catch(async (error) => {
  document.getElementById('status').textContent = String(error);
  if (capture) await fetch('/capture/done', { method: 'POST', body: JSON.stringify({ errors: [String(error.stack ?? error)] }) });
});
