// leanfade's LEAN maps drawn with WebGPU and the WGSL of `leanfade shaders --lang wgsl`: the
// textures, samplers and uniform blocks bound where shaders.json's reflection says, the vertex
// layout of shaders.json, the camera of `leanfade render`. The KTX2 reading, the mesh, the
// camera and the uniform-block bytes are those of the WebGL2 module (leanfade_webgl.js).
import {
  bottomRowFirst, checkPlateau, fillBlock, LeanfadeError, loadShaders, makeSphere,
  objectBlockValues, sceneBasics, toHalf, UniformBlock, viewAtDistance,
} from './leanfade_webgl.js';

// shaders.json's vertex attribute formats (Vulkan names) as WebGPU vertex formats.
const kVertexFormats = {
  R32_SFLOAT: 'float32', R32G32_SFLOAT: 'float32x2', R32G32B32_SFLOAT: 'float32x3', R32G32B32A32_SFLOAT: 'float32x4',
};

// shaders.json of `leanfade shaders --lang wgsl` and the WGSL of the variants `variants` names
// (and the vertex stage).
export function loadWgslShaders(baseUrl, variants) {
  return loadShaders(baseUrl, variants, 'wgsl');
}

// The LEAN map as the renderer uploads it: a 2D array of two layers, rgba16float, every level,
// rows bottom first (+v up). `map` is parseLeanMap's (leanfade_webgl.js).
export function uploadLeanMap(device, map) {
  return uploadHalfFloatLevels(device, map, 2);
}

// A 2D texture of RGBA half floats with its levels (parseTexture's: the plateau layer).
export function uploadTexture(device, texture2d) {
  return uploadHalfFloatLevels(device, texture2d, 1);
}

function uploadHalfFloatLevels(device, map, layers) {
  const texture = device.createTexture({
    size: [map.width, map.height, layers],
    mipLevelCount: map.levels.length,
    format: 'rgba16float',
    usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST,
  });
  map.levels.forEach((level, i) => {
    device.queue.writeTexture({ texture, mipLevel: i }, bottomRowFirst(level, layers),
                              { bytesPerRow: level.width * 8, rowsPerImage: level.height },
                              [level.width, level.height, layers]);
  });
  return texture;
}

// A 1 x 1 texture of `rgba`: the white base colour of a material without one, and a valid texture
// for a declared map the material leaves unread (shaders.json's maps[].when_absent).
// Half floats, as the filterable rgba16float format takes them (rgba32float is not filterable).
export function uploadConstant(device, rgba) {
  const texture = device.createTexture({
    size: [1, 1, 1], format: 'rgba16float',
    usage: GPUTextureUsage.TEXTURE_BINDING | GPUTextureUsage.COPY_DST,
  });
  device.queue.writeTexture({ texture }, new Uint16Array(rgba.map(toHalf)), { bytesPerRow: 8 }, [1, 1, 1]);
  return texture;
}


