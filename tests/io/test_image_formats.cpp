// The formats read through OpenImageIO (JPEG, TGA, DDS, TIFF, PSD, BMP, Radiance HDR, WebP, and
// OpenEXR's B44 / DWA compressions), two-channel DDS normal maps, OpenEXR normal channels
// X, Y, Z, and the guarantees of docs/robustness.md for each: size checked before decoding,
// bounded memory, one-line errors naming the file.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <cmath>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "format_writers.hpp"
#include "io_test_helpers.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/io/image_io.hpp"

using namespace leanfade;
using namespace leanfade::io;
using test::expect_error;
using test::read_bytes;
using test::scratch_folder;
using test::write_bytes;

namespace {

// Values k / 255 (exact in every 8-bit format), different per texel and channel.
Image byte_image(int width, int height, int channels) {
    Image image(width, height, channels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c)
                image.at(x, y, c) = float((x * 7 + y * 13 + c * 29 + 3) % 256) / 255.0f;
    return image;
}

// Values k / 65535, using the low byte too (a 16-bit reader that kept 8 bits fails).
Image word_image(int width, int height, int channels) {
    Image image(width, height, channels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c)
                image.at(x, y, c) = float((x * 2003 + y * 917 + c * 12345 + 77) % 65536) / 65535.0f;
    return image;
}

// Smooth values in [0.1, 0.9], for the lossy formats.
Image smooth_image(int width, int height, int channels) {
    Image image(width, height, channels);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < channels; ++c)
                image.at(x, y, c) =
                    0.5f + 0.4f * std::sin(0.11f * float(x) + 0.07f * float(y) + float(c));
    return image;
}

float largest_difference(const Image& a, const Image& b) {
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.height, b.height);
    EXPECT_EQ(a.channels, b.channels);
    if (a.pixels.size() != b.pixels.size()) return INFINITY;
    float largest = 0.0f;
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        largest = std::max(largest, std::abs(a.pixels[i] - b.pixels[i]));
    return largest;
}

Image compact_as_float(const std::variant<Image, UnormImage>& read) {
    if (const auto* unorm = std::get_if<UnormImage>(&read)) return unorm->to_float();
    return std::get<Image>(read);
}

// Truncations of a good file inside its first `data_end` bytes (the image data; the whole file
// by default): each read throws a one-line error naming the file.
void expect_truncations_refused(const std::string& folder, const std::vector<std::uint8_t>& bytes,
                                const std::string& cause, std::size_t data_end = 0) {
    if (data_end == 0) data_end = bytes.size();
    const std::string truncated = folder + "/truncated.bin";
    for (const std::size_t length :
         {std::size_t(3), std::size_t(20), data_end / 2, data_end - 10, data_end - 1}) {
        SCOPED_TRACE("truncated to " + std::to_string(length) + " of " +
                     std::to_string(bytes.size()) + " bytes");
        write_bytes(truncated, std::vector<std::uint8_t>(bytes.begin(),
                                                         bytes.begin() + std::ptrdiff_t(length)));
        expect_error([&] { read_image(truncated); }, truncated, cause);
    }
}

// Where the pixel data of a TGA 2.0 file ends: at its extension area, which the footer's first
// four bytes locate.
std::size_t targa_data_end(const std::vector<std::uint8_t>& bytes) {
    const std::size_t footer = bytes.size() - 26;
    return std::size_t(bytes[footer] | bytes[footer + 1] << 8 | bytes[footer + 2] << 16 |
                       bytes[footer + 3] << 24);
}

}  // namespace

// ---- the formats, read back ----

TEST(Formats, JpegIsReadByContentWithinItsLoss) {
    const std::string folder = scratch_folder();
    const Image rgb = smooth_image(40, 24, 3);
    const std::string path = folder + "/photo_named.png";  // a JPEG, whatever its name
    test::write_with_openimageio(path, "jpg", rgb, OIIO::TypeDesc::UINT8,
                                 {{"quality", "100"}, {"jpeg:subsampling", "4:4:4"}});
    const Image read = read_image(path);
    EXPECT_LT(largest_difference(read, rgb), 0.03f);  // JPEG at quality 100: a few 1/255
    const Image grey = smooth_image(16, 16, 1);
    test::write_with_openimageio(folder + "/grey.jpg", "jpg", grey, OIIO::TypeDesc::UINT8,
                                 {{"quality", "100"}});
    EXPECT_LT(largest_difference(read_image(folder + "/grey.jpg"), grey), 0.03f);
    expect_truncations_refused(folder, read_bytes(path), "JPEG");
}

