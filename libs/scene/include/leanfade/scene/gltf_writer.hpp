#pragma once
// A filtered copy of a glTF scene (docs/gltf.md): every material with a normal texture gets
// roughness MIPs (metallic-roughness, G = sqrt(alpha) with alpha^2 = alpha0^2 + Sxx + Syy per
// level), the matching normal MIPs, a KHR_materials_anisotropy texture where its bumps are
// anisotropic, and its LEAN map (the LEANFADE_lean_map extension); the textures' KTX2 files are
// stored as KHR_texture_basisu asks (Basis Universal UASTC) or as RGBA8. Everything else of the
// file (geometry, nodes, cameras, animations, other extensions) passes through unchanged.
// `leanfade bake SCENE -o OUT.gltf|OUT.glb` is this function; an engine's importer can call it.
#include <cstddef>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "leanfade/io/atomic_file.hpp"
#include "leanfade/io/block_compression.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/scene/gltf.hpp"

namespace leanfade::scene {

struct FilteredGltfSettings {
    // The LEAN maps' bake (storage, image size limit, threads, the LEAN-map cache, strict
    // normals): the cache also keeps each material's output files, under one key, so that a
    // later run copies them instead of filtering again.
    GltfBakeSettings bake;
    // The LEAN maps' KTX2 supercompression and Zstandard level.
    io::Supercompression supercompression = io::Supercompression::Zstandard;
    int zstd_level = 3;
    // The engine textures' KTX2 files: Basis Universal UASTC (KHR_texture_basisu) or None (RGBA8).
    io::BlockCompression compression = io::BlockCompression::Basis;
    io::Durability durability = io::Durability::Rename;
    // Also a JSON array of one summary per material (its files, sizes, anisotropy, cache use,
    // seconds) at this path; empty: none.
    std::string summary_path;
};

// What a write did, in the order met: `warnings` about the input scene (the loader's, cache
// entries that could not be stored), `other_convention`: normal textures (by image) that fit the
// DirectX convention clearly better than glTF's OpenGL one; `written`: every file published, the
// output first.
struct FilteredGltfReport {
    std::vector<std::string> warnings;
    std::vector<std::string> other_convention;
    std::vector<std::string> written;
    std::size_t materials = 0;  // materials filtered
};

// Called before each material is filtered: its index (from 0), the count and its name.
using GltfWriteProgress =
    std::function<void(std::size_t index, std::size_t count, const std::string& material)>;

// Writes `output` (.gltf or .glb) from `input` and, beside a .gltf, per material with a normal
// texture: OUT.<material>.roughness.ktx2/.png, .normal.ktx2/.png, .anisotropy.ktx2/.png and
// .lean.ktx2 (a .glb holds them in its binary chunk); a .gltf written from a .glb also gets
// OUT.bin. External files the output names are copied beside it when its folder is another.
// All are published together, nothing on an error, and none replaces an input (the scene, its
// buffers, its images). Throws leanfade::Error naming the file (a refused compression names the
// setting "compress"); `report` (if given) holds what was found, also when it throws.
void write_filtered_gltf(const std::string& input, const std::string& output,
                         const FilteredGltfSettings& settings, FilteredGltfReport* report = nullptr,
                         const GltfWriteProgress& progress = {});

// A material's (or file's) name as part of a file name: letters, digits, '-' and '_' kept, the
// rest '_', at most 64 characters, "material" when nothing is left.
std::string file_name_part(const std::string& name);
// `base` + `suffix`, or `base`-2 + `suffix`, -3, ...: the first not in `taken`, which it joins.
std::string unique_name(const std::string& base, const std::string& suffix,
                        std::set<std::string>& taken);

}  // namespace leanfade::scene
