// leanfade in WebGL2: LEAN maps and the exported GLSL ES 3.00 shaders (`leanfade shaders --lang
// glsl-es`) drawn with plain WebGL2 calls, everything set up from shaders.json. An engine takes
// what it needs: the KTX2 readers, the uploads, the uniform blocks written at the reflected
// offsets, the camera that `leanfade render` uses. docs/integration.md, "WebGL2 and three.js".
export {
  bottomRowFirst, LeanfadeError, parseLeanMap, parseTexture, plateauFromLeanMap, toHalf,
} from '../three/src/lean_map.js';
import { bottomRowFirst, LeanfadeError } from '../three/src/lean_map.js';

function setSampling(gl, target) {
  gl.texParameteri(target, gl.TEXTURE_MIN_FILTER, gl.LINEAR_MIPMAP_LINEAR);
  gl.texParameteri(target, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
  gl.texParameteri(target, gl.TEXTURE_WRAP_S, gl.REPEAT);
  gl.texParameteri(target, gl.TEXTURE_WRAP_T, gl.REPEAT);
}

// The LEAN map as the renderer uploads it: TEXTURE_2D_ARRAY, RGBA16F, every level, trilinear.
export function uploadLeanMap(gl, map) {
  const texture = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D_ARRAY, texture);
  gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
  gl.texStorage3D(gl.TEXTURE_2D_ARRAY, map.levels.length, gl.RGBA16F, map.width, map.height, 2);
  map.levels.forEach((level, i) =>
    gl.texSubImage3D(gl.TEXTURE_2D_ARRAY, i, 0, 0, 0, level.width, level.height, 2, gl.RGBA,
                     gl.HALF_FLOAT, bottomRowFirst(level, 2)));
  setSampling(gl, gl.TEXTURE_2D_ARRAY);
  return texture;
}

// A 2D texture of RGBA half floats (the plateau layer), uploaded like the LEAN map.
export function uploadTexture(gl, texture2d) {
  const texture = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, texture);
  gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
  gl.texStorage2D(gl.TEXTURE_2D, texture2d.levels.length, gl.RGBA16F, texture2d.width, texture2d.height);
  texture2d.levels.forEach((level, i) =>
    gl.texSubImage2D(gl.TEXTURE_2D, i, 0, 0, level.width, level.height, gl.RGBA, gl.HALF_FLOAT,
                     bottomRowFirst(level, 1)));
  setSampling(gl, gl.TEXTURE_2D);
  return texture;
}

// A 1 x 1 texture of `rgba` (half floats): the renderer's white base colour for a material without
// one, and a valid texture for declared samplers the material leaves unread.
export function uploadConstant(gl, rgba) {
  const texture = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, texture);
  gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA16F, 1, 1);
  gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, 1, 1, gl.RGBA, gl.FLOAT, new Float32Array(rgba));
  return texture;
}

