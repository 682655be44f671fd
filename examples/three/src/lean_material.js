// leanfade's own shading in three.js's WebGLRenderer: a RawShaderMaterial of the exported GLSL ES
// 3.00 vertex stage and one fragment variant (`leanfade shaders --lang glsl-es`), the LEAN map
// (and the plateau layer two-lobe reads) with every level leanfade baked, and the two uniform
// blocks as three.js UniformsGroups built from shaders.json's reflection. It draws what
// `leanfade render` draws, lit by the scene's first DirectionalLight.
import * as THREE from 'three';

import { LeanfadeError } from './lean_map.js';
import { halfFloatTexture, leanMapTexture } from './textures.js';

// The BufferGeometry of a leanfade mesh (makeSphere): the vertex stage's inputs by their names.
export function meshGeometry(mesh) {
  const geometry = new THREE.BufferGeometry();
  const interleaved = new THREE.InterleavedBuffer(mesh.vertices, mesh.floatsPerVertex);
  geometry.setAttribute('a_position', new THREE.InterleavedBufferAttribute(interleaved, 3, 0));
  geometry.setAttribute('a_normal', new THREE.InterleavedBufferAttribute(interleaved, 3, 3));
  geometry.setAttribute('a_uv', new THREE.InterleavedBufferAttribute(interleaved, 2, 6));
  geometry.setAttribute('a_tangent', new THREE.InterleavedBufferAttribute(interleaved, 4, 8));
  geometry.setAttribute('a_uv1', new THREE.InterleavedBufferAttribute(interleaved, 2, 12));
  geometry.setAttribute('a_linear_normal_change', new THREE.InterleavedBufferAttribute(interleaved, 1, 14));
  geometry.setIndex(new THREE.BufferAttribute(mesh.indices, 1));
  return geometry;
}

// A three.js value of a reflected block member (numbers for int and float; an array member, a list
// of its elements' values).
function memberValue(member) {
  if (member.array_size > 0)
    return Array.from({ length: member.array_size }, () => memberValue({ ...member, array_size: 0 }));
  switch (member.type) {
    case 'mat4': return new THREE.Matrix4();
    case 'mat3': return new THREE.Matrix3();
    case 'vec4': return new THREE.Vector4();
    case 'vec3': return new THREE.Vector3();
    case 'vec2': return new THREE.Vector2();
    case 'float': case 'int': return 0;
    default: throw new LeanfadeError('three.js material', `block member ${member.name} of type ${member.type}`);
  }
}

// A number, or a list of numbers (vectors component by component, matrices column by column, an
// array element by element).
function assign(uniform, value) {
  if (typeof uniform.value === 'number') uniform.value = value;
  else if (Array.isArray(uniform.value)) {
    const n = value.length / uniform.value.length;
    uniform.value.forEach((element, i) => element.fromArray(value.slice(i * n, (i + 1) * n)));
  } else uniform.value.fromArray(value);
}

// One UniformsGroup per uniform block, its uniforms in the reflection's order (std140 gives
// three.js's layout the reflected offsets; checkBlockOffsets verifies it after the first draw).
function uniformsGroup(resource, defaults) {
  const group = new THREE.UniformsGroup();
  group.setName(resource.name);
  const uniforms = new Map();
  for (const member of [...resource.members].sort((a, b) => a.offset - b.offset)) {
    const uniform = new THREE.Uniform(memberValue(member));
    if (member.type === 'int') uniform.type = 'int';
    group.add(uniform);
    uniforms.set(member.name, { uniform, member });
  }
  for (const d of defaults[resource.name] ?? []) if (uniforms.has(d.name)) assign(uniforms.get(d.name).uniform, d.value);
  return { group, uniforms };
}