TEST(Formats, TgaKeepsValuesAndUnpremultipliedAlphaExactly) {
    const std::string folder = scratch_folder();
    Image rgba = byte_image(13, 9, 4);
    rgba.at(2, 3, 3) = 0.0f;  // colour under zero alpha stays as stored
    for (const char* compression : {"none", "rle"}) {
        SCOPED_TRACE(compression);
        const std::string path = folder + "/map_" + compression + ".tga";
        test::write_with_openimageio(path, "tga", rgba, OIIO::TypeDesc::UINT8,
                                     {{"compression", compression}});
        EXPECT_EQ(largest_difference(read_image(path), rgba), 0.0f);
        ReadOptions opaque;
        opaque.drop_alpha = true;
        const auto compact = read_image_compact(path, opaque);
        ASSERT_TRUE(std::holds_alternative<UnormImage>(compact));
        EXPECT_EQ(std::get<UnormImage>(compact).max_value, 255);
        Image rgb(13, 9, 3);
        for (std::size_t i = 0; i < rgb.texel_count(); ++i)
            for (std::size_t c = 0; c < 3; ++c) rgb.pixels[3 * i + c] = rgba.pixels[4 * i + c];
        EXPECT_EQ(largest_difference(compact_as_float(compact), rgb), 0.0f);
        const std::vector<std::uint8_t> bytes = read_bytes(path);
        ASSERT_GT(targa_data_end(bytes), 18u + 13 * 9);
        expect_truncations_refused(folder, bytes, "TGA", targa_data_end(bytes));
    }
}