// --- The mesh: leanfade's built-in sphere (scene::make_sphere), its vertices as the renderer
// uploads them: position, normal, uv, tangent (xyz, handedness w), uv1 (the second texture
// coordinate set, a copy of uv: the sphere has one), linear_normal_change (0: a sphere's normals
// are smooth, docs/math.md §11), 15 floats each.
export function makeSphere(segments = 32, stacks = 32) {
  const floatsPerVertex = 15;
  const positions = [];
  const normals = [];
  const uvs = [];
  const unitCircle = (f) => (f <= 0 || f >= 1 ? [1, 0] : [Math.cos(2 * Math.PI * f), Math.sin(2 * Math.PI * f)]);
  // A grid of (segments + 1) x (stacks + 1) vertices; the pole rows' copies sit in the middle of
  // the one triangle that uses each.
  for (let j = 0; j <= stacks; ++j) {
    for (let i = 0; i <= segments; ++i) {
      let s = i / segments;
      const t = j / stacks;
      if (j === 0) s = (i + 0.5) / segments;
      if (j === stacks) s = (i - 0.5) / segments;
      const lon = unitCircle(s);
      const polar = Math.PI * (1 - t);
      let y = Math.cos(polar);
      let ring = Math.sin(polar);
      if (t <= 0 || t >= 1) {
        y = t <= 0 ? -1 : 1;
        ring = 0;
      }
      const p = [ring * lon[1], y, ring * lon[0]];
      const length = Math.hypot(p[0], p[1], p[2]);
      positions.push(p);
      normals.push(p.map((c) => c / length));
      uvs.push([Math.fround(16 * s), Math.fround(8 * t)]);
    }
  }
  const row = segments + 1;
  const indices = [];
  for (let j = 0; j < stacks; ++j) {
    for (let i = 0; i < segments; ++i) {
      const a = j * row + i, b = a + 1, c = a + row + 1, d = a + row;
      if (j !== 0) indices.push(a, b, c);
      if (j + 1 !== stacks) indices.push(a, c, d);
    }
  }
  const f32 = (v) => v.map(Math.fround);
  const P = positions.map(f32), N = normals.map(f32);
  const tangents = tangentFrames(P, N, uvs, indices);
  const vertices = new Float32Array(P.length * floatsPerVertex);
  P.forEach((p, k) => vertices.set([...p, ...N[k], ...uvs[k], ...tangents[k], ...uvs[k], 0], k * floatsPerVertex));
  const used = new Set(indices);
  const min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
  for (const k of used) for (let c = 0; c < 3; ++c) {
    min[c] = Math.min(min[c], P[k][c]);
    max[c] = Math.max(max[c], P[k][c]);
  }
  return { vertices, indices: new Uint32Array(indices), floatsPerVertex, bounds: { min, max } };
}

// Per-vertex tangents as leanfade computes them (scene::generate_tangents): each triangle's
// dp/du and dp/dv weighted by its area, made orthogonal to the normal, w the handedness.
function tangentFrames(P, N, uv, indices) {
  const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const len = (a) => Math.sqrt(dot(a, a));
  const scale = (a, k) => [a[0] * k, a[1] * k, a[2] * k];
  const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
  const tan = P.map(() => [0, 0, 0]), bit = P.map(() => [0, 0, 0]);
  for (let t = 0; t < indices.length; t += 3) {
    const [i0, i1, i2] = [indices[t], indices[t + 1], indices[t + 2]];
    const e1 = sub(P[i1], P[i0]), e2 = sub(P[i2], P[i0]);
    const d1 = [uv[i1][0] - uv[i0][0], uv[i1][1] - uv[i0][1]];
    const d2 = [uv[i2][0] - uv[i0][0], uv[i2][1] - uv[i0][1]];
    const area = 0.5 * len(cross(e1, e2));
    const r = d1[0] * d2[1] - d2[0] * d1[1];
    if (!(area > 0) || !(Math.abs(r) > 1e-12 * Math.hypot(...d1) * Math.hypot(...d2))) continue;
    const dpdu = scale(sub(scale(e1, d2[1]), scale(e2, d1[1])), 1 / r);
    const dpdv = scale(sub(scale(e2, d1[0]), scale(e1, d2[0])), 1 / r);
    const lu = len(dpdu), lv = len(dpdv);
    if (!(lu > 0) || !(lv > 0) || !Number.isFinite(lu) || !Number.isFinite(lv)) continue;
    for (const k of [i0, i1, i2]) {
      tan[k] = add(tan[k], scale(dpdu, area / lu));
      bit[k] = add(bit[k], scale(dpdv, area / lv));
    }
  }
  return P.map((_, k) => {
    const nn = scale(N[k], 1 / len(N[k]));
    const tp = sub(tan[k], scale(nn, dot(nn, tan[k])));
    const bp = sub(bit[k], scale(nn, dot(nn, bit[k])));
    const tl = len(tp), bl = len(bp);
    if (tl > 1e-6 * len(tan[k]) && tl > 0) {
      const tangent = scale(tp, 1 / tl);
      return [...tangent, dot(cross(nn, tangent), bit[k]) < 0 ? -1 : 1];
    }
    if (bl > 1e-6 * len(bit[k]) && bl > 0) {
      const c = cross(scale(bp, 1 / bl), nn);
      return [...scale(c, 1 / len(c)), 1];
    }
    // Degenerate (unused pole copies): any unit vector orthogonal to the normal.
    const other = Math.abs(nn[0]) < 0.9 ? [1, 0, 0] : [0, 1, 0];
    const c = cross(nn, other);
    return [...scale(c, 1 / len(c)), 1];
  });
}

