// Block-compressed engine textures (leanfade/io/detail/block_compression.hpp): every level of the
// roughness, normal and anisotropy MIPs of a bake compressed to BC4/BC5/BC1 (libsquish) and ASTC
// 4x4 (libastcenc) decodes within the stated error of the uncompressed level (docs/compression.md);
// the bytes do not depend on the thread count; the KTX2 and DDS files carry the format and every
// level and read back block for block; damaged files are refused with the file's name.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/io/detail/block_compression.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade::io {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// The engine textures of a bumpy 256² height field with a base roughness (every level).
const RoughnessTexturesRgba8& engine_textures() {
    static const RoughnessTexturesRgba8 textures = [] {
        BakeOptions options;
        const LeanMap map =
            bake_lean_map(make_builtin_height("bumps", 256, 3), BakeSource::Height, options).map;
        RoughnessOptions roughness;
        roughness.base_roughness = 0.3f;
        return roughness_textures_rgba8(map, roughness, nullptr);
    }();
    return textures;
}

const std::vector<Rgba8Image>& levels_of(EngineTexture texture) {
    switch (texture) {
        case EngineTexture::Roughness: return engine_textures().metallic_roughness;
        case EngineTexture::Normal: return engine_textures().normal;
        case EngineTexture::Anisotropy: return engine_textures().anisotropy;
    }
    return engine_textures().normal;
}

// Errors of a decoded level against the uncompressed one: the RMS and largest difference of the
// channels the texture's format keeps, in 8-bit codes, and for normals the angle in degrees.
struct LevelError {
    double rms_codes = 0.0;
    int max_codes = 0;
    double mean_degrees = 0.0;
    double max_degrees = 0.0;
};

glm::vec3 decode_normal(const std::uint8_t* t) {
    return glm::normalize(glm::vec3(t[0], t[1], t[2]) / 255.0f * 2.0f - 1.0f);
}

LevelError level_error(const Rgba8Image& want, const Rgba8Image& got, EngineTexture texture) {
    LevelError e;
    double sum = 0.0, angle_sum = 0.0;
    std::size_t count = 0;
    const std::size_t texels = std::size_t(want.width) * want.height;
    for (std::size_t t = 0; t < texels; ++t) {
        const std::uint8_t* w = &want.texels[4 * t];
        const std::uint8_t* g = &got.texels[4 * t];
        if (texture == EngineTexture::Anisotropy) {
            // The anisotropy as an axis: strength (B, in codes) times the doubled direction angle
            // of RG (the directions d and -d are the same anisotropy; where the strength is 0 the
            // direction does not matter).
            const auto axis = [](const std::uint8_t* t) {
                const double angle = 2.0 * std::atan2(2.0 * t[1] / 255.0 - 1.0, 2.0 * t[0] / 255.0 - 1.0);
                return std::pair{t[2] * std::cos(angle), t[2] * std::sin(angle)};
            };
            const auto [wx, wy] = axis(w);
            const auto [gx, gy] = axis(g);
            const double d = std::hypot(wx - gx, wy - gy);
            sum += d * d;
            e.max_codes = std::max(e.max_codes, int(std::lround(d)));
            ++count;
            continue;
        }
        // BC4 keeps roughness (G) only; the normals' x and y are stored (z is derived).
        const int first = texture == EngineTexture::Roughness ? 1 : 0;
        for (int c = first; c < 2; ++c) {
            const int d = int(w[c]) - int(g[c]);
            sum += double(d) * d;
            e.max_codes = std::max(e.max_codes, std::abs(d));
            ++count;
        }
        if (texture == EngineTexture::Normal) {
            const double cosine =
                std::clamp(double(glm::dot(decode_normal(w), decode_normal(g))), -1.0, 1.0);
            const double degrees = std::acos(cosine) * 180.0 / 3.14159265358979;
            angle_sum += degrees;
            e.max_degrees = std::max(e.max_degrees, degrees);
        }
    }
    e.rms_codes = std::sqrt(sum / double(count));
    e.mean_degrees = angle_sum / double(texels);
    return e;
}

struct Tolerance {
    BlockCompression compression;
    EngineTexture texture;
    double rms_codes;     // every level
    double mean_degrees;  // normals: every level
};