TEST(Formats, SixteenBitTiffKeepsEverySampleAndFloatTiffItsValues) {
    const std::string folder = scratch_folder();
    const Image rgb = word_image(17, 11, 3);
    const std::string path = folder + "/normals.tif";
    test::write_with_openimageio(path, "tif", rgb, OIIO::TypeDesc::UINT16,
                                 {{"compression", "zip"}});
    EXPECT_LT(largest_difference(read_image(path), rgb), 1e-7f);
    const auto compact = read_image_compact(path);
    ASSERT_TRUE(std::holds_alternative<UnormImage>(compact));
    const UnormImage& samples = std::get<UnormImage>(compact);
    EXPECT_EQ(samples.max_value, 65535);
    for (std::size_t i = 0; i < samples.samples.size(); ++i)
        ASSERT_EQ(samples.samples[i], std::uint16_t(std::lround(rgb.pixels[i] * 65535.0f))) << i;

    Image heights = smooth_image(9, 7, 1);
    heights.at(1, 1) = 37.25f;  // float TIFF: values as stored, beyond [0, 1]
    test::write_with_openimageio(folder + "/height.tif", "tif", heights, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(largest_difference(read_image(folder + "/height.tif"), heights), 0.0f);
    expect_truncations_refused(folder, read_bytes(path), "TIFF");
}

TEST(Formats, PsdCompositeIsReadAt8And16Bits) {
    const std::string folder = scratch_folder();
    const Image rgb8 = byte_image(10, 6, 3);
    write_bytes(folder + "/a.psd", test::psd_file(rgb8, 8));
    EXPECT_EQ(largest_difference(read_image(folder + "/a.psd"), rgb8), 0.0f);
    const Image rgb16 = word_image(10, 6, 3);
    write_bytes(folder + "/b.psd", test::psd_file(rgb16, 16));
    EXPECT_LT(largest_difference(read_image(folder + "/b.psd"), rgb16), 1e-7f);
    const Image grey = byte_image(5, 4, 1);
    write_bytes(folder + "/c.psd", test::psd_file(grey, 8));
    EXPECT_EQ(largest_difference(read_image(folder + "/c.psd"), grey), 0.0f);
    expect_truncations_refused(folder, read_bytes(folder + "/b.psd"), "PSD");
}

TEST(Formats, BmpHdrAndWebpAreRead) {
    const std::string folder = scratch_folder();
    const Image rgb = byte_image(12, 8, 3);
    test::write_with_openimageio(folder + "/a.bmp", "bmp", rgb, OIIO::TypeDesc::UINT8);
    EXPECT_EQ(largest_difference(read_image(folder + "/a.bmp"), rgb), 0.0f);
    const Image smooth = smooth_image(12, 8, 3);
    test::write_with_openimageio(folder + "/a.hdr", "hdr", smooth, OIIO::TypeDesc::FLOAT);
    EXPECT_LT(largest_difference(read_image(folder + "/a.hdr"), smooth), 0.01f);  // RGBE: 8 bits
    // WebP as OpenImageIO 2.4 writes it: lossy (4:2:0 chroma), so a grey picture.
    Image grey = smooth_image(12, 8, 3);
    for (std::size_t i = 0; i < grey.texel_count(); ++i)
        grey.pixels[3 * i + 1] = grey.pixels[3 * i + 2] = grey.pixels[3 * i];
    test::write_with_openimageio(folder + "/a.webp", "webp", grey, OIIO::TypeDesc::UINT8,
                                 {{"quality", "100"}});
    EXPECT_LT(largest_difference(read_image(folder + "/a.webp"), grey), 0.02f);
    expect_truncations_refused(folder, read_bytes(folder + "/a.bmp"), "BMP");
}

TEST(Formats, OpenExrOfEveryCompressionIsRead) {
    const std::string folder = scratch_folder();
    const Image rgb = smooth_image(37, 29, 3);
    // Lossless ones exactly (tinyexr), lossy ones (OpenEXR through OpenImageIO) within their loss.
    const std::vector<std::pair<std::string, float>> compressions{
        {"none", 0.0f},  {"zip", 0.0f},   {"piz", 0.0f},   {"b44", 2e-3f},
        {"b44a", 2e-3f}, {"dwaa", 0.02f}, {"dwab", 0.02f}, {"pxr24", 1e-4f}};
    for (const auto& [compression, tolerance] : compressions) {
        SCOPED_TRACE(compression);
        const std::string path = folder + "/" + compression + ".exr";
        test::write_with_openimageio(path, "exr", rgb, OIIO::TypeDesc::HALF,
                                     {{"compression", compression}});
        // half quantises by up to 2^-11 relative
        EXPECT_LE(largest_difference(read_image(path), rgb), tolerance + 5e-4f);
    }
    expect_truncations_refused(folder, read_bytes(folder + "/dwaa.exr"), "OpenEXR");
    expect_truncations_refused(folder, read_bytes(folder + "/b44.exr"), "OpenEXR");
}

TEST(Formats, OpenExrNormalChannelsXYZAreReadAsXYZ) {
    const std::string folder = scratch_folder();
    Image normal(6, 5, 3);
    for (std::size_t i = 0; i < normal.texel_count(); ++i) {
        normal.pixels[3 * i + 0] = 0.25f;  // x
        normal.pixels[3 * i + 1] = 0.5f;   // y
        normal.pixels[3 * i + 2] = 0.75f;  // z
    }
    for (const char* compression : {"zip", "dwaa"}) {
        for (const std::vector<std::string>& names :
             {std::vector<std::string>{"X", "Y", "Z"},
              std::vector<std::string>{"N.X", "N.Y", "N.Z"}}) {
            SCOPED_TRACE(std::string(compression) + " " + names[0]);
            const std::string path = folder + "/n.exr";
            // OpenEXR stores channels sorted by name: N.X, N.Y, N.Z; Y used to come first as
            // luminance, swapping x and y.
            test::write_with_openimageio(path, "exr", normal, OIIO::TypeDesc::FLOAT,
                                         {{"compression", compression}}, names);
            // (DWA compresses a channel named Y with loss, as luminance.)
            const Image read = read_image(path);
            ASSERT_EQ(read.channels, 3);
            EXPECT_FLOAT_EQ(read.at(2, 3, 0), 0.25f);
            EXPECT_NEAR(read.at(2, 3, 1), 0.5f, 2e-3f);
            EXPECT_FLOAT_EQ(read.at(2, 3, 2), 0.75f);
        }
    }
    // Y alone (or with A) is still luminance.
    test::write_with_openimageio(folder + "/y.exr", "exr", smooth_image(4, 4, 1),
                                 OIIO::TypeDesc::FLOAT, {{"compression", "zip"}}, {"Y"});
    EXPECT_EQ(read_image(folder + "/y.exr").channels, 1);
}

// ---- DDS ----

namespace {

// Texel i of a 4x4 block takes endpoint 0 on even rows, 1 on odd ones (rows top first).
const std::vector<int> kStripes{0, 0, 0, 0, 1, 1, 1, 1, 0, 0, 0, 0, 1, 1, 1, 1};

float encoded_z(float encoded_x, float encoded_y) {
    const float x = 2.0f * encoded_x - 1.0f, y = 2.0f * encoded_y - 1.0f;
    return 0.5f * std::sqrt(std::max(0.0f, 1.0f - x * x - y * y)) + 0.5f;
}

// One 4x4 block of a two-channel normal map: x = 160 / 255 and 100 / 255 on alternate rows,
// y = 90 / 255 and 200 / 255.
void expect_reconstructed_stripes(const Image& read) {
    ASSERT_EQ(read.channels, 3);
    ASSERT_EQ(read.width, 4);
    for (int y = 0; y < 4; ++y) {
        const float x_value = (y % 2 == 0 ? 160.0f : 100.0f) / 255.0f;
        const float y_value = (y % 2 == 0 ? 90.0f : 200.0f) / 255.0f;
        for (int x = 0; x < 4; ++x) {
            EXPECT_FLOAT_EQ(read.at(x, y, 0), x_value) << x << "," << y;
            EXPECT_FLOAT_EQ(read.at(x, y, 1), y_value) << x << "," << y;
            EXPECT_NEAR(read.at(x, y, 2), encoded_z(x_value, y_value), 1e-6f) << x << "," << y;
            EXPECT_GT(read.at(x, y, 2), 0.85f);  // a real z, not the 0.5 of a missing channel
        }
    }
}

}  // namespace

TEST(Dds, Bc5ReconstructsZ) {
    const std::string folder = scratch_folder();
    std::vector<std::uint8_t> blocks;
    test::append_bc4_block(blocks, 160, 100, kStripes);  // x
    test::append_bc4_block(blocks, 90, 200, kStripes);   // y
    for (const char* four_cc : {"ATI2", "BC5U"}) {
        SCOPED_TRACE(four_cc);
        write_bytes(folder + "/n.dds", test::dds_file(4, 4, four_cc, test::kDdsFourCcFlag, blocks));
        expect_reconstructed_stripes(read_image(folder + "/n.dds"));
    }
    write_bytes(folder + "/dx10.dds",
                test::dds_file(4, 4, "DX10", test::kDdsFourCcFlag, blocks, 83));  // BC5_UNORM
    expect_reconstructed_stripes(read_image(folder + "/dx10.dds"));
    // Compact reads too (the bake's): floats, the same values.
    expect_reconstructed_stripes(compact_as_float(read_image_compact(folder + "/dx10.dds")));
}

TEST(Dds, Dxt5nmWithXInAlphaReconstructsZ) {
    const std::string folder = scratch_folder();
    std::vector<std::uint8_t> blocks;
    test::append_bc4_block(blocks, 160, 100, kStripes);  // alpha: x
    // Colour: R = 1 and B = 0 everywhere (the swizzle's constants), G = y. RGB565 endpoints
    // (255, 90, 0) and (255, 200, 0) are not exact in G: y is written with 6 bits, so the test
    // checks against what the decoder made of G.
    const auto g6 = [](int g) { return std::uint16_t((g * 63 + 127) / 255); };
    const std::uint16_t colour0 = std::uint16_t(0xF800 | (g6(200) << 5));
    const std::uint16_t colour1 = std::uint16_t(0xF800 | (g6(90) << 5));
    std::vector<int> inverted(16);
    for (std::size_t i = 0; i < 16; ++i) inverted[i] = 1 - kStripes[i];
    test::append_bc1_block(blocks, colour0, colour1, inverted);  // y: 90 on even rows
    for (const auto& [four_cc, flags] :
         {std::pair<const char*, std::uint32_t>{"DXT5", test::kDdsFourCcFlag},
          std::pair<const char*, std::uint32_t>{"DXT5",
                                                test::kDdsFourCcFlag | test::kDdsNormalFlag}}) {
        SCOPED_TRACE(flags);
        write_bytes(folder + "/nm.dds", test::dds_file(4, 4, four_cc, flags, blocks));
        ReadOptions opaque;
        opaque.drop_alpha = true;  // as the bake reads: x is in alpha, yet it is kept
        const Image read = compact_as_float(read_image_compact(folder + "/nm.dds", opaque));
        ASSERT_EQ(read.channels, 3);
        for (int y = 0; y < 4; ++y) {
            const float x_value = (y % 2 == 0 ? 160.0f : 100.0f) / 255.0f;
            const float y_value = read.at(0, y, 1);
            EXPECT_NEAR(y_value, (y % 2 == 0 ? 90.0f : 200.0f) / 255.0f, 3.0f / 255.0f);
            EXPECT_FLOAT_EQ(read.at(0, y, 0), x_value) << y;
            EXPECT_NEAR(read.at(0, y, 2), encoded_z(x_value, y_value), 1e-6f) << y;
        }
    }
}

// Normal maps written by NVIDIA Texture Tools (`nvcompress -normal`, tests/io/data/README.md) carry
// DDPF_NORMAL in every format. Each must decode to the normals of the PNG they were made from,
// within the error of its compression:
// - BC1 (`-bc1`: x, y, z in RGB 565; `-bc1n`: x, y in RG, blue constant): two 5/6-bit endpoints
//   and four colours on one line per 4x4 block. On this smooth map NVTT's encoder is off by at
//   most 0.15 (38 codes, where a block's normals do not lie on a line) and 0.016 on average:
//   bounds 0.2 and 0.025.
// - BC3n (x in alpha: 8-bit endpoints, 8 levels; y in green: 6 bits, 4 levels): at most 0.02
//   (5 codes), bound 0.03; mean bound 0.01.
// - BC5 (two BC4 channels: 8-bit endpoints, 8 levels each): at most 0.012, bound 0.02; mean 0.006.
// - uncompressed RGBA8 (NVTT renormalises before rounding): one code, bound 1.5 / 255.
// A two-channel format's z is rebuilt from x and y (within the same bounds of the PNG's z). A
// decoder that reads the 4 channels with a 3-channel stride is off by about 0.3 on average.
TEST(Dds, NvttNormalMapsDecodeAsTheirPngWhateverTheirFlags) {
    const std::string data = std::string(LEANFADE_SOURCE_DIR) + "/tests/io/data/";
    const Image png = read_image(data + "normal32.png");
    ASSERT_EQ(png.channels, 3);
    struct Case {
        const char* file;
        bool flagged;
        float max_error, mean_error;
    };
    for (const Case& c : {Case{"nvtt-bc1.dds", true, 0.2f, 0.025f},
                          Case{"nvtt-bc1n.dds", true, 0.2f, 0.025f},
                          Case{"nvtt-bc3n.dds", true, 0.03f, 0.01f},
                          Case{"nvtt-bc5.dds", true, 0.02f, 0.006f},
                          Case{"nvtt-rgb.dds", false, 1.5f / 255.0f, 1.5f / 255.0f},
                          Case{"nvtt-rgb-flagged.dds", true, 1.5f / 255.0f, 1.5f / 255.0f}}) {
        SCOPED_TRACE(c.file);
        const std::string path = data + c.file;
        const std::vector<std::uint8_t> bytes = read_bytes(path);
        ASSERT_GE(bytes.size(), 128u);
        const std::uint32_t flags = std::uint32_t(bytes[80]) | (std::uint32_t(bytes[81]) << 8) |
                                    (std::uint32_t(bytes[82]) << 16) |
                                    (std::uint32_t(bytes[83]) << 24);
        EXPECT_EQ((flags & test::kDdsNormalFlag) != 0, c.flagged);  // the data is what it says
        ReadOptions opaque;
        opaque.drop_alpha = true;  // as the bake reads
        for (const Image& read :
             {read_image(path), compact_as_float(read_image_compact(path, opaque))}) {
            ASSERT_EQ(read.width, png.width);
            ASSERT_EQ(read.height, png.height);
            ASSERT_GE(read.channels, 3);
            double sum = 0.0;
            float largest = 0.0f;
            for (int y = 0; y < png.height; ++y) {
                for (int x = 0; x < png.width; ++x) {
                    for (int channel = 0; channel < 3; ++channel) {
                        const float error =
                            std::abs(read.at(x, y, channel) - png.at(x, y, channel));
                        largest = std::max(largest, error);
                        sum += double(error);
                    }
                }
            }
            EXPECT_LE(largest, c.max_error);
            EXPECT_LE(sum / double(3 * png.texel_count()), double(c.mean_error));
        }
        EXPECT_EQ(read_bytes(path), bytes);  // the file is never changed
    }
}

TEST(Dds, Bc1Bc3AndBc4AreColourAndGreyImages) {
    const std::string folder = scratch_folder();
    std::vector<std::uint8_t> bc1;
    test::append_bc1_block(bc1, 0xFFFF, 0x001F, kStripes);  // white, blue
    write_bytes(folder + "/c.dds", test::dds_file(4, 4, "DXT1", test::kDdsFourCcFlag, bc1));
    const Image colour = read_image(folder + "/c.dds");
    ASSERT_EQ(colour.channels, 4);
    EXPECT_EQ(colour.at(1, 0, 0), 1.0f);
    EXPECT_EQ(colour.at(1, 1, 0), 0.0f);
    EXPECT_EQ(colour.at(1, 1, 2), 1.0f);
    EXPECT_EQ(colour.at(1, 1, 3), 1.0f);

    // A DXT5 whose R varies is an ordinary RGBA image, alpha kept.
    std::vector<std::uint8_t> bc3;
    test::append_bc4_block(bc3, 160, 100, kStripes);
    test::append_bc1_block(bc3, 0xFFFF, 0x001F, kStripes);
    write_bytes(folder + "/rgba.dds", test::dds_file(4, 4, "DXT5", test::kDdsFourCcFlag, bc3));
    const Image rgba = read_image(folder + "/rgba.dds");
    ASSERT_EQ(rgba.channels, 4);
    EXPECT_FLOAT_EQ(rgba.at(0, 0, 3), 160.0f / 255.0f);
    EXPECT_EQ(rgba.at(0, 1, 0), 0.0f);

    std::vector<std::uint8_t> bc4;
    test::append_bc4_block(bc4, 160, 100, kStripes);
    write_bytes(folder + "/h.dds", test::dds_file(4, 4, "ATI1", test::kDdsFourCcFlag, bc4));
    const Image height = read_image(folder + "/h.dds");
    ASSERT_EQ(height.channels, 1);
    EXPECT_FLOAT_EQ(height.at(3, 2), 160.0f / 255.0f);
    EXPECT_FLOAT_EQ(height.at(3, 3), 100.0f / 255.0f);
}

// ---- hostile files ----

TEST(Formats, SizeLimitIsCheckedOnTheHeaderOfEveryFormat) {
    const std::string folder = scratch_folder();
    const Image rgb = byte_image(40, 24, 3);
    std::vector<std::string> paths;
    for (const char* extension : {"jpg", "tga", "tif", "bmp", "webp"}) {
        paths.push_back(folder + "/big." + extension);
        test::write_with_openimageio(paths.back(), extension, rgb, OIIO::TypeDesc::UINT8);
    }
    paths.push_back(folder + "/big.exr");
    test::write_with_openimageio(paths.back(), "exr", rgb, OIIO::TypeDesc::HALF,
                                 {{"compression", "dwaa"}});
    paths.push_back(folder + "/big.psd");
    write_bytes(paths.back(), test::psd_file(rgb, 8));
    paths.push_back(folder + "/big.dds");
    write_bytes(paths.back(), test::dds_file(40, 24, "ATI1", test::kDdsFourCcFlag,
                                             std::vector<std::uint8_t>(60 * 8, 0)));
    ReadOptions small;
    small.max_dimension = 32;
    for (const std::string& path : paths) {
        SCOPED_TRACE(path);
        expect_error([&] { read_image(path, small); }, path,
                     "image size 40x24 exceeds the limit of 32 texels per side");
        EXPECT_EQ(read_image(path).width, 40);
    }
}

// Before: every format but DDS was read into memory whole before its header was checked (a
// 2 GiB file over the size limit cost 2.2 GB). Each file here is padded to 64 MiB after its
// data (the readers ignore what follows): refused by its header, with no buffer of the file's
// size allocated.
TEST(Formats, SizeLimitIsCheckedBeforeTheFileIsRead) {
    const std::string folder = scratch_folder();
    const Image rgb = byte_image(40, 24, 3);
    std::vector<std::string> paths;
    for (const char* extension : {"jpg", "tga", "tif", "bmp", "hdr", "webp"}) {
        paths.push_back(folder + "/big." + extension);
        test::write_with_openimageio(
            paths.back(), extension, rgb,
            std::string(extension) == "hdr" ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    }
    paths.push_back(folder + "/big-dwaa.exr");  // decoded by OpenImageIO
    test::write_with_openimageio(paths.back(), "exr", rgb, OIIO::TypeDesc::HALF,
                                 {{"compression", "dwaa"}});
    paths.push_back(folder + "/big-zip.exr");  // decoded by tinyexr
    write_exr(paths.back(), rgb);
    paths.push_back(folder + "/big.pfm");
    write_pfm(paths.back(), rgb);
    paths.push_back(folder + "/big.psd");
    write_bytes(paths.back(), test::psd_file(rgb, 8));
    paths.push_back(folder + "/big.dds");
    write_bytes(paths.back(), test::dds_file(40, 24, "ATI1", test::kDdsFourCcFlag,
                                             std::vector<std::uint8_t>(60 * 8, 0)));
    constexpr std::uintmax_t kPadded = std::uintmax_t(64) << 20;
    ReadOptions small;
    small.max_dimension = 32;
    for (const std::string& path : paths) {
        SCOPED_TRACE(path);
        EXPECT_EQ(read_image(path).width, 40);  // a readable file
        std::filesystem::resize_file(path, kPadded);
        test::reset_largest_allocation();
        expect_error([&] { read_image(path, small); }, path,
                     "image size 40x24 exceeds the limit of 32 texels per side");
        expect_error([&] { read_image_compact(path, small); }, path,
                     "image size 40x24 exceeds the limit of 32 texels per side");
        EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);
    }
}

// Before: an allocation failure (under `ulimit -v`) ended the run with "internal error:
// std::bad_alloc", naming no file. Here every request over 2 MiB fails, as under a memory limit:
// the file's bytes fit, the decoded image (12 MiB of floats) does not.
TEST(Formats, AllocationFailureIsAnErrorNamingTheFile) {
    const std::string folder = scratch_folder();
    Image rgb(1024, 1024, 3);  // flat: a small file of every format
    std::fill(rgb.pixels.begin(), rgb.pixels.end(), 0.25f);
    std::vector<std::string> paths{folder + "/large.png"};
    write_png(paths.back(), rgb, 8);
    for (const char* extension : {"tif", "tga"}) {
        paths.push_back(folder + "/large." + extension);
        test::write_with_openimageio(
            paths.back(), extension, rgb, OIIO::TypeDesc::UINT8,
            {{"compression", std::string(extension) == "tif" ? "zip" : "rle"}});
    }
    constexpr std::size_t kLimit = std::size_t(2) << 20;
    struct LimitGuard {
        ~LimitGuard() { test::set_allocation_limit(0); }
    } guard;
    for (const std::string& path : paths) {
        SCOPED_TRACE(path);
        ASSERT_LT(std::filesystem::file_size(path), kLimit);
        EXPECT_EQ(read_image(path).width, 1024);  // without the limit
        test::set_allocation_limit(kLimit);
        expect_error([&] { read_image(path); }, path, "out of memory");
        test::set_allocation_limit(0);
    }
}

TEST(Formats, DecompressionBombsAreRefusedBeforeAllocating) {
    const std::string folder = scratch_folder();
    // A BC1 DDS declaring 16384 x 16384 texels (4 GiB as RGBA floats) with one block of data.
    std::vector<std::uint8_t> one_block;
    test::append_bc1_block(one_block, 0xFFFF, 0, kStripes);
    const std::string dds = folder + "/bomb.dds";
    write_bytes(dds, test::dds_file(16384, 16384, "DXT1", test::kDdsFourCcFlag, one_block));
    // A TGA header declaring 16000 x 16000 RLE texels with one packet of data.
    std::vector<std::uint8_t> tga(18, 0);
    tga[2] = 10;  // RLE true colour
    tga[12] = std::uint8_t(16000 & 0xFF);
    tga[13] = std::uint8_t(16000 >> 8);
    tga[14] = tga[12];
    tga[15] = tga[13];
    tga[16] = 24;
    tga.push_back(0xFF);  // one RLE packet of 128 texels
    tga.insert(tga.end(), {1, 2, 3});
    const std::string targa = folder + "/bomb.tga";
    write_bytes(targa, tga);
    for (const auto& [path, cause] :
         {std::pair<std::string, std::string>{dds,
                                              "truncated DDS data (DXT1 of 16384x16384, 1 "
                                              "level: 134217728 bytes of data after the "
                                              "128-byte header, the file holds 8)"},
          // Refused on its header, before the file is read: its data could not hold the texels.
          std::pair<std::string, std::string>{targa,
                                              "TGA of 16000x16000, 3 channels would decode "
                                              "to 3072000000 bytes from 22 bytes"}}) {
        SCOPED_TRACE(path);
        test::reset_largest_allocation();
        expect_error([&] { read_image(path); }, path, cause);
        EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);
    }
}

