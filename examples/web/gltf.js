// The filtered glTF of `leanfade bake SCENE -o OUT.glb` in three.js: loaded once with KTX2Loader
// (leanfade's MIP levels) and once without (the PNG fallbacks, MIPs made by the GPU), each drawn
// near, mid and far. With ?capture=1 it reports what the loaders made of each material's textures
// (the suite's test, serve.mjs --capture --page gltf.html).
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { KTX2Loader } from 'three/addons/loaders/KTX2Loader.js';

const params = new URLSearchParams(location.search);
const sceneUrl = `${params.get('data') ?? 'data'}/${params.get('scene') ?? 'plane.glb'}`;
const size = Math.min(512, Math.max(64, Number(params.get('size') ?? 256)));
const capture = params.get('capture');
const distances = [0.8, 4, 16];

function describe(texture) {
  if (!texture) return null;
  return {
    kind: texture.isDataTexture ? 'data' : texture.isCompressedTexture ? 'compressed' : 'image',
    width: texture.image?.width ?? 0,
    height: texture.image?.height ?? 0,
    levels: texture.mipmaps?.length ?? 0,
    generateMipmaps: texture.generateMipmaps,
    minFilter: texture.minFilter,
  };
}

async function main() {
  const canvas = document.getElementById('views');
  canvas.width = size * distances.length;
  canvas.height = size * 2;
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
  renderer.setPixelRatio(1);
  renderer.setSize(canvas.width, canvas.height, false);
  renderer.setScissorTest(true);
  const ktx2 = new KTX2Loader().setTranscoderPath('node_modules/three/examples/jsm/libs/basis/').detectSupport(renderer);
  const withKtx2 = await new GLTFLoader().setKTX2Loader(ktx2).loadAsync(sceneUrl);
  const withPng = await new GLTFLoader().loadAsync(sceneUrl);

  const lit = (gltf) => {
    const scene = gltf.scene;
    scene.background = new THREE.Color(0.02, 0.02, 0.025);
    const light = new THREE.DirectionalLight(0xffffff, 1.5);
    light.position.set(0, 0.35, -1);  // behind the plane's far side: the highlight faces the camera
    scene.add(light, new THREE.AmbientLight(0xffffff, 0.05));
    return scene;
  };
  const scenes = [lit(withKtx2), lit(withPng)];
  const camera = new THREE.PerspectiveCamera(20, 1, 0.05, 200);
  scenes.forEach((scene, row) => distances.forEach((d, column) => {
    camera.position.set(0, 0.35 * d, d);
    camera.lookAt(0, 0, 0);
    const y = (1 - row) * size;
    renderer.setViewport(column * size, y, size, size);
    renderer.setScissor(column * size, y, size, size);
    renderer.render(scene, camera);
  }));

  const report = [];
  withKtx2.scene.traverse((o) => {
    if (!o.isMesh) return;
    const png = withPng.scene.getObjectByName(o.name) ?? null;
    const m = o.material;
    report.push({
      material: m.name,
      ktx2: { roughness: describe(m.roughnessMap), normal: describe(m.normalMap), anisotropy: describe(m.anisotropyMap) },
      png: png ? { roughness: describe(png.material.roughnessMap), normal: describe(png.material.normalMap) } : null,
    });
  });

  if (capture) {
    const errors = [];
    const gl = renderer.getContext();
    if (gl.getError() !== gl.NO_ERROR) errors.push('WebGL error');
    await fetch('/capture/done', { method: 'POST', body: JSON.stringify({ errors, report, size }) });
  }
}

main().catch(async (error) => {
  document.getElementById('status').textContent = String(error);
  if (capture) await fetch('/capture/done', { method: 'POST', body: JSON.stringify({ errors: [String(error.stack ?? error)] }) });
});
