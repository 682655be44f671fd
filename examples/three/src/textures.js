// leanfade's maps as three.js textures, every level as baked (three.js would otherwise make its
// own MIPs by averaging, which is what LEAN mapping replaces), and a Loader for LEAN maps.
import * as THREE from 'three';

import { bottomRowFirst, parseLeanMap } from './lean_map.js';

// Levels of a parsed map (parseLeanMap, parseTexture) as three.js mipmaps. leanfade's files
// store rows top first; `vUp` (meshes with v = 0 at the image's bottom, as leanfade's and
// three.js's built-in geometries) reverses them, as three.js's flipY does for images; glTF meshes
// (v = 0 at the top) take them as they are.
function mipmaps(texture, vUp) {
  return texture.levels.map((level) => ({
    data: vUp ? bottomRowFirst(level, texture.layers) : level.data,
    width: level.width,
    height: level.height,
  }));
}

// Trilinear, repeating, the levels as given, no colour-space conversion (linear data).
function sampled(texture) {
  texture.minFilter = THREE.LinearMipmapLinearFilter;
  texture.magFilter = THREE.LinearFilter;
  texture.wrapS = THREE.RepeatWrapping;
  texture.wrapT = THREE.RepeatWrapping;
  texture.generateMipmaps = false;
  texture.flipY = false;
  texture.colorSpace = THREE.NoColorSpace;
  texture.needsUpdate = true;
  return texture;
}

// The LEAN map (parseLeanMap) as a texture: a 2D array of two layers (lean1, lean2), RGBA half
// floats, every level. Its userData holds what shading needs: scale (sc), leanOffset,
// roughnessBaked.
export function leanMapTexture(map, { vUp = true } = {}) {
  const texture = sampled(new THREE.CompressedArrayTexture(mipmaps(map, vUp), map.width, map.height, 2,
                                                           THREE.RGBAFormat, THREE.HalfFloatType));
  texture.userData = { scale: map.scale, leanOffset: map.leanOffset, roughnessBaked: map.roughnessBaked };
  return texture;
}

// A 2D texture of RGBA half floats with its levels: the plateau layer (a LEAN map's `plateau`, or
// parseTexture of `bake --plateau-out`).
export function halfFloatTexture(texture, { vUp = true } = {}) {
  return sampled(new THREE.CompressedTexture(mipmaps(texture, vUp), texture.width, texture.height,
                                             THREE.RGBAFormat, THREE.HalfFloatType));
}

// Loads a LEAN map (`leanfade bake --bits 16f`, KTX2, Zstandard or not) as
// { map: leanMapTexture, plateau: halfFloatTexture or null, source: parseLeanMap's result }.
// Options: vUp (see mipmaps; true by default, false for glTF meshes).
export class LeanMapLoader extends THREE.Loader {
  constructor(manager, { vUp = true } = {}) {
    super(manager);
    this.vUp = vUp;
  }

  load(url, onLoad, onProgress, onError) {
    const loader = new THREE.FileLoader(this.manager);
    loader.setPath(this.path);
    loader.setResponseType('arraybuffer');
    loader.setRequestHeader(this.requestHeader);
    loader.setWithCredentials(this.withCredentials);
    loader.load(url, (buffer) => {
      this.parse(buffer, url).then(onLoad, (error) => {
        if (onError) onError(error);
        else console.error(error);
        this.manager.itemError(url);
      });
    }, onProgress, onError);
  }

  async parse(buffer, name = 'LEAN map') {
    const source = await parseLeanMap(buffer, name);
    const options = { vUp: this.vUp };
    return {
      map: leanMapTexture(source, options),
      plateau: source.plateau ? halfFloatTexture(source.plateau, options) : null,
      source,
    };
  }
}