// --- Matrices (column-major Float32Array(16), glm's conventions: right-handed, OpenGL clip
// space with depth -1..1).
export const mat4 = {
  multiply(a, b) {
    const out = new Float32Array(16);
    for (let c = 0; c < 4; ++c)
      for (let r = 0; r < 4; ++r) {
        let sum = 0;
        for (let k = 0; k < 4; ++k) sum += a[k * 4 + r] * b[c * 4 + k];
        out[c * 4 + r] = sum;
      }
    return out;
  },
  perspective(fovYRadians, aspect, near, far) {
    const f = 1 / Math.tan(fovYRadians / 2);
    const out = new Float32Array(16);
    out[0] = f / aspect;
    out[5] = f;
    out[10] = -(far + near) / (far - near);
    out[11] = -1;
    out[14] = -(2 * far * near) / (far - near);
    return out;
  },
  lookAt(eye, target, up) {
    const norm = (v) => { const l = Math.hypot(...v); return v.map((c) => c / l); };
    const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    const f = norm([target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]]);
    const s = norm(cross(f, up));
    const u = cross(s, f);
    return new Float32Array([s[0], u[0], -f[0], 0, s[1], u[1], -f[1], 0, s[2], u[2], -f[2], 0,
                             -dot(s, eye), -dot(u, eye), dot(f, eye), 1]);
  },
  // The object scaled by 1 / its bounding radius about its box's centre.
  fitToUnitSphere(bounds) {
    const centre = [0, 1, 2].map((c) => 0.5 * (bounds.min[c] + bounds.max[c]));
    const radius = 0.5 * Math.hypot(...[0, 1, 2].map((c) => bounds.max[c] - bounds.min[c]));
    const k = 1 / radius;
    return new Float32Array([k, 0, 0, 0, 0, k, 0, 0, 0, 0, k, 0, -k * centre[0], -k * centre[1], -k * centre[2], 1]);
  },
};

// The camera of `leanfade render --distances d` (shaders.json's defaults.camera): the eye d
// bounding radii from the centre along the view direction, near and far planes enclosing the
// unit sphere.
export function viewAtDistance(distance, camera) {
  const direction = camera.view_direction;
  const length = Math.hypot(...direction);
  const unit = direction.map((c) => c / length);
  const eye = unit.map((c, i) => camera.target[i] + c * distance);
  const up = Math.abs(unit[1]) > 0.9999 ? [0, 0, -1] : [0, 1, 0];
  const near = Math.max(0.01, 0.9 * (distance - 1));
  const far = 1.1 * (distance + 1);
  return {
    eye,
    up,
    target: camera.target,
    fovYDegrees: camera.fov_y_degrees,
    near,
    far,
    view: mat4.lookAt(eye, camera.target, up),
    projection: (aspect) => mat4.perspective((camera.fov_y_degrees * Math.PI) / 180, aspect, near, far),
  };
}

// --- Uniform blocks: the bytes of a block written at the offsets of its reflection.
export class UniformBlock {
  constructor(resource) {
    this.name = resource.name;
    this.binding = resource.binding;
    this.members = new Map(resource.members.map((m) => [m.name.replace(/\[0\]$/, ''), m]));
    this.bytes = new ArrayBuffer(Math.ceil(resource.block_size / 16) * 16);
    this.view = new DataView(this.bytes);
  }

  has(name) {
    return this.members.has(name);
  }

  // Sets member `name` (as the reflection names it) to `value`: a number, or an array (a matrix
  // column by column; mat3 columns are padded to 16 bytes by std140, matrix_stride).
  set(name, value) {
    const m = this.members.get(name);
    if (m === undefined) throw new LeanfadeError(this.name, `has no member ${name}`);
    const values = typeof value === 'number' ? [value] : Array.from(value);
    const isInt = m.type === 'int' || m.type === 'bool';
    const rows = { mat3: 3, mat4: 4 }[m.type];
    values.forEach((v, i) => {
      const at = rows ? m.offset + Math.floor(i / rows) * m.matrix_stride + (i % rows) * 4 : m.offset + i * 4;
      if (isInt) this.view.setInt32(at, v, true);
      else this.view.setFloat32(at, v, true);
    });
  }

