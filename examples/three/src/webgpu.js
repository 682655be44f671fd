// LEAN-filtered normals and roughness for three.js's WebGPURenderer (TSL): the same per-pixel
// rule as leanStandardMaterial (lean_standard.js) as nodes of a MeshStandardNodeMaterial or
// MeshPhysicalNodeMaterial, lit by every three.js light.
import { float, max, normalMap, sqrt, texture, uniform, uv, vec3 } from 'three/tsl';

// { normalNode, roughnessNode } for the LEAN map `leanTexture` (leanMapTexture or LeanMapLoader's
// map; its userData gives sc and the encoding) and the base roughness `roughness` (a number or a
// node: perceptual r, α0 = r²), sampled at `uvNode` (the mesh's uv by default).
export function leanStandardNodes(leanTexture, { roughness = 0.5, uvNode = uv() } = {}) {
  const data = leanTexture.userData ?? {};
  const sc = uniform(data.scale ?? 1);
  const o = uniform(data.leanOffset ?? 0);
  const lean2 = texture(leanTexture, uvNode).depth(1);
  const gain = o.add(1);
  // lf_unpack: B and the diagonal of M.
  const b = lean2.xy.mul(gain).sub(o).mul(sc);
  const m = lean2.zw.mul(sc).mul(sc);
  const variance = max(m.x.sub(b.x.mul(b.x)), 0).add(max(m.y.sub(b.y.mul(b.y)), 0));
  const alpha0 = float(roughness).mul(roughness);
  // normalMap takes a texel in [0, 1] and applies the tangent frame (TBNViewMatrix).
  const normalNode = normalMap(vec3(b, 1).normalize().mul(0.5).add(0.5));
  const roughnessNode = sqrt(sqrt(alpha0.mul(alpha0).add(variance)));
  return { normalNode, roughnessNode };
}
