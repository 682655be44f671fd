#pragma once
// Block-compressed engine textures (`leanfade bake --compress bc|astc`, docs/compression.md):
// the roughness, normal and anisotropy MIP chains of `bake --roughness-out` / `--anisotropy-out`
// in the formats engines ship, as KTX2 (every level) or DDS (BC only; Unreal, Unity).
//
//   texture     bc (desktop)                          astc (mobile; 4x4 blocks, 8 bits/texel)
//   roughness   BC4: R = roughness (the glTF G)       ASTC 4x4: the RGBA texture as is
//   normal      BC5: R, G = x, y (z = sqrt(1-x²-y²))  ASTC 4x4: x in RGB, y in A (astcenc normal)
//   anisotropy  BC1: RGB = direction xy, strength     ASTC 4x4: the RGBA texture as is
//
// Every level is compressed from its own 8-bit texels (the filtered float level rounded once),
// never from another level or from compressed data. The encoders are Debian's libsquish (BC1,
// BC4, BC5) and Arm's libastcenc; only the containers' headers are written here. The KTX2 files
// carry KTXswizzle so that loaders which honour it sample the uncompressed texture's layout
// (roughness "1r01": R = 1, G = roughness, B = 0, A = 1; normals "rg01" / "ra01", z to be
// reconstructed by the shader). Every failure throws leanfade::Error(file or name, cause).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "leanfade/io/image_io.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"

namespace leanfade::io {

// How engine textures are stored: RGBA8 as computed, block-compressed for desktop GPUs (BC) or
// mobile GPUs (ASTC), or Basis Universal UASTC, which every GPU transcodes to one of its formats
// (the web, glTF's KHR_texture_basisu; basis_universal.hpp: it has no fixed block format here).
enum class BlockCompression { None, Bc, Astc, Basis };

// The names of `bake --compress`: "none", "bc", "astc", "basis".
const std::vector<std::pair<std::string, BlockCompression>>& block_compression_names();
const char* to_string(BlockCompression compression);

// What an engine texture holds; it decides the compressed format (table above).
enum class EngineTexture { Roughness, Normal, Anisotropy };
const char* to_string(EngineTexture texture);

// One compressed format: its Vulkan and DXGI numbers, block size and the KTX2 data format.
struct BlockFormat {
    std::uint32_t vk_format = 0;    // VK_FORMAT_*_BLOCK
    std::uint32_t dxgi_format = 0;  // DXGI_FORMAT_* for DDS; 0: no DDS form (ASTC)
    int block_width = 4;
    int block_height = 4;
    int block_bytes = 8;
    const char* name = "";      // "BC5_UNORM", "ASTC_4x4_UNORM", ...
    const char* swizzle = "";   // KTXswizzle: how the stored channels map to the texture's RGBA
};

// The format of `texture` under `compression` (Bc or Astc). Throws leanfade::Error for None and
// Basis.
const BlockFormat& block_format(BlockCompression compression, EngineTexture texture);

// One level's blocks, rows of blocks top first: ceil(width / bw) * ceil(height / bh) blocks.
struct CompressedLevel {
    int width = 0;  // texels
    int height = 0;
    std::vector<std::uint8_t> blocks;
};

// Compresses each level of an RGBA8 chain (level 0 first; Rgba8Level, rows top first) on
// `threads` threads (<= 0: all). The same bytes for any thread count. Throws
// leanfade::Error(name, cause) for a level of a wrong byte count or an encoder failure.
std::vector<CompressedLevel> compress_levels(const std::vector<Rgba8Level>& levels,
                                             BlockCompression compression, EngineTexture texture,
                                             int threads = 0, const std::string& name = "texture");

// The RGBA8 texels a GPU samples from compressed levels, in the uncompressed texture's layout
// (KTXswizzle applied; a normal's z reconstructed as sqrt(1 - x² - y²)): what tests and the
// bake-off compare with the uncompressed levels.
std::vector<Rgba8Level> decompress_levels(const std::vector<CompressedLevel>& levels,
                                          BlockCompression compression, EngineTexture texture,
                                          const std::string& name = "texture");

// A KTX2 file of compressed levels (the full chain, level 0 first): vkFormat and DFD of the
// format (colour model BC1A/BC4/BC5/ASTC, linear transfer, unspecified primaries: the data is not
// colour), KTXswizzle, KTXorientation "rd", KTXwriter and the caller's keys. Written atomically.
std::vector<std::uint8_t> encode_ktx2_compressed(const std::vector<CompressedLevel>& levels,
                                                 const BlockFormat& format,
                                                 const std::string& writer,
                                                 const std::string& name = "texture",
                                                 const TextureKeyValues& key_values = {});
void write_ktx2_compressed(const std::string& path, const std::vector<CompressedLevel>& levels,
                           const BlockFormat& format, const std::string& writer,
                           const WriteOptions& options = {},
                           const TextureKeyValues& key_values = {});
// Reads such a file's levels back, checking that it holds `format` (vkFormat, block sizes).
std::vector<CompressedLevel> read_ktx2_compressed(const std::string& path,
                                                  const BlockFormat& format);

// A DDS file (DX10 header, DXGI format of `format`, every level) of compressed levels, or of RGBA8
// levels (DXGI_FORMAT_R8G8B8A8_UNORM) with format == nullptr and `rgba8` given. Written atomically.
// DDS has no ASTC form: throws for a format whose dxgi_format is 0.
void write_dds_compressed(const std::string& path, const std::vector<CompressedLevel>& levels,
                          const BlockFormat& format, const WriteOptions& options = {});
void write_dds_rgba8(const std::string& path, const std::vector<Rgba8Level>& levels,
                     const WriteOptions& options = {});
// A DDS file written by the functions above, read back: its DXGI format and every level's bytes
// (texels or blocks). Throws leanfade::Error(path, cause) for any other or a damaged file.
struct DdsFile {
    std::uint32_t dxgi_format = 0;
    std::vector<CompressedLevel> levels;
};
DdsFile read_dds(const std::string& path);

}  // namespace leanfade::io