  // The defaults of `leanfade render` (shaders.json's defaults.blocks[name]).
  setDefaults(defaults) {
    for (const d of defaults[this.name] ?? []) if (this.has(d.name)) this.set(d.name, d.value);
  }
}

// The object block of a draw: the transforms of `model` (object -> world) seen by `camera` (a
// viewAtDistance), for a viewport of `aspect`.
export function objectBlockValues(model, camera, aspect) {
  // The normal matrix transpose(inverse(mat3(model))): for columns a, b, c of mat3(model), its
  // columns are (b x c, c x a, a x b) / det.
  const cross = (u, v) => [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
  const a = [model[0], model[1], model[2]], b = [model[4], model[5], model[6]], c = [model[8], model[9], model[10]];
  const bc = cross(b, c), ca = cross(c, a), ab = cross(a, b);
  const det = a[0] * bc[0] + a[1] * bc[1] + a[2] * bc[2];
  const normalMatrix = [...bc, ...ca, ...ab].map((v) => v / det);
  return {
    u_model: model,
    u_view: camera.view,
    u_clip: mat4.multiply(camera.projection(aspect), camera.view),
    u_normal_matrix: normalMatrix,
    u_eye_world: camera.eye,
  };
}

// --- Programs and drawing.

// shaders.json and the sources of the variants `variants` names (and the vertex stage), of
// `leanfade shaders --lang LANGUAGE` (glsl-es here; wgsl for WebGPU, leanfade_webgpu.js).
export async function loadShaders(baseUrl, variants, language = 'glsl-es') {
  const index = await (await fetch(`${baseUrl}/shaders.json`)).json();
  if (index.language !== language)
    throw new LeanfadeError(`${baseUrl}/shaders.json`, `is ${index.language}, not ${language} (leanfade shaders --lang ${language})`);
  const entry = (variant, stage) => {
    const e = index.shaders.find((s) => s.variant === variant && s.stage === stage);
    if (e === undefined) throw new LeanfadeError(`${baseUrl}/shaders.json`, `has no ${stage} stage of ${variant}`);
    if (e.omitted) throw new LeanfadeError(`${baseUrl}/shaders.json`, `${variant}: ${e.omitted}`);
    return e;
  };
  const vertex = index.shaders.find((s) => s.stage === 'vert');
  const sources = new Map();
  for (const e of [vertex, ...variants.map((v) => entry(v, 'frag'))])
    sources.set(e.file, await (await fetch(`${baseUrl}/${e.file}`)).text());
  return { index, vertex, entry, sources };
}

function compile(gl, type, source, name) {
  const shader = gl.createShader(type);
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS))
    throw new LeanfadeError(name, gl.getShaderInfoLog(shader));
  return shader;
}

// A program of the vertex stage and the fragment variant `fragment` (shaders.json entries), its
// samplers on their units and its blocks on their bindings as the reflection gives them (GLSL ES
// 3.00 has no layout bindings), and its vertex inputs at the reflected locations.
export function createProgram(gl, shaders, fragment) {
  const vertex = shaders.vertex;
  const program = gl.createProgram();
  gl.attachShader(program, compile(gl, gl.VERTEX_SHADER, shaders.sources.get(vertex.file), vertex.file));
  gl.attachShader(program, compile(gl, gl.FRAGMENT_SHADER, shaders.sources.get(fragment.file), fragment.file));
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS))
    throw new LeanfadeError(fragment.file, gl.getProgramInfoLog(program));
  gl.useProgram(program);
  const blocks = new Map();
  for (const stage of [vertex, fragment])
    for (const r of stage.reflection.resources) {
      if (r.descriptor_type === 'uniform_buffer') {
        gl.uniformBlockBinding(program, gl.getUniformBlockIndex(program, r.name), r.binding);
        blocks.set(r.name, new UniformBlock(r));
      } else {
        gl.uniform1i(gl.getUniformLocation(program, r.name), r.binding);
      }
    }
  const samplers = fragment.reflection.resources.filter((r) => r.descriptor_type !== 'uniform_buffer');
  return { program, blocks, samplers, inputs: vertex.reflection.inputs };
}

