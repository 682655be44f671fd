// Plain 2D KTX2 textures (leanfade/io/detail/ktx2_texture.hpp): RGBA8 and RGBA half floats written with
// every level, their key/values sorted after KTXorientation and KTXwriter, read back texel for
// texel (half floats: the nearest half of each value); broken chains, values a half cannot hold
// and reserved or repeated keys are refused with the file's name.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <glm/gtc/packing.hpp>

#include "leanfade/core/error.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade::io {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// A full chain of 4-channel images from `w` x `h` down to 1 x 1, texels varying in sign and size.
std::vector<Image> float_chain(int w, int h) {
    std::vector<Image> levels;
    for (int level = 0;; ++level) {
        Image image(w, h, 4);
        for (std::size_t i = 0; i < image.pixels.size(); ++i)
            image.pixels[i] = std::sin(0.37f * float(i) + float(level)) * (1.0f + float(i % 7));
        levels.push_back(std::move(image));
        if (w == 1 && h == 1) break;
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
    return levels;
}

TEST(Ktx2Texture, HalfFloatLevelsReadBackAsTheNearestHalves) {
    const fs::path dir = ::leanfade::test::fresh_scratch_folder("io", "ktx2_texture_half");
    const std::vector<Image> levels = float_chain(8, 4);
    const std::string path = (dir / "t.ktx2").string();
    write_ktx2_rgba16f(path, levels, "leanfade test", {}, {{kKeyTextureContent, "plateau v1"}});
    const std::vector<Image> back = read_ktx2_rgba16f(path);
    ASSERT_EQ(back.size(), levels.size());
    for (std::size_t l = 0; l < levels.size(); ++l) {
        ASSERT_EQ(back[l].width, levels[l].width);
        ASSERT_EQ(back[l].height, levels[l].height);
        for (std::size_t i = 0; i < levels[l].pixels.size(); ++i)
            EXPECT_EQ(back[l].pixels[i],
                      glm::unpackHalf1x16(glm::packHalf1x16(levels[l].pixels[i])))
                << "level " << l << " value " << i;
    }
    const Ktx2Info info = inspect_ktx2(path);
    EXPECT_EQ(info.vk_format, kVkFormatR16G16B16A16Sfloat);
    EXPECT_EQ(info.layer_count, 0u);
    EXPECT_EQ(info.level_count, 4u);
    ASSERT_EQ(info.key_values.size(), 3u);
    EXPECT_EQ(info.key_values[0].first, "KTXorientation");
    EXPECT_EQ(info.key_values[1].first, "KTXwriter");
    EXPECT_EQ(info.key_values[2], std::make_pair(std::string(kKeyTextureContent),
                                                 std::string("plateau v1")));
    // Each level 8-byte aligned (lcm of the texel size and 4).
    for (const Ktx2Level& level : info.levels) EXPECT_EQ(level.byte_offset % 8, 0u);
    // An RGBA8 reader refuses it by its format.
    try {
        read_ktx2_rgba8(path);
        FAIL() << "read as RGBA8";
    } catch (const Error& e) {
        EXPECT_THAT(e.what(), HasSubstr("R16G16B16A16_SFLOAT"));
    }
}

TEST(Ktx2Texture, Rgba8KeysAreWrittenSortedAfterTheKtxKeys) {
    std::vector<Rgba8Level> levels;
    levels.push_back({2, 2, std::vector<std::uint8_t>(16, 7)});
    levels.push_back({1, 1, std::vector<std::uint8_t>(4, 9)});
    const std::vector<std::uint8_t> bytes =
        encode_ktx2_rgba8(levels, "w", "t", {{"LEANFADEz", "1"}, {kKeyTextureContent, "roughness v1"}});
    const Ktx2Info info = inspect_ktx2_from_memory(bytes, "t");
    ASSERT_EQ(info.key_values.size(), 4u);
    EXPECT_EQ(info.key_values[2].first, kKeyTextureContent);
    EXPECT_EQ(info.key_values[3].first, "LEANFADEz");
}

// The in-place writer (the engine textures of `leanfade bake`) writes the bytes of
// write_ktx2_rgba8 once every level is filled, for square, wide and one-texel chains, and leaves
// nothing behind without commit().
TEST(Ktx2Texture, InPlaceRgba8WriterWritesTheSameFile) {
    const fs::path dir = ::leanfade::test::fresh_scratch_folder("io", "ktx2_texture_in_place");
    for (const auto& [w, h] : {std::pair{8, 8}, std::pair{13, 3}, std::pair{1, 1}}) {
        std::vector<Rgba8Level> levels;
        for (int lw = w, lh = h;; lw = std::max(1, lw / 2), lh = std::max(1, lh / 2)) {
            Rgba8Level level{lw, lh, std::vector<std::uint8_t>(std::size_t(lw * lh * 4))};
            for (std::size_t i = 0; i < level.texels.size(); ++i)
                level.texels[i] = std::uint8_t(i * 31 + std::size_t(lw));
            levels.push_back(std::move(level));
            if (lw == 1 && lh == 1) break;
        }
        const TextureKeyValues keys{{kKeyTextureContent, "roughness v1"}};
        const std::string whole = (dir / "whole.ktx2").string();
        const std::string in_place = (dir / "in_place.ktx2").string();
        write_ktx2_rgba8(whole, levels, "w", {}, keys);
        {
            Ktx2Rgba8Writer abandoned((dir / "abandoned.ktx2").string(), w, h, "w", keys);
        }
        Ktx2Rgba8Writer writer(in_place, w, h, "w", keys);
        ASSERT_EQ(writer.levels().size(), levels.size());
        for (std::size_t l = 0; l < levels.size(); ++l)
            std::copy(levels[l].texels.begin(), levels[l].texels.end(), writer.levels()[l]);
        writer.commit();
        const auto bytes_of = [](const std::string& path) {
            std::ifstream in(path, std::ios::binary);
            return std::vector<char>(std::istreambuf_iterator<char>(in), {});
        };
        EXPECT_EQ(bytes_of(in_place), bytes_of(whole)) << w << "x" << h;
        EXPECT_FALSE(fs::exists(dir / "abandoned.ktx2"));
    }
    EXPECT_THROW(Ktx2Rgba8Writer((dir / "zero.ktx2").string(), 0, 4, "w"), Error);
    EXPECT_FALSE(fs::exists(dir / "zero.ktx2"));
}

TEST(Ktx2Texture, RefusesWhatItCannotWriteNamingTheFile) {
    const auto refused = [](const std::vector<Image>& levels, const TextureKeyValues& keys,
                            const std::string& cause) {
        try {
            encode_ktx2_rgba16f(levels, "w", "out.ktx2", keys);
            ADD_FAILURE() << "written: " << cause;
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), "out.ktx2");
            EXPECT_THAT(e.cause(), HasSubstr(cause));
        }
    };
    std::vector<Image> chain = float_chain(4, 4);
    refused({}, {}, "at least one level");
    refused({chain[0]}, {}, "down to 1x1");
    std::vector<Image> three_channels = chain;
    three_channels[1] = Image(2, 2, 3);
    refused(three_channels, {}, "4 channels");
    std::vector<Image> huge = chain;
    huge[0].pixels[3] = 70000.0f;
    refused(huge, {}, "cannot store");
    std::vector<Image> nan = chain;
    nan[2].pixels[0] = std::nanf("");
    refused(nan, {}, "cannot store");
    refused(chain, {{"KTXwriter", "x"}}, "reserved");
    refused(chain, {{"LEANFADEa", "1"}, {"LEANFADEa", "2"}}, "twice");
}

}  // namespace
}  // namespace leanfade::io
