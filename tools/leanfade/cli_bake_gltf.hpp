#pragma once
// glTF scenes on the command line: `leanfade bake FILE.gltf|FILE.glb` (every normal texture of
// the scene baked to a LEAN map, through the LEAN-map cache) and the scene that `--scene
// FILE.gltf` draws in render, view, eval, calibrate and bench.
#include <set>
#include <string>
#include <vector>

#include "leanfade/core/detail/bump_source.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/detail/block_compression.hpp"
#include "leanfade/scene/gltf.hpp"
#include "leanfade/scene/material.hpp"

namespace leanfade::cli {

struct GltfBakeArgs {
    std::string input;    // the .gltf or .glb
    std::string out_dir;  // empty: the glTF's folder
    StoragePolicy bits = StoragePolicy::fixed(Storage::Unorm16);  // auto: 16 (bounded slopes)
    int threads = 0;
    int max_size = 0;  // largest image side; 0: the default limit
    std::string json;  // also write the summaries as JSON
    bool fsync = false;
    bool strict_normals = false;  // --strict-normals
    // The LEAN maps' KTX2 supercompression (--supercompression, --zstd-level).
    io::Supercompression supercompression = io::Supercompression::Zstandard;
    int zstd_level = 3;
    // -o OUT.gltf|glb: how the engine textures' KTX2 files are stored (--compress basis|none):
    // Basis Universal UASTC as KHR_texture_basisu requires (bake's default for a glTF), or RGBA8.
    io::BlockCompression compression = io::BlockCompression::Basis;
    // Flags of `bake` that have no meaning for a glTF scene and were given (refused by name).
    std::vector<std::string> refused_flags;
};

// What the glTF commands share (cli_bake_gltf.cpp, cli_bake_gltf_out.cpp):
// The bake settings of --bits (8, 16, 16f, 32f), --max-size (0: the default), --threads and
// --strict-normals, through the LEAN-map cache.
scene::GltfBakeSettings gltf_bake_settings(const StoragePolicy& bits, int max_size, int threads,
                                           bool strict_normals);
// Each of `warnings` as a "leanfade: PATH: ..." line on stderr.
void print_warnings(const std::string& path, const std::vector<std::string>& warnings);

// Bakes every normal texture of the scene (one per material and normal scale) to
// `<out>/<stem>.<material>.ktx2`, all published together (nothing is written on an error), and
// stores each in the LEAN-map cache so that a later render does not bake it again. Prints one
// line per map; returns 0. Throws leanfade::Error naming the file or the flag.
int run_bake_gltf(const GltfBakeArgs& args);

}  // namespace leanfade::cli