// A vertex array of `mesh` (makeSphere) for the vertex stage's reflected inputs.
export function createVertexArray(gl, mesh, inputs) {
  const vao = gl.createVertexArray();
  gl.bindVertexArray(vao);
  const buffer = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
  gl.bufferData(gl.ARRAY_BUFFER, mesh.vertices, gl.STATIC_DRAW);
  const offsets = { a_position: 0, a_normal: 3, a_uv: 6, a_tangent: 8, a_uv1: 12, a_linear_normal_change: 14 };
  const sizes = { float: 1, vec2: 2, vec3: 3, vec4: 4 };
  for (const input of inputs) {
    if (!(input.name in offsets)) throw new LeanfadeError('vertex stage', `unknown input ${input.name}`);
    gl.enableVertexAttribArray(input.location);
    gl.vertexAttribPointer(input.location, sizes[input.type], gl.FLOAT, false, mesh.floatsPerVertex * 4, offsets[input.name] * 4);
  }
  const indices = gl.createBuffer();
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, indices);
  gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, mesh.indices, gl.STATIC_DRAW);
  gl.bindVertexArray(null);
  return { vao, count: mesh.indices.length };
}

// What a scene of one object keeps of its shaders and LEAN map, in any API: the render defaults,
// the model transform of `leanfade render` and how the map's moments are encoded.
export function sceneBasics(shaders, leanMap, mesh) {
  return {
    shaders,
    defaults: shaders.index.defaults,
    model: mat4.fitToUnitSphere(mesh.bounds),
    scale: leanMap.scale,
    leanOffset: leanMap.leanOffset,
    roughnessBaked: leanMap.roughnessBaked,
  };
}

// A uniform block of one draw: the render defaults, then the object block's transforms `values`
// (objectBlockValues) or the shading block's map encoding (`scene`: sceneBasics) and map bits.
export function fillBlock(block, scene, values, maps) {
  block.setDefaults(scene.defaults.blocks);
  if (block.name === 'LfObjectBlock') for (const [name, v] of Object.entries(values)) block.set(name, v);
  if (block.name === 'LfShadingBlock') {
    block.set('u_shading.scale', scene.scale);
    block.set('u_shading.lean_offset', scene.leanOffset);
    // A map with 1/s baked into its moments: none added again at shading time.
    if (scene.roughnessBaked) block.set('u_shading.params.inv_s_shading', 0);
    block.set('u_shading.maps', maps);
  }
}

// A parsed texture (parseTexture, or a LEAN map's `plateau`) that is two-lobe LEAN's plateau layer.
export function checkPlateau(plateau) {
  if (plateau.content !== 'plateau v1')
    throw new LeanfadeError('plateau layer', `holds ${plateau.content ?? 'no LEANFADEcontent'}, not the plateau layer`);
}

// Draws leanfade's scenes of one object with the exported variants: a LEAN map (and the plateau
// layer two-lobe reads) on the sphere, each technique's program set up once.
export class LeanfadeScene {
  constructor(gl, shaders, { leanMap, plateau, mesh = makeSphere() }) {
    this.gl = gl;
    this.mesh = mesh;
    Object.assign(this, sceneBasics(shaders, leanMap, mesh));
    this.textures = {
      u_lean: { target: gl.TEXTURE_2D_ARRAY, texture: uploadLeanMap(gl, leanMap) },
      u_base_color: { target: gl.TEXTURE_2D, texture: uploadConstant(gl, [1, 1, 1, 1]) },
      u_base_roughness: { target: gl.TEXTURE_2D, texture: uploadConstant(gl, [1, 1, 1, 1]) },
    };
    this.mapBits = 0;
    if (plateau) {
      checkPlateau(plateau);
      this.textures.u_plateau = { target: gl.TEXTURE_2D, texture: uploadTexture(gl, plateau) };
      this.plateauBit = 4;  // LF_MAP_PLATEAU of shaders/map_kinds.glsl
    }
    this.programs = new Map();
    this.buffers = new Map();
  }