TEST(Formats, PsdSectionsPastTheEndAreRefusedBeforeAllocating) {
    // Found by fuzz_image_bake: OpenImageIO allocated the declared colour mode data (4 GB).
    const std::string folder = scratch_folder();
    const std::vector<std::uint8_t> good = test::psd_file(byte_image(4, 4, 3), 8);
    for (const std::size_t section : {std::size_t(26), std::size_t(30), std::size_t(34)}) {
        SCOPED_TRACE(section);
        std::vector<std::uint8_t> bytes = good;
        for (int i = 0; i < 4; ++i) bytes[section + std::size_t(i)] = 0xFF;  // 4 GiB - 1
        const std::string path = folder + "/sections.psd";
        write_bytes(path, bytes);
        test::reset_largest_allocation();
        expect_error([&] { read_image(path); }, path, "bytes past the end of the");
        EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);
    }
}

TEST(Formats, CorruptHeadersGiveOneLineErrors) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/bad.dds";
    write_bytes(
        path, test::dds_file(4, 4, "XYZW", test::kDdsFourCcFlag, std::vector<std::uint8_t>(16, 0)));
    expect_error([&] { read_image(path); }, path, "DDS");
    write_bytes(path, {'D', 'D'});
    expect_error([&] { read_image(path); }, path, "truncated DDS data");
    const std::string psd = folder + "/bad.psd";
    std::vector<std::uint8_t> bytes = test::psd_file(byte_image(4, 4, 3), 8);
    bytes[13] = 99;  // 99 channels
    write_bytes(psd, bytes);
    expect_error([&] { read_image(psd); }, psd, "PSD");
}