// A render pipeline of the vertex stage and the fragment variant `fragment` (shaders.json
// entries) drawing into `colorFormat` with depth. The layout is the shaders' own ('auto'): the
// bind group takes exactly the resources their reflection lists.
export async function createPipeline(device, shaders, fragment, colorFormat) {
  const vertex = shaders.vertex;
  const module = async (entry) => {
    const m = device.createShaderModule({ label: entry.file, code: shaders.sources.get(entry.file) });
    const info = await m.getCompilationInfo();
    const errors = info.messages.filter((msg) => msg.type === 'error');
    if (errors.length) throw new LeanfadeError(entry.file, errors.map((e) => `${e.lineNum}:${e.linePos} ${e.message}`).join('; '));
    return m;
  };
  const layout = shaders.index.vertex_layout;
  const attributes = vertex.reflection.inputs.map((input) => {
    const a = layout.attributes.find((x) => x.location === input.location);
    if (!a) throw new LeanfadeError(vertex.file, `input ${input.name} has no attribute in shaders.json's vertex_layout`);
    return { shaderLocation: input.location, offset: a.offset, format: kVertexFormats[input.format] };
  });
  device.pushErrorScope('validation');
  const pipeline = device.createRenderPipeline({
    label: fragment.variant,
    layout: 'auto',
    vertex: {
      module: await module(vertex), entryPoint: vertex.reflection.entry_point,
      buffers: [{ arrayStride: layout.stride, attributes }],
    },
    fragment: {
      module: await module(fragment), entryPoint: fragment.reflection.entry_point,
      targets: [{ format: colorFormat }],
    },
    primitive: { topology: 'triangle-list', frontFace: 'ccw', cullMode: 'back' },
    depthStencil: { format: 'depth24plus', depthWriteEnabled: true, depthCompare: 'less' },
  });
  const error = await device.popErrorScope();
  if (error) throw new LeanfadeError(fragment.file, error.message);
  return { pipeline, resources: [...vertex.reflection.resources, ...fragment.reflection.resources] };
}

// Draws leanfade's scenes of one object with the exported WGSL variants: a LEAN map (and the
// plateau layer two-lobe reads) on the sphere, each technique's pipeline made once.
export class LeanfadeWebGpuScene {
  constructor(device, shaders, { leanMap, plateau, mesh = makeSphere(), colorFormat = 'rgba32float' }) {
    this.device = device;
    this.colorFormat = colorFormat;
    Object.assign(this, sceneBasics(shaders, leanMap, mesh));
    const lean = uploadLeanMap(device, leanMap);
    const white = uploadConstant(device, [1, 1, 1, 1]);
    this.views = {
      u_lean: lean.createView({ dimension: '2d-array' }),
      u_base_color: white.createView(),
    };
    this.fallbackView = this.views.u_base_color;
    if (plateau) {
      checkPlateau(plateau);
      this.views.u_plateau = uploadTexture(device, plateau).createView();
    }
    // The bit of each map by its texture's binding (shaders.json's maps[]).
    this.mapBits = new Map(shaders.index.maps.map((m) => [m.binding, m.maps_bit]));
    // The renderer's sampling: trilinear, repeating, every level.
    this.sampler = device.createSampler({
      magFilter: 'linear', minFilter: 'linear', mipmapFilter: 'linear',
      addressModeU: 'repeat', addressModeV: 'repeat',
    });
    this.vertices = device.createBuffer({ size: mesh.vertices.byteLength, usage: GPUBufferUsage.VERTEX | GPUBufferUsage.COPY_DST });
    device.queue.writeBuffer(this.vertices, 0, mesh.vertices);
    this.indices = device.createBuffer({ size: mesh.indices.byteLength, usage: GPUBufferUsage.INDEX | GPUBufferUsage.COPY_DST });
    device.queue.writeBuffer(this.indices, 0, mesh.indices);
    this.indexCount = mesh.indices.length;
    this.pipelines = new Map();
  }

  async pipeline(technique) {
    if (!this.pipelines.has(technique)) {
      const variant = this.defaults.variants[technique];
      this.pipelines.set(technique, await createPipeline(this.device, this.shaders, this.shaders.entry(variant, 'frag'), this.colorFormat));
    }
    return this.pipelines.get(technique);
  }