  // The technique's program (the variant `leanfade render` draws it with).
  program(technique) {
    if (!this.programs.has(technique)) {
      const variant = this.defaults.variants[technique];
      const p = createProgram(this.gl, this.shaders, this.shaders.entry(variant, 'frag'));
      p.vertexArray = createVertexArray(this.gl, this.mesh, p.inputs);
      this.programs.set(technique, p);
    }
    return this.programs.get(technique);
  }

  uniformBuffer(binding) {
    const gl = this.gl;
    if (!this.buffers.has(binding)) this.buffers.set(binding, gl.createBuffer());
    return this.buffers.get(binding);
  }

  // Draws `technique` at `distance` bounding radii into the bound framebuffer's `viewport`
  // ([x, y, width, height]), as `leanfade render --techniques T --distances D` does.
  draw(technique, distance, viewport) {
    const gl = this.gl;
    const p = this.program(technique);
    const camera = viewAtDistance(distance, this.defaults.camera);
    gl.useProgram(p.program);
    const values = objectBlockValues(this.model, camera, viewport[2] / viewport[3]);
    let maps = 0;
    for (const sampler of p.samplers) if (sampler.name === 'u_plateau' && this.textures.u_plateau) maps |= this.plateauBit;
    for (const block of p.blocks.values()) {
      fillBlock(block, this, values, maps);
      const buffer = this.uniformBuffer(block.binding);
      gl.bindBuffer(gl.UNIFORM_BUFFER, buffer);
      gl.bufferData(gl.UNIFORM_BUFFER, block.bytes, gl.DYNAMIC_DRAW);
      gl.bindBufferBase(gl.UNIFORM_BUFFER, block.binding, buffer);
    }
    for (const sampler of p.samplers) {
      const t = this.textures[sampler.name] ?? this.textures.u_base_roughness;
      gl.activeTexture(gl.TEXTURE0 + sampler.binding);
      gl.bindTexture(t.target, t.texture);
    }
    gl.viewport(...viewport);
    gl.enable(gl.DEPTH_TEST);
    gl.enable(gl.CULL_FACE);
    gl.cullFace(gl.BACK);
    gl.frontFace(gl.CCW);
    gl.bindVertexArray(p.vertexArray.vao);
    gl.drawElements(gl.TRIANGLES, p.vertexArray.count, gl.UNSIGNED_INT, 0);
    gl.bindVertexArray(null);
  }
}

// A float render target of `width` x `height` with a depth buffer (EXT_color_buffer_float), where
// the scenes draw linear radiance as `leanfade render` does before its sRGB encoding.
export function createFloatTarget(gl, width, height) {
  if (!gl.getExtension('EXT_color_buffer_float'))
    throw new LeanfadeError('WebGL2', 'EXT_color_buffer_float is missing: no float render target');
  const framebuffer = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
  const color = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, color);
  gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, width, height);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, color, 0);
  const depth = gl.createRenderbuffer();
  gl.bindRenderbuffer(gl.RENDERBUFFER, depth);
  gl.renderbufferStorage(gl.RENDERBUFFER, gl.DEPTH_COMPONENT24, width, height);
  gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.DEPTH_ATTACHMENT, gl.RENDERBUFFER, depth);
  if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE)
    throw new LeanfadeError('WebGL2', 'the float render target is incomplete');
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  return { framebuffer, color, width, height };
}

// The linear RGBA floats of a target's region, rows bottom first (readPixels).
export function readFloats(gl, target, [x, y, width, height]) {
  gl.bindFramebuffer(gl.FRAMEBUFFER, target.framebuffer);
  const pixels = new Float32Array(width * height * 4);
  gl.readPixels(x, y, width, height, gl.RGBA, gl.FLOAT, pixels);
  gl.bindFramebuffer(gl.FRAMEBUFFER, null);
  return pixels;
}
