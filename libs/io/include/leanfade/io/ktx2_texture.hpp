#pragma once
// Plain 2D textures with their MIP chain as KTX 2.0 files (Khronos,
// https://registry.khronos.org/KTX/specs/2.0/ktxspec.v2.html), in the form common loaders read:
// VK_FORMAT_R8G8B8A8_UNORM, one layer, one face, no supercompression, linear transfer (the
// textures are data: roughness, normals, anisotropy; docs/roughness.md). leanfade writes its
// roughness MIPs with this (`leanfade bake --roughness-out`); LEAN maps have their own container
// (ktx2.hpp).
//
// Rows are top row first (KTXorientation "rd"); level 0 (the largest) first in the level index,
// level data from the smallest to the largest in the file, each level 4-byte aligned. Every
// failure throws leanfade::Error(file, cause); the file is written atomically (AtomicFile).
#include <cstdint>
#include <string>
#include <vector>

#include "leanfade/io/image_io.hpp"

namespace leanfade::io {

// One MIP level of 8-bit RGBA texels, rows top first: width * height * 4 bytes.
struct Rgba8Level {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> texels;
};

// The bytes of a KTX2 file of `levels` (level 0 first; sizes halving with floor down to 1 x 1,
// the full chain), KTXwriter = `writer`. Throws leanfade::Error(name, cause) for an empty or
// broken chain or wrong byte counts.
std::vector<std::uint8_t> encode_ktx2_rgba8(const std::vector<Rgba8Level>& levels,
                                            const std::string& writer,
                                            const std::string& name = "texture");

// encode_ktx2_rgba8 written atomically to `path`.
void write_ktx2_rgba8(const std::string& path, const std::vector<Rgba8Level>& levels,
                      const std::string& writer, const WriteOptions& options = {});

// Reads the levels of a file in the form above back (for tests and tools): checks the structure
// with inspect_ktx2 (ktx2.hpp), then that it is a 2D R8G8B8A8_UNORM texture with one layer and
// one face, and copies each level. Throws leanfade::Error(path, cause).
std::vector<Rgba8Level> read_ktx2_rgba8(const std::string& path);

}  // namespace leanfade::io
