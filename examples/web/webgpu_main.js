// The WebGPU page: bump | LEAN | two-lobe drawn with the WGSL of `leanfade shaders --lang wgsl`
// at the distance the slider sets. With ?capture=CELLS it draws each cell ("technique@distance")
// once, posts its linear floats to the server (serve.mjs --capture) and reports when done: the
// suite's WebGPU test.
import { parseLeanMap, parseTexture } from './leanfade_webgl.js';
import { fetchBytes, pageParams } from './page.js';
import { createTarget, LeanfadeWebGpuScene, loadWgslShaders, readFloats } from './leanfade_webgpu.js';

const { dataUrl, mapName, size, capture } = pageParams();
const techniques = ['bump', 'lean', 'two-lobe'];


// Linear radiance of a float target to sRGB in the canvas, as `leanfade render` encodes figures.
const PRESENT = `
@group(0) @binding(0) var linear: texture_2d<f32>;
@vertex fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
  let p = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
  return vec4<f32>(p * 2.0 - 1.0, 0.0, 1.0);
}
@fragment fn fs(@builtin(position) at: vec4<f32>) -> @location(0) vec4<f32> {
  let size = textureDimensions(linear);
  let p = vec2<i32>(i32(at.x) % i32(size.x), i32(at.y));
  let c = clamp(textureLoad(linear, p, 0).rgb, vec3<f32>(0.0), vec3<f32>(1.0));
  let srgb = select(1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055, c * 12.92, c <= vec3<f32>(0.0031308));
  return vec4<f32>(srgb, 1.0);
}`;

async function main() {
  if (!navigator.gpu) throw new Error('this browser has no WebGPU');
  const adapter = await navigator.gpu.requestAdapter();
  if (!adapter) throw new Error('WebGPU has no adapter');
  const device = await adapter.requestDevice();
  const errors = [];
  device.addEventListener('uncapturederror', (e) => errors.push(e.error.message));
  const leanMap = await parseLeanMap(await fetchBytes(`${dataUrl}/${mapName}.ktx2`), `${mapName}.ktx2`);
  const plateau = await parseTexture(await fetchBytes(`${dataUrl}/${mapName}.plateau.ktx2`), `${mapName}.plateau.ktx2`);
  const index = await (await fetch(`${dataUrl}/wgsl/shaders.json`)).json();
  const shaders = await loadWgslShaders(`${dataUrl}/wgsl`, techniques.map((t) => index.defaults.variants[t]));
  const scene = new LeanfadeWebGpuScene(device, shaders, { leanMap, plateau });
  const target = createTarget(device, size, size);

  if (capture) {
    for (const cell of capture.split(',')) {
      const [technique, distanceText] = cell.split('@');
      await scene.draw(technique, Number(distanceText), target);
      const pixels = await readFloats(device, target);
      await fetch(`/capture/${technique}_d${distanceText}.f32`, { method: 'POST', body: pixels });
    }
    const info = adapter.info ?? {};
    const renderer = [info.vendor, info.architecture, info.description].filter(Boolean).join(' ');
    await fetch('/capture/done', { method: 'POST', body: JSON.stringify({ errors, renderer, size }) });
    return;
  }

  const canvas = document.getElementById('views');
  canvas.width = size * techniques.length;
  canvas.height = size;
  document.querySelector('.labels').style.width = `${canvas.width}px`;
  const context = canvas.getContext('webgpu');
  const format = navigator.gpu.getPreferredCanvasFormat();
  context.configure({ device, format });
  const module = device.createShaderModule({ code: PRESENT });
  const present = device.createRenderPipeline({
    layout: 'auto', vertex: { module, entryPoint: 'vs' }, fragment: { module, entryPoint: 'fs', targets: [{ format }] },
  });
  const cells = techniques.map(() => createTarget(device, size, size));
  const slider = document.getElementById('distance');
  const label = document.getElementById('distance-label');
  const redraw = async () => {
    const distance = Math.pow(2, Number(slider.value));
    label.textContent = `${distance.toFixed(1)} radii`;
    for (let i = 0; i < techniques.length; ++i) await scene.draw(techniques[i], distance, cells[i]);
    const encoder = device.createCommandEncoder();
    const pass = encoder.beginRenderPass({
      colorAttachments: [{ view: context.getCurrentTexture().createView(), loadOp: 'clear', storeOp: 'store' }],
    });
    pass.setPipeline(present);
    cells.forEach((cell, i) => {
      pass.setViewport(i * size, 0, size, size, 0, 1);
      pass.setBindGroup(0, device.createBindGroup({
        layout: present.getBindGroupLayout(0), entries: [{ binding: 0, resource: cell.color.createView() }],
      }));
      pass.draw(3);
    });
    pass.end();
    device.queue.submit([encoder.finish()]);
  };
  slider.addEventListener('input', redraw);
  await redraw();
}

main().catch(async (error) => {
  document.getElementById('status').textContent = String(error);
  if (capture) await fetch('/capture/done', { method: 'POST', body: JSON.stringify({ errors: [String(error.stack ?? error)] }) });
});