// The material of `variant` (a name in shaders.json, e.g. defaults.variants.lean) for the LEAN map
// `map` (parseLeanMap) and, for two-lobe, the plateau layer `plateau` (parseTexture, or the map's
// own: map.plateau).
export class LeanMaterial extends THREE.RawShaderMaterial {
  constructor(shaders, variant, map, plateau = map.plateau ?? null) {
    const fragment = shaders.entry(variant, 'frag');
    const vertex = shaders.vertex;
    // three.js writes the #version line of GLSL3 materials itself.
    const body = (file) => shaders.sources.get(file).replace(/^#version 300 es\s*\n/, '');
    const white = new THREE.DataTexture(new Uint16Array([15360, 15360, 15360, 15360]), 1, 1,
                                        THREE.RGBAFormat, THREE.HalfFloatType);
    white.needsUpdate = true;
    const textures = {
      u_lean: leanMapTexture(map),
      u_base_color: white,
      u_base_roughness: white,
    };
    if (plateau) textures.u_plateau = halfFloatTexture(plateau);
    const uniforms = {};
    for (const r of fragment.reflection.resources)
      if (r.descriptor_type !== 'uniform_buffer') uniforms[r.name] = { value: textures[r.name] ?? white };
    super({ vertexShader: body(vertex.file), fragmentShader: body(fragment.file),
            glslVersion: THREE.GLSL3, uniforms });
    this.blocks = new Map();
    for (const stage of [vertex, fragment])
      for (const r of stage.reflection.resources)
        if (r.descriptor_type === 'uniform_buffer' && !this.blocks.has(r.name))
          this.blocks.set(r.name, uniformsGroup(r, shaders.index.defaults.blocks));
    this.uniformsGroups = [...this.blocks.values()].map((b) => b.group);
    this.set('LfShadingBlock', 'u_shading.scale', map.scale);
    this.set('LfShadingBlock', 'u_shading.lean_offset', map.leanOffset);  // parseLeanMap's
    if (map.roughnessBaked) this.set('LfShadingBlock', 'u_shading.params.inv_s_shading', 0);
    if (plateau && textures.u_plateau && 'u_plateau' in uniforms)
      this.set('LfShadingBlock', 'u_shading.maps', 4);  // LF_MAP_PLATEAU of shaders/map_kinds.glsl
  }

  set(block, name, value) {
    const entry = this.blocks.get(block)?.uniforms.get(name);
    if (entry === undefined) return;
    assign(entry.uniform, value);
  }

  // The light from the scene's first visible DirectionalLight, if it has one: the direction
  // toward it (world) and its colour times its intensity (LfParams::light_color).
  updateLight(scene) {
    let light = null;
    scene.traverseVisible((o) => { if (!light && o.isDirectionalLight) light = o; });
    if (!light) return;
    const from = light.getWorldPosition(new THREE.Vector3());
    const to = light.target.getWorldPosition(new THREE.Vector3());
    this.set('LfObjectBlock', 'u_light_world', from.sub(to).normalize().toArray());
    this.set('LfShadingBlock', 'u_shading.params.light_color', light.color.clone().multiplyScalar(light.intensity).toArray());
  }

  // The object block from the mesh's world matrix and the camera, as leanfade's renderer fills it
  // (call before each render: Mesh.onBeforeRender).
  updateObject(mesh, camera) {
    const normal = new THREE.Matrix3().getNormalMatrix(mesh.matrixWorld);
    const clip = new THREE.Matrix4().multiplyMatrices(camera.projectionMatrix, camera.matrixWorldInverse);
    this.set('LfObjectBlock', 'u_model', mesh.matrixWorld.elements);
    this.set('LfObjectBlock', 'u_view', camera.matrixWorldInverse.elements);
    this.set('LfObjectBlock', 'u_clip', clip.elements);
    this.set('LfObjectBlock', 'u_normal_matrix', normal.elements);
    this.set('LfObjectBlock', 'u_eye_world', camera.getWorldPosition(new THREE.Vector3()).toArray());
  }

  // After the first draw: the offsets three.js gave each uniform against the reflected ones.
  // Returns the mismatches ([] when the layouts agree).
  checkBlockOffsets() {
    const wrong = [];
    for (const { uniforms } of this.blocks.values())
      for (const { uniform, member } of uniforms.values())
        if (uniform.__offset !== member.offset) wrong.push(`${member.name}: three.js ${uniform.__offset}, reflection ${member.offset}`);
    return wrong;
  }
}

// A mesh of leanfade's geometry with a LeanMaterial that updates its object block and light each frame,
// scaled to the unit sphere about its centre (the renderer's model transform).
export function leanMesh(mesh, material) {
  const object = new THREE.Mesh(meshGeometry(mesh), material);
  const centre = [0, 1, 2].map((c) => 0.5 * (mesh.bounds.min[c] + mesh.bounds.max[c]));
  const radius = 0.5 * Math.hypot(...[0, 1, 2].map((c) => mesh.bounds.max[c] - mesh.bounds.min[c]));
  object.scale.setScalar(1 / radius);
  object.position.set(...centre.map((c) => -c / radius));
  object.frustumCulled = false;
  object.onBeforeRender = (renderer, scene, camera) => {
    material.updateLight(scene);
    material.updateObject(object, camera);
  };
  return object;
}

// A three.js camera of `leanfade render --distances d` (viewAtDistance's eye and planes).
export function leanfadeCamera(view, aspect) {
  const camera = new THREE.PerspectiveCamera(view.fovYDegrees, aspect, view.near, view.far);
  camera.position.set(...view.eye);
  camera.up.set(...view.up);
  camera.lookAt(...view.target);
  camera.updateMatrixWorld();
  return camera;
}
