// Block-compressed engine textures (leanfade/io/detail/block_compression.hpp): libsquish for BC1, BC4 and
// BC5, libastcenc for ASTC; the KTX2 and DDS containers.
#include "leanfade/io/detail/block_compression.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>

// Debian's libastcenc is the shared library: its C entry points are declared extern "C" only
// with ASTCENC_DYNAMIC_LIBRARY.
#define ASTCENC_DYNAMIC_LIBRARY 1
#include <astcenc.h>
#include <squish.h>

#include "input_file.hpp"
#include "ktx2_internal.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/detail/parallel.hpp"
#include "leanfade/io/detail/atomic_file.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::io {
namespace {

using namespace ktx2_detail;

// Vulkan and DXGI format numbers (vulkan_core.h, dxgiformat.h).
constexpr std::uint32_t kVkBc1RgbUnorm = 131;
constexpr std::uint32_t kVkBc4Unorm = 139;
constexpr std::uint32_t kVkBc5Unorm = 141;
constexpr std::uint32_t kVkAstc4x4Unorm = 157;
constexpr std::uint32_t kDxgiBc1Unorm = 71;
constexpr std::uint32_t kDxgiBc4Unorm = 80;
constexpr std::uint32_t kDxgiBc5Unorm = 83;
constexpr std::uint32_t kDxgiR8G8B8A8Unorm = 28;

// Khronos Data Format colour models of block-compressed data and their channel ids.
constexpr std::uint32_t kDfdModelBc1a = 128;
constexpr std::uint32_t kDfdModelBc4 = 131;
constexpr std::uint32_t kDfdModelBc5 = 132;
constexpr std::uint32_t kDfdModelAstc = 162;
constexpr std::uint32_t kDfdPrimariesUnspecified = 0;

const BlockFormat kBc4{kVkBc4Unorm, kDxgiBc4Unorm, 4, 4, 8, "BC4_UNORM", "1r01"};
const BlockFormat kBc5{kVkBc5Unorm, kDxgiBc5Unorm, 4, 4, 16, "BC5_UNORM", "rg01"};
const BlockFormat kBc1{kVkBc1RgbUnorm, kDxgiBc1Unorm, 4, 4, 8, "BC1_RGB_UNORM", "rgb1"};
const BlockFormat kAstcRgba{kVkAstc4x4Unorm, 0, 4, 4, 16, "ASTC_4x4_UNORM", "rgba"};
const BlockFormat kAstcNormal{kVkAstc4x4Unorm, 0, 4, 4, 16, "ASTC_4x4_UNORM", "ra01"};

int blocks_across(int texels, int block) {
    return (texels + block - 1) / block;
}

std::size_t level_block_bytes(int width, int height, const BlockFormat& format) {
    return std::size_t(blocks_across(width, format.block_width)) *
           std::size_t(blocks_across(height, format.block_height)) * std::size_t(format.block_bytes);
}

void check_level(const Rgba8Level& level, std::size_t index, const std::string& name) {
    if (level.width < 1 || level.height < 1 ||
        level.texels.size() != std::size_t(level.width) * std::size_t(level.height) * 4)
        throw Error(name, "level " + std::to_string(index) + " is not " +
                              std::to_string(level.width) + "x" + std::to_string(level.height) +
                              " RGBA8 texels");
}

// --- BC (libsquish) ---

int squish_flags(EngineTexture texture) {
    switch (texture) {
        case EngineTexture::Roughness: return squish::kBc4;
        case EngineTexture::Normal: return squish::kBc5;
        case EngineTexture::Anisotropy: return squish::kDxt1 | squish::kColourClusterFit;
    }
    return 0;
}

// The 4x4 texels of a block as libsquish takes them (RGBA; BC4 reads R, BC5 R and G), and the
// mask of those inside the level.
int gather_block(const Rgba8Level& level, int bx, int by, EngineTexture texture,
                 std::array<std::uint8_t, 64>& rgba) {
    int mask = 0;
    rgba.fill(0);
    for (int y = 0; y < 4; ++y) {
        for (int x = 0; x < 4; ++x) {
            const int tx = 4 * bx + x, ty = 4 * by + y;
            if (tx >= level.width || ty >= level.height) continue;
            const std::uint8_t* t =
                &level.texels[(std::size_t(ty) * std::size_t(level.width) + std::size_t(tx)) * 4];
            std::uint8_t* out = &rgba[std::size_t(4 * (4 * y + x))];
            if (texture == EngineTexture::Roughness) {
                out[0] = t[1];  // roughness: the glTF texture's G
            } else {
                out[0] = t[0];
                out[1] = t[1];
                out[2] = t[2];
            }
            out[3] = 255;
            mask |= 1 << (4 * y + x);
        }
    }
    return mask;
}

CompressedLevel compress_bc(const Rgba8Level& level, EngineTexture texture, const BlockFormat& format,
                            int threads) {
    CompressedLevel out{level.width, level.height, {}};
    out.blocks.resize(level_block_bytes(level.width, level.height, format));
    const int across = blocks_across(level.width, 4), down = blocks_across(level.height, 4);
    const int flags = squish_flags(texture);
    parallel_for_dynamic(down, threads, 4, [&](int, int first, int end) {
        std::array<std::uint8_t, 64> rgba{};
        for (int by = first; by < end; ++by) {
            for (int bx = 0; bx < across; ++bx) {
                const int mask = gather_block(level, bx, by, texture, rgba);
                std::uint8_t* block =
                    &out.blocks[(std::size_t(by) * std::size_t(across) + std::size_t(bx)) *
                                std::size_t(format.block_bytes)];
                squish::CompressMasked(rgba.data(), mask, block, flags);
            }
        }
    });
    return out;
}

std::uint8_t unit_to_code(float v) {
    return std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

// z of a unit normal from its stored x, y codes (0..255 for -1..1), as a code.
std::uint8_t normal_z_code(std::uint8_t x_code, std::uint8_t y_code) {
    const float x = float(x_code) / 255.0f * 2.0f - 1.0f;
    const float y = float(y_code) / 255.0f * 2.0f - 1.0f;
    const float z = std::sqrt(std::max(0.0f, 1.0f - x * x - y * y));
    return unit_to_code(0.5f * z + 0.5f);
}

// One BC4 block (BC5 is two) decoded into 16 values (D3D11 functional specification, "BC4"):
// two 8-bit endpoints and 3-bit indices into 8 values (endpoints first) when red0 > red1, else 6
// values plus 0 and 255. Written here because Debian's libsquish 1.15 encodes BC4 and BC5 but its
// Decompress reads those blocks as BC1.
void decode_bc4_block(const std::uint8_t* block, std::uint8_t* values, int stride) {
    const int red0 = block[0], red1 = block[1];
    std::array<int, 8> palette{red0, red1, 0, 0, 0, 0, 0, 0};
    if (red0 > red1) {
        for (int i = 1; i <= 6; ++i) palette[std::size_t(i + 1)] = ((7 - i) * red0 + i * red1 + 3) / 7;
    } else {
        for (int i = 1; i <= 4; ++i) palette[std::size_t(i + 1)] = ((5 - i) * red0 + i * red1 + 2) / 5;
        palette[6] = 0;
        palette[7] = 255;
    }
    std::uint64_t indices = 0;
    for (int i = 0; i < 6; ++i) indices |= std::uint64_t(block[2 + i]) << (8 * i);
    for (int t = 0; t < 16; ++t)
        values[t * stride] = std::uint8_t(palette[std::size_t((indices >> (3 * t)) & 7u)]);
}

Rgba8Level decompress_bc(const CompressedLevel& level, EngineTexture texture,
                         const BlockFormat& format) {
    Rgba8Level out{level.width, level.height,
                   std::vector<std::uint8_t>(std::size_t(level.width) * level.height * 4)};
    const int across = blocks_across(level.width, 4), down = blocks_across(level.height, 4);
    const int flags = squish_flags(texture);
    std::array<std::uint8_t, 64> rgba{};
    for (int by = 0; by < down; ++by) {
        for (int bx = 0; bx < across; ++bx) {
            const std::uint8_t* block = &level.blocks[(std::size_t(by) * across + std::size_t(bx)) *
                                                      std::size_t(format.block_bytes)];
            if (texture == EngineTexture::Anisotropy) {
                squish::Decompress(rgba.data(), block, flags);
            } else {
                decode_bc4_block(block, &rgba[0], 4);
                if (texture == EngineTexture::Normal) decode_bc4_block(block + 8, &rgba[1], 4);
            }
            for (int y = 0; y < 4; ++y) {
                for (int x = 0; x < 4; ++x) {
                    const int tx = 4 * bx + x, ty = 4 * by + y;
                    if (tx >= level.width || ty >= level.height) continue;
                    const std::uint8_t* s = &rgba[std::size_t(4 * (4 * y + x))];
                    std::uint8_t* t =
                        &out.texels[(std::size_t(ty) * std::size_t(level.width) + std::size_t(tx)) * 4];
                    switch (texture) {
                        case EngineTexture::Roughness:  // KTXswizzle 1r01
                            t[0] = 255, t[1] = s[0], t[2] = 0, t[3] = 255;
                            break;
                        case EngineTexture::Normal:  // rg01, z reconstructed
                            t[0] = s[0], t[1] = s[1], t[2] = normal_z_code(s[0], s[1]), t[3] = 255;
                            break;
                        case EngineTexture::Anisotropy:
                            t[0] = s[0], t[1] = s[1], t[2] = s[2], t[3] = 255;
                            break;
                    }
                }
            }
        }
    }
    return out;
}

// --- ASTC (libastcenc) ---

struct AstcContextDeleter {
    void operator()(astcenc_context* context) const { astcenc_context_free(context); }
};
using AstcContext = std::unique_ptr<astcenc_context, AstcContextDeleter>;

AstcContext astc_context(EngineTexture texture, unsigned thread_count, const std::string& name) {
    astcenc_config config{};
    const unsigned flags = texture == EngineTexture::Normal ? ASTCENC_FLG_MAP_NORMAL : 0u;
    astcenc_error status =
        astcenc_config_init(ASTCENC_PRF_LDR, 4, 4, 1, ASTCENC_PRE_MEDIUM, flags, &config);
    if (status != ASTCENC_SUCCESS)
        throw Error(name, std::string("ASTC encoder: ") + astcenc_get_error_string(status));
    astcenc_context* context = nullptr;
    status = astcenc_context_alloc(&config, thread_count, &context);
    if (status != ASTCENC_SUCCESS)
        throw Error(name, std::string("ASTC encoder: ") + astcenc_get_error_string(status));
    return AstcContext(context);
}

// Normals as astcenc's normal mode takes them: x in RGB, y in A (the KTX2 swizzle "ra01").
astcenc_swizzle astc_encode_swizzle(EngineTexture texture) {
    if (texture == EngineTexture::Normal)
        return {ASTCENC_SWZ_R, ASTCENC_SWZ_R, ASTCENC_SWZ_R, ASTCENC_SWZ_G};
    return {ASTCENC_SWZ_R, ASTCENC_SWZ_G, ASTCENC_SWZ_B, ASTCENC_SWZ_A};
}

CompressedLevel compress_astc(astcenc_context* context, const Rgba8Level& level,
                              EngineTexture texture, const BlockFormat& format, int threads,
                              const std::string& name) {
    CompressedLevel out{level.width, level.height, {}};
    out.blocks.resize(level_block_bytes(level.width, level.height, format));
    void* slice = const_cast<std::uint8_t*>(level.texels.data());  // read only by the encoder
    astcenc_image image{unsigned(level.width), unsigned(level.height), 1, ASTCENC_TYPE_U8, &slice};
    const astcenc_swizzle swizzle = astc_encode_swizzle(texture);
    // Each thread joins once: astcenc hands out the blocks and a joined thread works until every
    // block is done, so a worker that could not be started costs time, not blocks.
    std::vector<std::atomic<bool>> joined(static_cast<std::size_t>(threads));
    std::atomic<int> failure{ASTCENC_SUCCESS};
    parallel_for_dynamic(threads, threads, 1, [&](int worker, int, int) {
        if (joined[std::size_t(worker)].exchange(true)) return;
        const astcenc_error status = astcenc_compress_image(
            context, &image, &swizzle, out.blocks.data(), out.blocks.size(), unsigned(worker));
        if (status != ASTCENC_SUCCESS) failure = status;
    });
    astcenc_compress_reset(context);
    if (failure != ASTCENC_SUCCESS)
        throw Error(name, std::string("ASTC encoder: ") +
                              astcenc_get_error_string(astcenc_error(failure.load())));
    return out;
}

Rgba8Level decompress_astc(astcenc_context* context, const CompressedLevel& level,
                           EngineTexture texture, const std::string& name) {
    Rgba8Level out{level.width, level.height,
                   std::vector<std::uint8_t>(std::size_t(level.width) * level.height * 4)};
    void* slice = out.texels.data();
    astcenc_image image{unsigned(level.width), unsigned(level.height), 1, ASTCENC_TYPE_U8, &slice};
    // Normals: x from R, y from A, z reconstructed by the decoder.
    const astcenc_swizzle swizzle =
        texture == EngineTexture::Normal
            ? astcenc_swizzle{ASTCENC_SWZ_R, ASTCENC_SWZ_A, ASTCENC_SWZ_Z, ASTCENC_SWZ_1}
            : astcenc_swizzle{ASTCENC_SWZ_R, ASTCENC_SWZ_G, ASTCENC_SWZ_B, ASTCENC_SWZ_A};
    const astcenc_error status = astcenc_decompress_image(context, level.blocks.data(),
                                                          level.blocks.size(), &image, &swizzle, 0);
    astcenc_decompress_reset(context);
    if (status != ASTCENC_SUCCESS)
        throw Error(name, std::string("ASTC decoder: ") + astcenc_get_error_string(status));
    return out;
}

LevelByteCount block_bytes_of(const BlockFormat& format) {
    return [&format](int w, int h) { return level_block_bytes(w, h, format); };
}

std::string blocks_unit(const BlockFormat& format) {
    return std::string(" of ") + format.name + " blocks";
}

void check_compressed(const std::vector<CompressedLevel>& levels, const BlockFormat& format,
                      const std::string& name) {
    std::vector<TextureLevelSize> sizes;
    for (const CompressedLevel& level : levels)
        sizes.push_back({level.width, level.height, level.blocks.size()});
    check_mip_chain(sizes, block_bytes_of(format), blocks_unit(format), name);
}

// The basic data format descriptor of a block format (KDFS §5.6: one sample per plane of the
// block, covering all its bits).
Ktx2DataFormat block_data_format(const BlockFormat& format) {
    Ktx2DataFormat dfd;
    dfd.version_number = kDfdVersion13;
    dfd.color_primaries = kDfdPrimariesUnspecified;
    dfd.transfer_function = kDfdTransferLinear;
    dfd.texel_block_dimensions[0] = std::uint32_t(format.block_width - 1);
    dfd.texel_block_dimensions[1] = std::uint32_t(format.block_height - 1);
    dfd.bytes_plane[0] = std::uint32_t(format.block_bytes);
    const auto sample = [](std::uint32_t offset, std::uint32_t bits, std::uint32_t channel) {
        Ktx2Sample s;
        s.bit_offset = offset;
        s.bit_length = bits;
        s.channel_id = channel;
        s.sample_lower = 0;
        s.sample_upper = 0xFFFFFFFFu;
        return s;
    };
    switch (format.vk_format) {
        case kVkBc1RgbUnorm:
            dfd.color_model = kDfdModelBc1a;
            dfd.samples = {sample(0, 64, 0)};  // KHR_DF_CHANNEL_BC1A_COLOR
            break;
        case kVkBc4Unorm:
            dfd.color_model = kDfdModelBc4;
            dfd.samples = {sample(0, 64, 0)};  // KHR_DF_CHANNEL_BC4_DATA
            break;
        case kVkBc5Unorm:
            dfd.color_model = kDfdModelBc5;
            dfd.samples = {sample(0, 64, 0), sample(64, 64, 1)};  // RED, GREEN
            break;
        default:
            dfd.color_model = kDfdModelAstc;
            dfd.samples = {sample(0, 128, 0)};  // KHR_DF_CHANNEL_ASTC_DATA
            break;
    }
    dfd.descriptor_block_size =
        kDfdBlockHeaderSize + kDfdSampleSize * std::uint32_t(dfd.samples.size());
    dfd.total_size = 4 + dfd.descriptor_block_size;
    return dfd;
}

// --- DDS (Microsoft's DDS_HEADER + DDS_HEADER_DXT10) ---

constexpr std::uint32_t kDdsMagic = 0x20534444;  // "DDS "
constexpr std::uint32_t kDdsFourCcDx10 = 0x30315844;  // "DX10"
constexpr std::size_t kDdsHeadSize = 4 + 124 + 20;
constexpr std::uint32_t kDdsdCaps = 0x1, kDdsdHeight = 0x2, kDdsdWidth = 0x4, kDdsdPitch = 0x8,
                        kDdsdPixelFormat = 0x1000, kDdsdMipMapCount = 0x20000,
                        kDdsdLinearSize = 0x80000;
constexpr std::uint32_t kDdpfFourCc = 0x4;
constexpr std::uint32_t kDdsCapsComplex = 0x8, kDdsCapsTexture = 0x1000, kDdsCapsMipMap = 0x400000;
constexpr std::uint32_t kD3d10ResourceDimensionTexture2d = 3;

std::vector<std::uint8_t> dds_head(std::uint32_t dxgi_format, int width, int height,
                                   std::size_t level_count, bool compressed,
                                   std::uint64_t pitch_or_linear_size) {
    std::vector<std::uint8_t> head;
    append_u32_le(head, kDdsMagic);
    append_u32_le(head, 124);
    append_u32_le(head, kDdsdCaps | kDdsdHeight | kDdsdWidth | kDdsdPixelFormat | kDdsdMipMapCount |
                            (compressed ? kDdsdLinearSize : kDdsdPitch));
    append_u32_le(head, std::uint32_t(height));
    append_u32_le(head, std::uint32_t(width));
    append_u32_le(head, std::uint32_t(std::min<std::uint64_t>(pitch_or_linear_size, 0xFFFFFFFFu)));
    append_u32_le(head, 0);  // depth
    append_u32_le(head, std::uint32_t(level_count));
    for (int i = 0; i < 11; ++i) append_u32_le(head, 0);  // reserved
    append_u32_le(head, 32);                                // pixel format: size
    append_u32_le(head, kDdpfFourCc);
    append_u32_le(head, kDdsFourCcDx10);
    for (int i = 0; i < 5; ++i) append_u32_le(head, 0);  // bit count and masks
    append_u32_le(head, kDdsCapsTexture | kDdsCapsMipMap | kDdsCapsComplex);
    for (int i = 0; i < 4; ++i) append_u32_le(head, 0);  // caps2..4, reserved
    append_u32_le(head, dxgi_format);
    append_u32_le(head, kD3d10ResourceDimensionTexture2d);
    append_u32_le(head, 0);  // misc flags
    append_u32_le(head, 1);  // array size
    append_u32_le(head, 0);  // alpha mode unknown
    return head;
}

}  // namespace

const std::vector<std::pair<std::string, BlockCompression>>& block_compression_names() {
    static const std::vector<std::pair<std::string, BlockCompression>> names = {
        {"none", BlockCompression::None},
        {"bc", BlockCompression::Bc},
        {"astc", BlockCompression::Astc},
        {"basis", BlockCompression::Basis}};
    return names;
}

const char* to_string(BlockCompression compression) {
    for (const auto& [name, value] : block_compression_names())
        if (value == compression) return name.c_str();
    return "none";
}

const char* to_string(EngineTexture texture) {
    switch (texture) {
        case EngineTexture::Roughness: return "roughness";
        case EngineTexture::Normal: return "normal";
        case EngineTexture::Anisotropy: return "anisotropy";
    }
    return "texture";
}

const BlockFormat& block_format(BlockCompression compression, EngineTexture texture) {
    if (compression == BlockCompression::Bc) {
        switch (texture) {
            case EngineTexture::Roughness: return kBc4;
            case EngineTexture::Normal: return kBc5;
            case EngineTexture::Anisotropy: return kBc1;
        }
    }
    if (compression == BlockCompression::Astc)
        return texture == EngineTexture::Normal ? kAstcNormal : kAstcRgba;
    throw Error::setting("compress",
                         compression == BlockCompression::Basis
                             ? "Basis Universal textures are written by write_ktx2_uastc"
                             : "uncompressed textures have no block format");
}

std::vector<CompressedLevel> compress_levels(const std::vector<Rgba8Level>& levels,
                                             BlockCompression compression, EngineTexture texture,
                                             int threads, const std::string& name) {
    const BlockFormat& format = block_format(compression, texture);
    for (std::size_t l = 0; l < levels.size(); ++l) check_level(levels[l], l, name);
    const int thread_count = resolve_thread_count(threads);
    std::vector<CompressedLevel> out;
    out.reserve(levels.size());
    if (compression == BlockCompression::Bc) {
        for (const Rgba8Level& level : levels)
            out.push_back(compress_bc(level, texture, format, thread_count));
        return out;
    }
    const AstcContext context = astc_context(texture, unsigned(thread_count), name);
    for (const Rgba8Level& level : levels)
        out.push_back(compress_astc(context.get(), level, texture, format, thread_count, name));
    return out;
}

std::vector<Rgba8Level> decompress_levels(const std::vector<CompressedLevel>& levels,
                                          BlockCompression compression, EngineTexture texture,
                                          const std::string& name) {
    const BlockFormat& format = block_format(compression, texture);
    for (std::size_t l = 0; l < levels.size(); ++l)
        if (levels[l].width < 1 || levels[l].height < 1 ||
            levels[l].blocks.size() != level_block_bytes(levels[l].width, levels[l].height, format))
            throw Error(name, "level " + std::to_string(l) + " holds a wrong number of blocks");
    std::vector<Rgba8Level> out;
    if (compression == BlockCompression::Bc) {
        for (const CompressedLevel& level : levels) out.push_back(decompress_bc(level, texture, format));
        return out;
    }
    const AstcContext context = astc_context(texture, 1, name);
    for (const CompressedLevel& level : levels)
        out.push_back(decompress_astc(context.get(), level, texture, name));
    return out;
}

std::vector<std::uint8_t> encode_ktx2_compressed(const std::vector<CompressedLevel>& levels,
                                                 const BlockFormat& format,
                                                 const std::string& writer, const std::string& name,
                                                 const TextureKeyValues& key_values) {
    check_compressed(levels, format, name);
    const auto level_count = std::uint32_t(levels.size());
    const std::vector<std::uint8_t> kvd =
        texture_key_value_data(writer, key_values, name, {{kKeySwizzle, format.swizzle}});
    const std::vector<std::uint8_t> dfd = encode_data_format(block_data_format(format));
    const std::uint64_t dfd_offset = kHeaderSize + kLevelIndexEntrySize * level_count;
    const std::uint64_t kvd_offset = dfd_offset + dfd.size();
    // Levels from the smallest to the largest, each aligned to lcm(block bytes, 4).
    std::vector<std::uint64_t> offsets(level_count);
    std::uint64_t end = kvd_offset + kvd.size();
    for (std::uint32_t l = level_count; l-- > 0;) {
        end = align_up(end, std::uint64_t(format.block_bytes));
        offsets[l] = end;
        end += levels[l].blocks.size();
    }
    std::vector<std::uint8_t> bytes(kIdentifier.begin(), kIdentifier.end());
    append_u32_le(bytes, format.vk_format);
    append_u32_le(bytes, 1);  // typeSize of block-compressed formats
    append_u32_le(bytes, std::uint32_t(levels.front().width));
    append_u32_le(bytes, std::uint32_t(levels.front().height));
    append_u32_le(bytes, 0);  // pixelDepth
    append_u32_le(bytes, 0);  // layerCount
    append_u32_le(bytes, 1);  // faceCount
    append_u32_le(bytes, level_count);
    append_u32_le(bytes, kSchemeNone);
    append_u32_le(bytes, std::uint32_t(dfd_offset));
    append_u32_le(bytes, std::uint32_t(dfd.size()));
    append_u32_le(bytes, std::uint32_t(kvd_offset));
    append_u32_le(bytes, std::uint32_t(kvd.size()));
    append_u64_le(bytes, 0);
    append_u64_le(bytes, 0);
    for (std::uint32_t l = 0; l < level_count; ++l) {
        append_u64_le(bytes, offsets[l]);
        append_u64_le(bytes, levels[l].blocks.size());
        append_u64_le(bytes, levels[l].blocks.size());
    }
    bytes.insert(bytes.end(), dfd.begin(), dfd.end());
    bytes.insert(bytes.end(), kvd.begin(), kvd.end());
    bytes.resize(std::size_t(end), 0);
    for (std::uint32_t l = 0; l < level_count; ++l)
        std::copy(levels[l].blocks.begin(), levels[l].blocks.end(),
                  bytes.begin() + std::ptrdiff_t(offsets[l]));
    return bytes;
}

void write_ktx2_compressed(const std::string& path, const std::vector<CompressedLevel>& levels,
                           const BlockFormat& format, const std::string& writer,
                           const WriteOptions& options, const TextureKeyValues& key_values) {
    write_file_atomically(path, encode_ktx2_compressed(levels, format, writer, path, key_values), options);
}

std::vector<CompressedLevel> read_ktx2_compressed(const std::string& path,
                                                  const BlockFormat& format) {
    std::vector<CompressedLevel> levels;
    for (TextureLevelData& level : read_plain_2d_levels(path, format.vk_format, format.name,
                                                        block_bytes_of(format), blocks_unit(format)))
        levels.push_back({level.width, level.height, std::move(level.bytes)});
    return levels;
}

void write_dds_compressed(const std::string& path, const std::vector<CompressedLevel>& levels,
                          const BlockFormat& format, const WriteOptions& options) {
    if (format.dxgi_format == 0)
        throw Error(path, std::string("DDS has no ") + format.name +
                              " format (write ASTC textures as KTX2)");
    check_compressed(levels, format, path);
    std::vector<std::uint8_t> bytes =
        dds_head(format.dxgi_format, levels.front().width, levels.front().height, levels.size(),
                 true, levels.front().blocks.size());
    for (const CompressedLevel& level : levels)
        bytes.insert(bytes.end(), level.blocks.begin(), level.blocks.end());
    write_file_atomically(path, bytes, options);
}

void write_dds_rgba8(const std::string& path, const std::vector<Rgba8Level>& levels,
                     const WriteOptions& options) {
    if (levels.empty()) throw Error(path, "a texture needs at least one level");
    for (std::size_t l = 0; l < levels.size(); ++l) check_level(levels[l], l, path);
    std::vector<std::uint8_t> bytes =
        dds_head(kDxgiR8G8B8A8Unorm, levels.front().width, levels.front().height, levels.size(),
                 false, std::uint64_t(levels.front().width) * 4);
    for (const Rgba8Level& level : levels)
        bytes.insert(bytes.end(), level.texels.begin(), level.texels.end());
    write_file_atomically(path, bytes, options);
}

DdsFile read_dds(const std::string& path) {
    const detail::InputFile file(path);
    if (file.size() < kDdsHeadSize) throw Error(path, "truncated DDS header");
    std::array<std::uint8_t, kDdsHeadSize> head{};
    file.read_at(0, head.data(), head.size(), "truncated DDS header");
    const auto u32 = [&](std::size_t offset) { return load_u32_le(head.data() + offset); };
    if (u32(0) != kDdsMagic || u32(4) != 124) throw Error(path, "not a DDS file");
    if (u32(4 + 80) != kDdsFourCcDx10) throw Error(path, "DDS file without a DX10 header");
    const std::uint32_t height = u32(12), width = u32(16), level_count = u32(28);
    DdsFile dds;
    dds.dxgi_format = u32(128);
    if (width < 1 || height < 1 || width > 65536 || height > 65536 || level_count < 1 ||
        level_count > kMaxLevelCount)
        throw Error(path, "DDS size or level count out of range");
    // Bytes per 4x4 block (compressed) or per texel (RGBA8).
    std::size_t unit = 0;
    int block = 4;
    switch (dds.dxgi_format) {
        case kDxgiBc1Unorm:
        case kDxgiBc4Unorm: unit = 8; break;
        case kDxgiBc5Unorm: unit = 16; break;
        case kDxgiR8G8B8A8Unorm: unit = 4, block = 1; break;
        default: throw Error(path, "unsupported DXGI format " + std::to_string(dds.dxgi_format));
    }
    std::uint64_t offset = kDdsHeadSize;
    int w = int(width), h = int(height);
    for (std::uint32_t l = 0; l < level_count; ++l) {
        const std::size_t size =
            std::size_t(blocks_across(w, block)) * std::size_t(blocks_across(h, block)) * unit;
        if (!inside(offset, size, file.size()))
            throw Error(path, "truncated in level " + std::to_string(l));
        CompressedLevel level{w, h, std::vector<std::uint8_t>(size)};
        file.read_at(offset, level.blocks.data(), size, "truncated in level " + std::to_string(l));
        offset += size;
        dds.levels.push_back(std::move(level));
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
    if (offset != file.size())
        throw Error(path, std::to_string(file.size() - offset) + " bytes after the last level");
    return dds;
}

}  // namespace leanfade::io
