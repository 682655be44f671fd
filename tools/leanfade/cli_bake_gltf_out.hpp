#pragma once
// `leanfade bake SCENE.gltf|SCENE.glb -o OUT.gltf|OUT.glb`: a copy of the scene whose materials
// carry filtered roughness MIPs, the matching normal MIPs, KHR_materials_anisotropy textures where
// the bumps are anisotropic, and the scene's own LEAN maps (docs/gltf.md). Everything else of the
// file (geometry, nodes, cameras, animations, other extensions) passes through unchanged.
#include "cli_bake_gltf.hpp"

namespace leanfade::cli {

// Writes `output` (.gltf or .glb) and, beside it, per material with a normal texture:
// OUT.<material>.roughness.ktx2/.png, .normal.ktx2/.png, .anisotropy.ktx2/.png (when written)
// and .lean.ktx2; a .gltf written from a .glb also gets OUT.bin (the binary chunk). All are
// published together; none replaces an input of the run (the scene, its buffers, its images).
// Prints every file written. Throws leanfade::Error naming the file or the flag.
int run_bake_gltf_out(const GltfBakeArgs& args, const std::string& output);

}  // namespace leanfade::cli