// The stated errors (docs/compression.md): the largest over the levels of this map (the printed
// figures) with a margin of about 1.3x. The anisotropy texture's are large: from level 1 on its
// direction changes from texel to texel, which a block's two endpoints cannot follow (the error is
// that of the anisotropy as an axis, strength times the doubled angle, in codes of strength).
const Tolerance kTolerances[] = {
    {BlockCompression::Bc, EngineTexture::Roughness, 4.5, 0.0},
    {BlockCompression::Bc, EngineTexture::Normal, 3.5, 1.8},
    {BlockCompression::Bc, EngineTexture::Anisotropy, 75.0, 0.0},
    {BlockCompression::Astc, EngineTexture::Roughness, 2.0, 0.0},
    {BlockCompression::Astc, EngineTexture::Normal, 3.8, 1.8},
    {BlockCompression::Astc, EngineTexture::Anisotropy, 42.0, 0.0},
};

TEST(BlockCompression, EveryLevelDecodesWithinTheStatedError) {
    for (const Tolerance& tolerance : kTolerances) {
        const std::vector<Rgba8Image>& levels = levels_of(tolerance.texture);
        const std::vector<CompressedLevel> compressed =
            compress_levels(levels, tolerance.compression, tolerance.texture, 2);
        const BlockFormat& format = block_format(tolerance.compression, tolerance.texture);
        ASSERT_EQ(compressed.size(), levels.size());
        const std::vector<Rgba8Image> decoded =
            decompress_levels(compressed, tolerance.compression, tolerance.texture);
        for (std::size_t l = 0; l < levels.size(); ++l) {
            const int bw = (levels[l].width + 3) / 4, bh = (levels[l].height + 3) / 4;
            EXPECT_EQ(compressed[l].blocks.size(), std::size_t(bw * bh * format.block_bytes));
            const LevelError e = level_error(levels[l], decoded[l], tolerance.texture);
            std::printf("%-4s %-10s level %2zu (%4dx%-4d): rms %.2f codes, max %3d codes, "
                        "normal %.2f deg mean, %.2f deg max\n",
                        to_string(tolerance.compression), to_string(tolerance.texture), l,
                        levels[l].width, levels[l].height, e.rms_codes, e.max_codes,
                        e.mean_degrees, e.max_degrees);
            EXPECT_LE(e.rms_codes, tolerance.rms_codes)
                << to_string(tolerance.compression) << " " << to_string(tolerance.texture)
                << " level " << l;
            if (tolerance.texture == EngineTexture::Normal) {
                EXPECT_LE(e.mean_degrees, tolerance.mean_degrees)
                    << to_string(tolerance.compression) << " level " << l;
            }
        }
    }
}

TEST(BlockCompression, TheSameBytesForAnyThreadCount) {
    for (BlockCompression compression : {BlockCompression::Bc, BlockCompression::Astc}) {
        const std::vector<Rgba8Image>& levels = levels_of(EngineTexture::Normal);
        const auto one = compress_levels(levels, compression, EngineTexture::Normal, 1);
        const auto three = compress_levels(levels, compression, EngineTexture::Normal, 3);
        for (std::size_t l = 0; l < levels.size(); ++l)
            EXPECT_EQ(one[l].blocks, three[l].blocks) << to_string(compression) << " level " << l;
    }
}

// A level whose sides are not multiples of 4 (the partial blocks of the edges) decodes in place.
TEST(BlockCompression, PartialBlocksAtTheEdges) {
    Rgba8Image level{6, 5, {}};
    for (int i = 0; i < 6 * 5; ++i) {
        const std::uint8_t v = std::uint8_t(40 * (i % 6) + 7 * (i / 6));
        level.texels.insert(level.texels.end(), {255, v, 0, 255});
    }
    for (BlockCompression compression : {BlockCompression::Bc, BlockCompression::Astc}) {
        const auto compressed =
            compress_levels({level}, compression, EngineTexture::Roughness, 1);
        EXPECT_EQ(compressed[0].blocks.size(),
                  std::size_t(2 * 2 * block_format(compression, EngineTexture::Roughness).block_bytes));
        const auto decoded = decompress_levels(compressed, compression, EngineTexture::Roughness);
        EXPECT_LE(level_error(level, decoded[0], EngineTexture::Roughness).max_codes, 8)
            << to_string(compression);
    }
}

