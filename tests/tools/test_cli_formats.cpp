// `leanfade bake` on every image format it reads: JPEG, TGA, DDS (BC5 and DXT5nm two-channel
// normal maps), 16-bit TIFF, PSD, BMP and OpenEXR with DWAA / B44 compression. Lossless formats
// give the very bytes of the same map baked from a PNG; grey colour images are baked as height
// maps under --from auto (and the summary says so); hostile files fail on one line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../io/format_writers.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/io/image_io.hpp"
#include "tools_test_helpers.hpp"

using namespace leanfade;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace {

std::vector<std::uint8_t> file_bytes(const fs::path& path) {
    const std::string text = test::read_text(path);
    return std::vector<std::uint8_t>(text.begin(), text.end());
}

void put_bytes(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// A tangent-space normal map of gentle bumps, encoded 0.5 n + 0.5 and quantised to `levels`
// (255 or 65535) so that integer formats hold it exactly.
Image normal_map(int size, float levels) {
    Image map(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float u = 6.2831853f * float(x) / float(size);
            const float v = 6.2831853f * float(y) / float(size);
            float nx = 0.3f * std::cos(u) * std::sin(v), ny = 0.25f * std::sin(2.0f * v);
            const float nz = std::sqrt(1.0f - nx * nx - ny * ny);
            const float encoded[3] = {0.5f * nx + 0.5f, 0.5f * ny + 0.5f, 0.5f * nz + 0.5f};
            for (int c = 0; c < 3; ++c) map.at(x, y, c) = std::round(encoded[c] * levels) / levels;
        }
    return map;
}

std::string q(const fs::path& path) {
    return test::shell_quote(path.string());
}

struct Baked {
    test::RunResult run;
    std::vector<std::uint8_t> map;  // the .ktx2
};

Baked bake(const fs::path& input, const fs::path& scratch, const std::string& flags = "",
           const std::string& output_suffix = ".ktx2") {
    const fs::path output = input.string() + output_suffix;
    Baked baked{test::run_leanfade("bake " + q(input) + " -o " + q(output) + " " + flags, scratch),
                {}};
    if (fs::exists(output)) baked.map = file_bytes(output);
    return baked;
}

}  // namespace

TEST(CliFormats, LosslessFormatsBakeTheSameMapAsPng) {
    const fs::path dir = test::scratch_dir("cli_formats_lossless");
    const Image map8 = normal_map(32, 255.0f), map16 = normal_map(32, 65535.0f);
    io::write_png((dir / "ref8.png").string(), map8, 8);
    io::write_png((dir / "ref16.png").string(), map16, 16);
    const Baked ref8 = bake(dir / "ref8.png", dir), ref16 = bake(dir / "ref16.png", dir);
    ASSERT_EQ(ref8.run.exit_code, 0) << ref8.run.err;
    ASSERT_EQ(ref16.run.exit_code, 0) << ref16.run.err;

    io::test::write_with_openimageio((dir / "map.tga").string(), "tga", map8, OIIO::TypeDesc::UINT8,
                                     {{"compression", "rle"}});
    io::test::write_with_openimageio((dir / "map.bmp").string(), "bmp", map8,
                                     OIIO::TypeDesc::UINT8);
    io::test::write_with_openimageio((dir / "map8.tif").string(), "tif", map8,
                                     OIIO::TypeDesc::UINT8);
    io::test::write_with_openimageio((dir / "map16.tif").string(), "tif", map16,
                                     OIIO::TypeDesc::UINT16, {{"compression", "zip"}});
    put_bytes(dir / "map8.psd", io::test::psd_file(map8, 8));
    put_bytes(dir / "map16.psd", io::test::psd_file(map16, 16));
    for (const char* name : {"map.tga", "map.bmp", "map8.tif", "map8.psd"}) {
        SCOPED_TRACE(name);
        const Baked baked = bake(dir / name, dir);
        ASSERT_EQ(baked.run.exit_code, 0) << baked.run.err;
        EXPECT_THAT(baked.run.out, HasSubstr("normal map"));
        EXPECT_TRUE(baked.map == ref8.map) << "differs from the 8-bit PNG's map";
    }
    for (const char* name : {"map16.tif", "map16.psd"}) {
        SCOPED_TRACE(name);
        const Baked baked = bake(dir / name, dir);
        ASSERT_EQ(baked.run.exit_code, 0) << baked.run.err;
        EXPECT_TRUE(baked.map == ref16.map) << "differs from the 16-bit PNG's map";
    }
}

TEST(CliFormats, LossyFormatsAndCompressedNormalMapsBake) {
    const fs::path dir = test::scratch_dir("cli_formats_lossy");
    const Image map = normal_map(32, 255.0f);
    io::test::write_with_openimageio((dir / "map.jpg").string(), "jpg", map, OIIO::TypeDesc::UINT8,
                                     {{"quality", "95"}});
    for (const char* compression : {"dwaa", "b44"}) {
        io::test::write_with_openimageio((dir / (std::string(compression) + ".exr")).string(),
                                         "exr", map, OIIO::TypeDesc::HALF,
                                         {{"compression", compression}});
    }
    // BC5 and DXT5nm of a 4x4-block normal map: x and y per block, z reconstructed.
    std::vector<std::uint8_t> bc5, dxt5nm;
    const std::vector<int> stripes{0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 1, 1, 1, 1};
    for (int block = 0; block < 64; ++block) {  // 32 x 32 texels
        const auto x0 = std::uint8_t(100 + block), y0 = std::uint8_t(150 - block);
        io::test::append_bc4_block(bc5, x0, 128, stripes);
        io::test::append_bc4_block(bc5, y0, 128, stripes);
        io::test::append_bc4_block(dxt5nm, x0, 128, stripes);  // x in alpha
        // R = 1 and B = 0 everywhere (the swizzle's constants); y in G (40 / 63 and 24 / 63).
        io::test::append_bc1_block(dxt5nm, 0xF800 | (40 << 5), 0xF800 | (24 << 5), stripes);
    }
    put_bytes(dir / "bc5.dds", io::test::dds_file(32, 32, "ATI2", io::test::kDdsFourCcFlag, bc5));
    put_bytes(dir / "nm.dds", io::test::dds_file(32, 32, "DXT5", io::test::kDdsFourCcFlag, dxt5nm));
    for (const char* name : {"map.jpg", "dwaa.exr", "b44.exr", "bc5.dds", "nm.dds"}) {
        SCOPED_TRACE(name);
        const Baked baked =
            bake(dir / name, dir, "--json " + q(dir / (std::string(name) + ".json")));
        ASSERT_EQ(baked.run.exit_code, 0) << baked.run.err;
        EXPECT_THAT(baked.run.out, HasSubstr("32x32, 6 levels, normal map"));
        EXPECT_FALSE(baked.map.empty());
        // Two-channel maps with z reconstructed: no normal was below the horizon.
        EXPECT_THAT(baked.run.out, ::testing::Not(HasSubstr("were raised")));
    }
}

TEST(CliFormats, GreyColourImagesBakeAsHeightMapsUnderAuto) {
    const fs::path dir = test::scratch_dir("cli_formats_grey");
    Image height(24, 24, 1), grey(24, 24, 3);
    for (int y = 0; y < 24; ++y)
        for (int x = 0; x < 24; ++x) {
            const float h = std::round(255.0f * (0.5f + 0.3f * std::sin(0.5f * float(x)) *
                                                            std::cos(0.3f * float(y)))) /
                            255.0f;
            height.at(x, y) = h;
            for (int c = 0; c < 3; ++c) grey.at(x, y, c) = h;
        }
    io::write_png((dir / "height.png").string(), height, 8);
    io::write_png((dir / "grey_rgb.png").string(), grey, 8);
    io::test::write_with_openimageio((dir / "grey.tga").string(), "tga", grey,
                                     OIIO::TypeDesc::UINT8);
    const Baked reference = bake(dir / "height.png", dir);
    ASSERT_EQ(reference.run.exit_code, 0) << reference.run.err;
    for (const char* name : {"grey_rgb.png", "grey.tga"}) {
        SCOPED_TRACE(name);
        const fs::path json = dir / (std::string(name) + ".json");
        const Baked baked = bake(dir / name, dir, "--json " + q(json));
        ASSERT_EQ(baked.run.exit_code, 0) << baked.run.err;
        EXPECT_THAT(baked.run.out, HasSubstr("height map"));
        EXPECT_THAT(test::read_text(json), HasSubstr("\"source\": \"height\""));
        EXPECT_TRUE(baked.map == reference.map) << "differs from the grey PNG's map";
    }
    // --from normal still takes it as a normal map, and the refusal of --strict-normals says, in
    // the command line's words, what may be meant.
    const Baked forced =
        bake(dir / "grey_rgb.png", dir, "--from normal --strict-normals", ".forced.ktx2");
    EXPECT_EQ(forced.run.exit_code, 1);
    EXPECT_THAT(forced.run.err, HasSubstr("grey_rgb.png: normal with z <= 0"));
    EXPECT_THAT(forced.run.err, HasSubstr("refused by --strict-normals"));
    EXPECT_THAT(forced.run.err, HasSubstr("a height map stored as colour? read it with --from height)"));
    EXPECT_EQ(std::count(forced.run.err.begin(), forced.run.err.end(), '\n'), 1);
    EXPECT_TRUE(forced.map.empty());
}

TEST(CliFormats, HostileFilesOfTheNewFormatsFailOnOneLine) {
    const fs::path dir = test::scratch_dir("cli_formats_hostile");
    const Image map = normal_map(16, 255.0f);
    io::test::write_with_openimageio((dir / "good.jpg").string(), "jpg", map,
                                     OIIO::TypeDesc::UINT8);
    io::test::write_with_openimageio((dir / "good.tga").string(), "tga", map,
                                     OIIO::TypeDesc::UINT8);
    io::test::write_with_openimageio((dir / "good.exr").string(), "exr", map, OIIO::TypeDesc::HALF,
                                     {{"compression", "dwaa"}});
    std::vector<std::uint8_t> block;
    io::test::append_bc1_block(block, 0xFFFF, 0, std::vector<int>(16, 0));
    put_bytes(dir / "bomb.dds",
              io::test::dds_file(16384, 16384, "DXT1", io::test::kDdsFourCcFlag, block));
    for (const char* name : {"good.jpg", "good.tga", "good.exr"}) {
        std::vector<std::uint8_t> bytes = file_bytes(dir / name);
        bytes.resize(bytes.size() * 2 / 5);
        put_bytes(dir / (std::string("cut_") + name), bytes);
    }
    for (const char* name : {"cut_good.jpg", "cut_good.tga", "cut_good.exr", "bomb.dds"}) {
        SCOPED_TRACE(name);
        const auto run =
            test::run_leanfade_bounded("bake " + q(dir / name) + " -o " + q(dir / "out.ktx2"), dir);
        EXPECT_EQ(run.exit_code, 1) << run.err;
        EXPECT_THAT(run.err, HasSubstr(std::string(name) + ": "));
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
        EXPECT_FALSE(fs::exists(dir / "out.ktx2"));
        EXPECT_LT(run.max_rss_kib, leanfade::test::memory_bound_kib(200 * 1024))
            << "a small file made leanfade allocate";
    }
}