// ---- DDS headers checked before the file is read (docs/robustness.md, "Limits") ----

// An uncompressed DDS of `width` x `height` texels, `bits` per texel, with the given pixel
// flags and channel masks (R, G, B, A), and `data` after the 128-byte header.
std::vector<std::uint8_t> uncompressed_dds(int width, int height, std::uint32_t pixel_flags,
                                           std::uint32_t bits,
                                           const std::array<std::uint32_t, 4>& masks,
                                           const std::vector<std::uint8_t>& data) {
    std::vector<std::uint8_t> bytes = test::dds_file(width, height, "\0\0\0\0", pixel_flags, data);
    test::put_u32(bytes, 88, bits);
    for (std::size_t c = 0; c < 4; ++c) test::put_u32(bytes, 92 + 4 * c, masks[c]);
    return bytes;
}

// Before: a red (or luminance) mask of 0 made OpenImageIO's DDS reader loop forever; overlapping
// masks and masks beyond the bit count decoded garbage.
TEST(Formats, DdsChannelMasksAreCheckedBeforeDecoding) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/masks.dds";
    const std::vector<std::uint8_t> data(4 * 4 * 4, 0x80);
    constexpr std::uint32_t kRgb = 0x40, kRgba = 0x41, kLuminance = 0x20000;
    // A good one first: the masks are what decides the channels.
    write_bytes(path, uncompressed_dds(4, 4, kRgba, 32,
                                       {0x00FF0000, 0x0000FF00, 0x000000FF, 0xFF000000}, data));
    EXPECT_EQ(read_image(path).width, 4);
    const struct {
        std::uint32_t flags, bits;
        std::array<std::uint32_t, 4> masks;
        const char* cause;
    } cases[] = {
        {kRgb, 32, {0, 0x0000FF00, 0x000000FF, 0}, "the red channel's mask is 0"},
        {kRgb, 32, {0x00FF0000, 0, 0x000000FF, 0}, "the green channel's mask is 0"},
        {kRgb, 32, {0x00FF0000, 0x0000FF00, 0, 0}, "the blue channel's mask is 0"},
        {kRgba, 32, {0x00FF0000, 0x0000FF00, 0x000000FF, 0}, "the alpha channel's mask is 0"},
        {kLuminance, 8, {0, 0, 0, 0}, "the red channel's mask is 0"},
        {kRgb, 32, {0x00FF0000, 0x00FFFF00, 0x000000FF, 0}, "green channel's mask 0x00FFFF00 "
                                                            "overlaps another channel's"},
        {kRgb, 16, {0x00FF0000, 0x0000FF00, 0x000000FF, 0},
         "red channel's mask 0x00FF0000 lies beyond the 16 bits of a texel"},
        {kRgb, 12, {0xF00, 0x0F0, 0x00F, 0}, "12 bits per texel, expected 8, 16, 24 or 32"},
        {0, 32, {0x00FF0000, 0x0000FF00, 0x000000FF, 0}, "name no compression and no channels"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.cause);
        write_bytes(path, uncompressed_dds(4, 4, c.flags, c.bits, c.masks, data));
        expect_error([&] { read_image(path); }, path, c.cause);
    }
}