TEST(BlockCompression, Ktx2FileCarriesTheFormatAndEveryLevel) {
    const fs::path dir = ::leanfade::test::fresh_scratch_folder("io", "block_ktx2");
    const std::vector<Rgba8Image>& levels = levels_of(EngineTexture::Normal);
    for (BlockCompression compression : {BlockCompression::Bc, BlockCompression::Astc}) {
        const BlockFormat& format = block_format(compression, EngineTexture::Normal);
        const auto compressed = compress_levels(levels, compression, EngineTexture::Normal, 2);
        const std::string path = (dir / (std::string(to_string(compression)) + ".ktx2")).string();
        write_ktx2_compressed(path, compressed, format, "leanfade test", {},
                              {{kKeyTextureContent, "normal v1"}});
        const Ktx2Info info = inspect_ktx2(path);
        EXPECT_EQ(info.vk_format, compression == BlockCompression::Bc ? 141u : 157u);
        EXPECT_EQ(info.level_count, levels.size());
        EXPECT_EQ(info.data_format.color_model, compression == BlockCompression::Bc ? 132u : 162u);
        EXPECT_EQ(info.data_format.texel_block_dimensions[0], 3u);
        EXPECT_EQ(info.data_format.bytes_plane[0], std::uint32_t(format.block_bytes));
        EXPECT_EQ(info.data_format.transfer_function, 1u);
        ASSERT_NE(info.find("KTXswizzle"), nullptr);
        EXPECT_EQ(*info.find("KTXswizzle"), compression == BlockCompression::Bc ? "rg01" : "ra01");
        const auto back = read_ktx2_compressed(path, format);
        ASSERT_EQ(back.size(), compressed.size());
        for (std::size_t l = 0; l < back.size(); ++l) EXPECT_EQ(back[l].blocks, compressed[l].blocks);
        // Another format is refused by name.
        EXPECT_THROW(
            read_ktx2_compressed(path, block_format(BlockCompression::Bc, EngineTexture::Roughness)),
            Error);
    }
}

TEST(BlockCompression, DdsFileCarriesTheFormatAndEveryLevel) {
    const fs::path dir = ::leanfade::test::fresh_scratch_folder("io", "block_dds");
    const struct {
        EngineTexture texture;
        std::uint32_t dxgi;
    } cases[] = {{EngineTexture::Roughness, 80}, {EngineTexture::Normal, 83},
                 {EngineTexture::Anisotropy, 71}};
    for (const auto& c : cases) {
        const auto compressed = compress_levels(levels_of(c.texture), BlockCompression::Bc, c.texture, 2);
        const std::string path = (dir / (std::string(to_string(c.texture)) + ".dds")).string();
        write_dds_compressed(path, compressed, block_format(BlockCompression::Bc, c.texture));
        const DdsFile dds = read_dds(path);
        EXPECT_EQ(dds.dxgi_format, c.dxgi);
        ASSERT_EQ(dds.levels.size(), compressed.size());
        for (std::size_t l = 0; l < compressed.size(); ++l)
            EXPECT_EQ(dds.levels[l].blocks, compressed[l].blocks);
        // 4 + 124 + 20 header bytes, then the levels back to back.
        std::size_t bytes = 148;
        for (const auto& level : compressed) bytes += level.blocks.size();
        EXPECT_EQ(fs::file_size(path), bytes);
    }
    const std::string rgba = (dir / "rgba8.dds").string();
    write_dds_rgba8(rgba, levels_of(EngineTexture::Roughness));
    const DdsFile dds = read_dds(rgba);
    EXPECT_EQ(dds.dxgi_format, 28u);
    EXPECT_EQ(dds.levels[0].blocks, levels_of(EngineTexture::Roughness)[0].texels);
    // DDS has no ASTC.
    const auto astc = compress_levels(levels_of(EngineTexture::Normal), BlockCompression::Astc,
                                      EngineTexture::Normal, 2);
    try {
        write_dds_compressed((dir / "astc.dds").string(), astc,
                             block_format(BlockCompression::Astc, EngineTexture::Normal));
        ADD_FAILURE() << "ASTC written as DDS";
    } catch (const Error& e) {
        EXPECT_THAT(e.what(), HasSubstr("DDS has no ASTC_4x4_UNORM"));
    }
    EXPECT_FALSE(fs::exists(dir / "astc.dds"));
}

