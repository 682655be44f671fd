#pragma once
// KTX2 files of Basis Universal UASTC: the payload glTF's KHR_texture_basisu asks for, which
// every GPU transcodes at load time to a format it has (BC7, ASTC, ETC2, ...). Written for
// `leanfade bake --compress basis` by Basis Universal's own encoder, its WebAssembly build run
// by Node.js (tools/node/encode_uastc.mjs, npm package ktx2-encoder pinned by the lockfile):
// Debian 12 packages no Basis Universal encoder.
//
// Every level is encoded from its own RGBA8 level (the encoder makes no MIPs), UASTC 4x4
// Zstandard-supercompressed (scheme 2), DFD colour model UASTC with one channel, RGB (or RGBA
// where alpha matters), primaries unspecified and linear transfer: the non-colour data of
// KHR_texture_basisu (normals, roughness).
#include <string>
#include <vector>

#include "leanfade/io/detail/ktx2_texture.hpp"

namespace leanfade::io {

struct UastcTexture {
    std::string output;                      // the KTX2 file to write (a staged path)
    const std::vector<Rgba8Level>* levels;   // the full chain, level 0 first, rows top first
    bool alpha = false;                      // RGBA (its A is used) or RGB
};

// Encodes every texture with the encoder script `encoder` (find_node_script of
// kUastcEncoderScript), the textures shared out among up to one process per hardware thread (the
// WebAssembly encoder is single-threaded). Throws leanfade::Error("compress", ...) without Node.js or the script's
// packages, Error(<output>, cause) when a texture cannot be encoded.
inline constexpr const char* kUastcEncoderScript = "encode_uastc.mjs";
void write_ktx2_uastc(const std::vector<UastcTexture>& textures, const std::string& writer,
                      const std::string& encoder);

// What a UASTC KTX2 file's header says (no transcoding): its size, levels, supercompression and
// the DFD's channel and colour space. Throws leanfade::Error(path, cause) for a file that is not
// UASTC KTX2.
struct UastcFileInfo {
    int width = 0;
    int height = 0;
    int levels = 0;
    bool zstd = false;        // supercompression scheme 2
    bool alpha = false;       // channel UASTC_RGBA (else RGB)
    bool linear = false;      // transfer function linear
    bool primaries_unspecified = false;
};
UastcFileInfo inspect_ktx2_uastc(const std::string& path);

}  // namespace leanfade::io