  // The bind group of one draw: each resource of the reflection at its binding. A sampler is named
  // <texture>_sampler; a map the scene lacks gets the white texture, its bit left 0.
  bindGroup(p, blocks) {
    const entries = [];
    const seen = new Set();
    for (const r of p.resources) {
      if (seen.has(r.binding)) continue;
      seen.add(r.binding);
      if (r.descriptor_type === 'uniform_buffer') {
        const block = blocks.get(r.name);
        const buffer = this.device.createBuffer({ size: block.bytes.byteLength, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
        this.device.queue.writeBuffer(buffer, 0, block.bytes);
        entries.push({ binding: r.binding, resource: { buffer } });
      } else if (r.descriptor_type === 'sampler') {
        entries.push({ binding: r.binding, resource: this.sampler });
      } else {
        entries.push({ binding: r.binding, resource: this.views[r.name] ?? this.fallbackView });
      }
    }
    return this.device.createBindGroup({ layout: p.pipeline.getBindGroupLayout(0), entries });
  }

  // Draws `technique` at `distance` bounding radii into `target` (createTarget), as
  // `leanfade render --techniques T --distances D` does: the same matrices as OpenGL (the WGSL
  // vertex stage maps its clip space to WebGPU's).
  async draw(technique, distance, target) {
    const p = await this.pipeline(technique);
    const camera = viewAtDistance(distance, this.defaults.camera);
    const values = objectBlockValues(this.model, camera, target.width / target.height);
    const blocks = new Map();
    let maps = 0;
    // The plateau layer's bit when the variant reads it and the scene has it (the white base
    // colour stands for none: its bit stays 0).
    for (const r of p.resources)
      if (r.name === 'u_plateau' && this.views.u_plateau) maps |= this.mapBits.get(r.binding) ?? 0;
    for (const r of p.resources) {
      if (r.descriptor_type !== 'uniform_buffer' || blocks.has(r.name)) continue;
      const block = new UniformBlock(r);
      fillBlock(block, this, values, maps);
      blocks.set(block.name, block);
    }
    const background = this.defaults.camera.background;
    const encoder = this.device.createCommandEncoder();
    const pass = encoder.beginRenderPass({
      colorAttachments: [{
        view: target.color.createView(), loadOp: 'clear', storeOp: 'store',
        clearValue: { r: background[0], g: background[1], b: background[2], a: 1 },
      }],
      depthStencilAttachment: { view: target.depth.createView(), depthLoadOp: 'clear', depthClearValue: 1, depthStoreOp: 'store' },
    });
    pass.setPipeline(p.pipeline);
    pass.setBindGroup(0, this.bindGroup(p, blocks));
    pass.setVertexBuffer(0, this.vertices);
    pass.setIndexBuffer(this.indices, 'uint32');
    pass.drawIndexed(this.indexCount);
    pass.end();
    this.device.queue.submit([encoder.finish()]);
  }
}

// A float colour target with depth, where the scenes draw linear radiance as `leanfade render`
// does before its sRGB encoding.
export function createTarget(device, width, height, format = 'rgba32float') {
  const color = device.createTexture({
    size: [width, height], format,
    usage: GPUTextureUsage.RENDER_ATTACHMENT | GPUTextureUsage.COPY_SRC | GPUTextureUsage.TEXTURE_BINDING,
  });
  const depth = device.createTexture({ size: [width, height], format: 'depth24plus', usage: GPUTextureUsage.RENDER_ATTACHMENT });
  return { color, depth, width, height };
}

// The target's linear RGBA floats, rows bottom first (as WebGL2's readPixels gives them).
export async function readFloats(device, target) {
  const bytesPerRow = Math.ceil((target.width * 16) / 256) * 256;
  const buffer = device.createBuffer({ size: bytesPerRow * target.height, usage: GPUBufferUsage.COPY_DST | GPUBufferUsage.MAP_READ });
  const encoder = device.createCommandEncoder();
  encoder.copyTextureToBuffer({ texture: target.color }, { buffer, bytesPerRow }, [target.width, target.height]);
  device.queue.submit([encoder.finish()]);
  await buffer.mapAsync(GPUMapMode.READ);
  const rows = new Float32Array(buffer.getMappedRange());
  const stride = bytesPerRow / 4;
  const out = new Float32Array(target.width * target.height * 4);
  for (let y = 0; y < target.height; ++y)
    out.set(rows.subarray(y * stride, y * stride + target.width * 4), (target.height - 1 - y) * target.width * 4);
  buffer.unmap();
  return out;
}