// OpenImageIO's DDS reader (an independent BC decoder) reads level 0 of the files as our decoder
// does: the container and the blocks are what a DDS importer expects.
TEST(BlockCompression, DdsLevelZeroReadsTheSameThroughOpenImageIO) {
    const fs::path dir = ::leanfade::test::fresh_scratch_folder("io", "block_dds_oiio");
    for (const EngineTexture texture : {EngineTexture::Roughness, EngineTexture::Normal}) {
        const auto compressed = compress_levels(levels_of(texture), BlockCompression::Bc, texture, 2);
        const std::string path = (dir / (std::string(to_string(texture)) + ".dds")).string();
        write_dds_compressed(path, compressed, block_format(BlockCompression::Bc, texture));
        const Rgba8Image ours = decompress_levels(compressed, BlockCompression::Bc, texture)[0];
        const Image theirs = read_image(path);
        ASSERT_EQ(theirs.width, ours.width);
        ASSERT_EQ(theirs.height, ours.height);
        // BC4: one channel (our roughness G); BC5: x, y in the first two.
        int largest = 0;
        for (int t = 0; t < theirs.width * theirs.height; ++t) {
            for (int c = 0; c < (texture == EngineTexture::Normal ? 2 : 1); ++c) {
                const int code = int(std::lround(theirs.pixels[std::size_t(t * theirs.channels + c)] * 255.0f));
                const int want = ours.texels[std::size_t(4 * t + (texture == EngineTexture::Normal ? c : 1))];
                largest = std::max(largest, std::abs(code - want));
            }
        }
        EXPECT_LE(largest, 1) << to_string(texture) << " (" << theirs.channels << " channels)";
    }
}

TEST(BlockCompression, DamagedDdsRefusedWithItsName) {
    const fs::path dir = ::leanfade::test::fresh_scratch_folder("io", "block_dds_damaged");
    const auto compressed = compress_levels(levels_of(EngineTexture::Normal), BlockCompression::Bc,
                                            EngineTexture::Normal, 2);
    const std::string path = (dir / "n.dds").string();
    write_dds_compressed(path, compressed, block_format(BlockCompression::Bc, EngineTexture::Normal));
    const auto size = fs::file_size(path);
    for (const std::uintmax_t cut : {std::uintmax_t(10), std::uintmax_t(200), size - 1}) {
        fs::copy_file(path, path + ".cut", fs::copy_options::overwrite_existing);
        fs::resize_file(path + ".cut", cut);
        try {
            read_dds(path + ".cut");
            ADD_FAILURE() << "a DDS file cut to " << cut << " bytes was read";
        } catch (const Error& e) {
            EXPECT_THAT(e.what(), HasSubstr("n.dds.cut"));
            EXPECT_THAT(e.what(), HasSubstr("truncated"));
        }
    }
    // A huge declared size is refused before any level is allocated.
    {
        std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(12);
        const std::uint32_t huge = 0x7FFFFFFF;
        f.write(reinterpret_cast<const char*>(&huge), 4);
    }
    EXPECT_THROW(read_dds(path), Error);
}

TEST(BlockCompression, NamesAndFormats) {
    EXPECT_EQ(block_compression_names().size(), 4u);
    EXPECT_STREQ(to_string(BlockCompression::Basis), "basis");
    EXPECT_EQ(block_format(BlockCompression::Bc, EngineTexture::Roughness).vk_format, 139u);
    EXPECT_EQ(block_format(BlockCompression::Bc, EngineTexture::Normal).vk_format, 141u);
    EXPECT_EQ(block_format(BlockCompression::Bc, EngineTexture::Anisotropy).vk_format, 131u);
    EXPECT_EQ(block_format(BlockCompression::Astc, EngineTexture::Normal).vk_format, 157u);
    EXPECT_THROW(block_format(BlockCompression::None, EngineTexture::Normal), Error);
    // Basis Universal has no fixed block format: write_ktx2_uastc writes it.
    EXPECT_THROW(block_format(BlockCompression::Basis, EngineTexture::Normal), Error);
    EXPECT_THROW(compress_levels({}, BlockCompression::Basis, EngineTexture::Normal), Error);
}

}  // namespace
}  // namespace leanfade::io