// Before: a DDS cut short (no data, half, one byte short) decoded as if the missing blocks were
// 0 and baked into a flat map with exit 0. The header gives the exact byte count.
TEST(Formats, TruncatedDdsIsRefusedByItsHeadersByteCount) {
    const std::string folder = scratch_folder();
    std::vector<std::uint8_t> bc1;
    for (int i = 0; i < 4; ++i) test::append_bc1_block(bc1, 0xFFFF, 0, kStripes);  // 8x8
    const std::vector<std::uint8_t> rgb(8 * 8 * 4, 0x80);
    struct Case {
        const char* name;
        std::vector<std::uint8_t> bytes;
        std::size_t data;
    };
    const Case files[] = {
        {"bc1", test::dds_file(8, 8, "DXT1", test::kDdsFourCcFlag, bc1), bc1.size()},
        {"rgb", uncompressed_dds(8, 8, 0x41, 32, {0x00FF0000, 0x0000FF00, 0x000000FF, 0xFF000000},
                                 rgb),
         rgb.size()},
    };
    for (const Case& file : files) {
        const std::string path = folder + "/" + file.name + ".dds";
        write_bytes(path, file.bytes);
        EXPECT_EQ(read_image(path).width, 8) << file.name;  // whole: read
        for (const std::size_t kept : {std::size_t(0), file.data / 2, file.data - 1}) {
            SCOPED_TRACE(std::string(file.name) + " with " + std::to_string(kept) + " bytes");
            std::vector<std::uint8_t> cut = file.bytes;
            cut.resize(128 + kept);
            write_bytes(path, cut);
            expect_error([&] { read_image(path); }, path,
                         std::to_string(file.data) + " bytes of data after the 128-byte header, "
                                                     "the file holds " + std::to_string(kept));
        }
    }
    // MIP levels declared in the header count too: a BC1 of 8x8 with 4 levels needs 4 + 1 + 1 + 1
    // blocks.
    std::vector<std::uint8_t> bytes = test::dds_file(8, 8, "DXT1", test::kDdsFourCcFlag, bc1);
    test::put_u32(bytes, 8, 0x1007 | 0x80000 | 0x20000);  // + DDSD_MIPMAPCOUNT
    test::put_u32(bytes, 28, 4);
    const std::string path = folder + "/mips.dds";
    write_bytes(path, bytes);
    expect_error([&] { read_image(path); }, path,
                 "DXT1 of 8x8, 4 levels: 56 bytes of data after the 128-byte header, the file "
                 "holds 32");
    bytes.resize(bytes.size() + 24, 0);
    write_bytes(path, bytes);
    EXPECT_EQ(read_image(path).width, 8);
}

// Before: a 2 GiB DDS over the size limit was read whole (2.2 GB) before its header was looked
// at. The header is read alone; nothing of the file's size is allocated.
TEST(Formats, DdsHeaderIsCheckedBeforeTheFileIsRead) {
    const std::string folder = scratch_folder();
    std::vector<std::uint8_t> bc1;
    test::append_bc1_block(bc1, 0xFFFF, 0, kStripes);
    const std::string path = folder + "/large.dds";
    write_bytes(path, test::dds_file(65536, 4, "DXT1", test::kDdsFourCcFlag, bc1));
    std::filesystem::resize_file(path, std::uintmax_t(2) << 30);  // sparse: 2 GiB of zeros
    test::reset_largest_allocation();
    expect_error([&] { read_image(path); }, path,
                 "image size 65536x4 exceeds the limit of 16384 texels per side");
    EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);
    // Unknown compressions are refused on the header too, naming the four characters.
    write_bytes(path, test::dds_file(4, 4, "XYZW", test::kDdsFourCcFlag,
                                     std::vector<std::uint8_t>(16, 0)));
    expect_error([&] { read_image(path); }, path, "unsupported DDS compression 'XYZW'");
}

TEST(Formats, UnknownFormatNamesEveryReadableFormat) {
    const std::string folder = scratch_folder();
    const std::string text = folder + "/notes.tga";
    write_bytes(text, std::vector<std::uint8_t>(40, 'x'));
    expect_error([&] { read_image(text); }, text,
                 "unknown image format (expected PNG, OpenEXR, PFM, JPEG, TGA, DDS, TIFF, PSD, "
                 "BMP, Radiance HDR or WebP)");
}
