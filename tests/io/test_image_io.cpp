#include <png.h>
#include <sys/stat.h>
#include <tinyexr.h>
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <variant>

#include "io_test_helpers.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/io/image_io.hpp"

namespace leanfade::io {
namespace {

using test::expect_error;
using test::read_bytes;
using test::scratch_folder;
using test::write_bytes;

// An image whose values are exact multiples of 1 / max_value, different in every channel.
Image quantised_image(int width, int height, int channels, int max_value, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_int_distribution<int> level(0, max_value);
    Image image(width, height, channels);
    for (float& value : image.pixels) value = float(level(random)) / float(max_value);
    if (!image.pixels.empty()) {
        image.pixels.front() = 0.0f;
        image.pixels.back() = 1.0f;
    }
    return image;
}

Image float_image(int width, int height, int channels, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> value(-100.0f, 1000.0f);
    Image image(width, height, channels);
    for (float& v : image.pixels) v = value(random);
    image.pixels.front() = 1e-30f;
    image.pixels.back() = -3.5e20f;
    return image;
}

void expect_same_pixels(const Image& actual, const Image& expected) {
    ASSERT_EQ(actual.width, expected.width);
    ASSERT_EQ(actual.height, expected.height);
    ASSERT_EQ(actual.channels, expected.channels);
    for (int y = 0; y < expected.height; ++y) {
        for (int x = 0; x < expected.width; ++x) {
            for (int c = 0; c < expected.channels; ++c) {
                ASSERT_EQ(actual.at(x, y, c), expected.at(x, y, c))
                    << "texel (" << x << ", " << y << ") channel " << c;
            }
        }
    }
}

// ---- PNG files written with libpng directly (layouts write_png never produces) ----

struct RawPng {
    int width = 0;
    int height = 0;
    int bit_depth = 8;
    int color_type = PNG_COLOR_TYPE_GRAY;
    bool interlaced = false;
    std::vector<std::vector<std::uint8_t>> rows;  // packed as libpng expects
    std::vector<png_color> palette;
    std::vector<std::uint8_t> transparency;  // tRNS for palette entries
};

// Test-only encoder; no C++ object with a destructor lives in this frame below setjmp.
bool encode_raw_png(const std::string& path, const RawPng& raw, png_bytepp rows) {
    FILE* file = std::fopen(path.c_str(), "wb");
    if (file == nullptr) return false;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png)) != 0) {
        png_destroy_write_struct(&png, &info);
        std::fclose(file);
        return false;
    }
    png_init_io(png, file);
    png_set_IHDR(png, info, png_uint_32(raw.width), png_uint_32(raw.height), raw.bit_depth,
                 raw.color_type, raw.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (!raw.palette.empty()) png_set_PLTE(png, info, raw.palette.data(), int(raw.palette.size()));
    if (!raw.transparency.empty()) {
        png_set_tRNS(png, info, raw.transparency.data(), int(raw.transparency.size()), nullptr);
    }
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return std::fclose(file) == 0;
}

void write_raw_png(const std::string& path, RawPng raw) {
    std::vector<png_bytep> rows;
    for (auto& row : raw.rows) rows.push_back(row.data());
    ASSERT_TRUE(encode_raw_png(path, raw, rows.data()));
}

// Rewrites the IHDR width and height of a PNG file and fixes the chunk's CRC.
void patch_png_size(std::vector<std::uint8_t>& png, std::uint32_t width, std::uint32_t height) {
    for (int i = 0; i < 4; ++i) {
        png[16 + std::size_t(i)] = std::uint8_t(width >> (24 - 8 * i));
        png[20 + std::size_t(i)] = std::uint8_t(height >> (24 - 8 * i));
    }
    const auto crc = std::uint32_t(::crc32(0L, png.data() + 12, 17));  // type + 13 data bytes
    for (int i = 0; i < 4; ++i) png[29 + std::size_t(i)] = std::uint8_t(crc >> (24 - 8 * i));
}

// ---- OpenEXR files written with tinyexr directly ----

struct RawExr {
    int width = 0;
    int height = 0;
    std::vector<std::string> names;          // sorted, as OpenEXR lists channels
    std::vector<std::vector<float>> planes;  // one per name, rows top first
    int file_pixel_type = TINYEXR_PIXELTYPE_FLOAT;
    int tile_size = 0;  // 0 = scan lines
};

void write_raw_exr(const std::string& path, const RawExr& raw) {
    const std::size_t count = raw.names.size();
    std::vector<EXRChannelInfo> channels(count);
    std::vector<int> input_types(count, TINYEXR_PIXELTYPE_FLOAT);
    std::vector<int> file_types(count, raw.file_pixel_type);
    std::vector<std::vector<float>> planes = raw.planes;
    std::vector<unsigned char*> plane_pointers;
    for (std::size_t c = 0; c < count; ++c) {
        std::memset(&channels[c], 0, sizeof channels[c]);
        std::snprintf(channels[c].name, sizeof channels[c].name, "%s", raw.names[c].c_str());
        plane_pointers.push_back(reinterpret_cast<unsigned char*>(planes[c].data()));
    }
    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = int(count);
    header.channels = channels.data();
    header.pixel_types = input_types.data();
    header.requested_pixel_types = file_types.data();
    header.compression_type = TINYEXR_COMPRESSIONTYPE_NONE;
    header.data_window = {0, 0, raw.width - 1, raw.height - 1};
    header.display_window = header.data_window;
    EXRImage image;
    InitEXRImage(&image);
    image.width = raw.width;
    image.height = raw.height;
    image.num_channels = int(count);

    // Tiles: tile_size x tile_size blocks, each channel stored with a stride of tile_size.
    std::vector<EXRTile> tiles;
    std::vector<std::vector<std::vector<float>>> tile_planes;
    std::vector<std::vector<unsigned char*>> tile_pointers;
    if (raw.tile_size > 0) {
        header.tiled = 1;
        header.tile_size_x = raw.tile_size;
        header.tile_size_y = raw.tile_size;
        header.tile_level_mode = TINYEXR_TILE_ONE_LEVEL;
        header.tile_rounding_mode = TINYEXR_TILE_ROUND_DOWN;
        const int tiles_x = (raw.width + raw.tile_size - 1) / raw.tile_size;
        const int tiles_y = (raw.height + raw.tile_size - 1) / raw.tile_size;
        tile_planes.resize(std::size_t(tiles_x * tiles_y));
        tile_pointers.resize(tile_planes.size());
        tiles.resize(tile_planes.size());
        for (int ty = 0; ty < tiles_y; ++ty) {
            for (int tx = 0; tx < tiles_x; ++tx) {
                const std::size_t t = std::size_t(ty * tiles_x + tx);
                EXRTile& tile = tiles[t];
                tile.offset_x = tx;
                tile.offset_y = ty;
                tile.level_x = 0;
                tile.level_y = 0;
                tile.width = std::min(raw.tile_size, raw.width - tx * raw.tile_size);
                tile.height = std::min(raw.tile_size, raw.height - ty * raw.tile_size);
                for (std::size_t c = 0; c < count; ++c) {
                    std::vector<float> block(std::size_t(raw.tile_size * raw.tile_size), 0.0f);
                    for (int y = 0; y < tile.height; ++y) {
                        for (int x = 0; x < tile.width; ++x) {
                            const int ix = tx * raw.tile_size + x;
                            const int iy = ty * raw.tile_size + y;
                            block[std::size_t(y * raw.tile_size + x)] =
                                raw.planes[c][std::size_t(iy * raw.width + ix)];
                        }
                    }
                    tile_planes[t].push_back(std::move(block));
                }
                for (auto& block : tile_planes[t]) {
                    tile_pointers[t].push_back(reinterpret_cast<unsigned char*>(block.data()));
                }
                tile.images = tile_pointers[t].data();
            }
        }
        image.tiles = tiles.data();
        image.num_tiles = int(tiles.size());
    } else {
        image.images = plane_pointers.data();
    }

    unsigned char* memory = nullptr;
    const char* message = nullptr;
    const std::size_t size = SaveEXRImageToMemory(&image, &header, &memory, &message);
    ASSERT_GT(size, 0u) << (message != nullptr ? message : "");
    write_bytes(path, std::vector<std::uint8_t>(memory, memory + size));
    std::free(memory);
}

// ---- PNG ----

TEST(Png, RoundTripsAllChannelCountsAndDepths) {
    const std::string folder = scratch_folder();
    const int sizes[][2] = {{1, 1}, {13, 7}, {4, 9}, {31, 1}, {1, 17}};
    for (const int bits : {8, 16}) {
        for (int channels = 1; channels <= 4; ++channels) {
            for (const auto& size : sizes) {
                SCOPED_TRACE(std::to_string(bits) + "-bit, " + std::to_string(channels) +
                             " channels, " + std::to_string(size[0]) + "x" +
                             std::to_string(size[1]));
                const Image image =
                    quantised_image(size[0], size[1], channels, bits == 8 ? 255 : 65535,
                                    unsigned(bits * 100 + channels * 10 + size[0]));
                const std::string path = folder + "/image.png";
                write_png(path, image, bits);
                expect_same_pixels(read_image(path), image);
            }
        }
    }
}

// read_image_compact keeps a PNG's integer samples: to_float() is exactly read_image's image,
// for both depths and every channel count, and an image larger than the reader's buffer streams
// the same from the file as from memory.
TEST(Png, CompactReadKeepsSamplesThatConvertToReadImagesValues) {
    const std::string folder = scratch_folder();
    for (const int bits : {8, 16}) {
        for (int channels = 1; channels <= 4; ++channels) {
            SCOPED_TRACE(std::to_string(bits) + "-bit, " + std::to_string(channels) + " channels");
            // 16-bit RGBA noise of 300x300 is ~700 KB: several buffers of the streaming reader.
            const Image image = quantised_image(300, 300, channels, bits == 8 ? 255 : 65535,
                                                unsigned(bits + channels));
            const std::string path = folder + "/image.png";
            write_png(path, image, bits);
            const auto compact = read_image_compact(path);
            ASSERT_TRUE(std::holds_alternative<UnormImage>(compact));
            const UnormImage& samples = std::get<UnormImage>(compact);
            EXPECT_EQ(samples.max_value, bits == 8 ? 255 : 65535);
            expect_same_pixels(samples.to_float(), image);
            expect_same_pixels(read_image(path), image);
            expect_same_pixels(read_image_from_memory(read_bytes(path), path), image);
            expect_same_pixels(
                std::get<UnormImage>(read_image_compact_from_memory(read_bytes(path), path))
                    .to_float(),
                image);
        }
    }
    // Float formats come as floats.
    const std::string exr = folder + "/image.exr";
    const Image floats = float_image(5, 4, 3, 9);
    write_exr(exr, floats);
    const auto compact = read_image_compact(exr);
    ASSERT_TRUE(std::holds_alternative<Image>(compact));
    expect_same_pixels(std::get<Image>(compact), floats);
}

TEST(ImageIo, DropAlphaKeepsColourChannelsOfRgbaOnly) {
    const std::string folder = scratch_folder();
    ReadOptions options;
    options.drop_alpha = true;
    const Image rgba = quantised_image(9, 7, 4, 65535, 5);
    Image rgb(9, 7, 3);
    for (std::size_t i = 0; i < rgba.texel_count(); ++i)
        for (int c = 0; c < 3; ++c)
            rgb.pixels[3 * i + std::size_t(c)] = rgba.pixels[4 * i + std::size_t(c)];
    write_png(folder + "/rgba.png", rgba, 16);
    expect_same_pixels(read_image(folder + "/rgba.png", options), rgb);
    expect_same_pixels(
        std::get<UnormImage>(read_image_compact(folder + "/rgba.png", options)).to_float(), rgb);
    write_exr(folder + "/rgba.exr", rgba);
    expect_same_pixels(read_image(folder + "/rgba.exr", options), rgb);
    // Gray + alpha stays two channels (a height map's alpha decides nothing, but the channel
    // count tells a height map from a normal map).
    const Image gray_alpha = quantised_image(9, 7, 2, 255, 6);
    write_png(folder + "/ga.png", gray_alpha, 8);
    expect_same_pixels(read_image(folder + "/ga.png", options), gray_alpha);
}

TEST(Png, WriteClampsAndRounds) {
    const std::string folder = scratch_folder();
    Image image(4, 1, 1);
    image.pixels = {-0.5f, 1.5f, 0.5f, 100.4f / 255.0f};
    write_png(folder + "/clamped.png", image, 8);
    const Image read = read_image(folder + "/clamped.png");
    EXPECT_EQ(read.pixels, (std::vector<float>{0.0f, 1.0f, 128.0f / 255.0f, 100.0f / 255.0f}));
}

TEST(Png, WritesValuesAsStoredWithoutColourConversion) {
    const std::string folder = scratch_folder();
    Image image(1, 1, 3);
    image.pixels = {0.5f, 0.25f, 0.75f};
    write_png(folder + "/raw.png", image, 16);
    const std::vector<std::uint8_t> bytes = read_bytes(folder + "/raw.png");
    // No gAMA, sRGB, iCCP or cHRM chunk claims a colour space.
    for (const char* chunk : {"gAMA", "sRGB", "iCCP", "cHRM"}) {
        EXPECT_EQ(std::search(bytes.begin(), bytes.end(), chunk, chunk + 4), bytes.end()) << chunk;
    }
    const Image read = read_image(folder + "/raw.png");
    EXPECT_NEAR(read.pixels[0], 0.5f, 1.0f / 65535.0f);
    EXPECT_NEAR(read.pixels[1], 0.25f, 1.0f / 65535.0f);
}

TEST(Png, ReadsLowBitGrayPaletteTransparencyAndInterlacing) {
    const std::string folder = scratch_folder();

    RawPng gray1;  // 1-bit gray, 9 pixels wide: bits packed from the most significant
    gray1.width = 9;
    gray1.height = 2;
    gray1.bit_depth = 1;
    gray1.rows = {{0b10110000, 0b10000000}, {0b01001111, 0b00000000}};
    write_raw_png(folder + "/gray1.png", gray1);
    const Image gray = read_image(folder + "/gray1.png");
    ASSERT_EQ(gray.channels, 1);
    EXPECT_EQ(gray.pixels, (std::vector<float>{1, 0, 1, 1, 0, 0, 0, 0, 1,  //
                                               0, 1, 0, 0, 1, 1, 1, 1, 0}));

    RawPng palette;
    palette.width = 3;
    palette.height = 2;
    palette.color_type = PNG_COLOR_TYPE_PALETTE;
    palette.palette = {{255, 0, 0}, {0, 128, 0}, {10, 20, 30}};
    palette.rows = {{0, 1, 2}, {2, 2, 0}};
    write_raw_png(folder + "/palette.png", palette);
    const Image rgb = read_image(folder + "/palette.png");
    ASSERT_EQ(rgb.channels, 3);
    EXPECT_EQ(rgb.at(1, 0, 1), 128.0f / 255.0f);
    EXPECT_EQ(rgb.at(0, 1, 2), 30.0f / 255.0f);
    EXPECT_EQ(rgb.at(2, 1, 0), 1.0f);

    palette.transparency = {255, 0};  // entry 2 has no tRNS value: opaque
    write_raw_png(folder + "/palette_alpha.png", palette);
    const Image rgba = read_image(folder + "/palette_alpha.png");
    ASSERT_EQ(rgba.channels, 4);
    EXPECT_EQ(rgba.at(0, 0, 3), 1.0f);
    EXPECT_EQ(rgba.at(1, 0, 3), 0.0f);
    EXPECT_EQ(rgba.at(2, 0, 3), 1.0f);

    RawPng interlaced;  // 16-bit RGB, Adam7
    interlaced.width = 7;
    interlaced.height = 5;
    interlaced.bit_depth = 16;
    interlaced.color_type = PNG_COLOR_TYPE_RGB;
    interlaced.interlaced = true;
    for (int y = 0; y < interlaced.height; ++y) {
        std::vector<std::uint8_t> row;
        for (int x = 0; x < interlaced.width; ++x) {
            for (int c = 0; c < 3; ++c) {
                const int value = 1000 * y + 100 * x + c;
                row.push_back(std::uint8_t(value >> 8));
                row.push_back(std::uint8_t(value & 0xFF));
            }
        }
        interlaced.rows.push_back(row);
    }
    write_raw_png(folder + "/interlaced.png", interlaced);
    const Image adam7 = read_image(folder + "/interlaced.png");
    ASSERT_EQ(adam7.channels, 3);
    for (int y = 0; y < 5; ++y) {
        for (int x = 0; x < 7; ++x) {
            ASSERT_EQ(adam7.at(x, y, 2), float(1000 * y + 100 * x + 2) / 65535.0f);
        }
    }

    // The compact read (what `leanfade bake` uses) expands these the same way.
    for (const char* name : {"gray1.png", "palette.png", "palette_alpha.png", "interlaced.png"}) {
        SCOPED_TRACE(name);
        const std::string path = folder + "/" + name;
        expect_same_pixels(std::get<UnormImage>(read_image_compact(path)).to_float(),
                           read_image(path));
    }
}

TEST(Png, HostileFilesThrowNamingFileAndCause) {
    const std::string folder = scratch_folder();
    const std::string good = folder + "/good.png";
    write_png(good, quantised_image(29, 23, 3, 255, 7), 8);
    const std::vector<std::uint8_t> bytes = read_bytes(good);
    ASSERT_GT(bytes.size(), 100u);

    const std::string missing = folder + "/missing.png";
    expect_error([&] { read_image(missing); }, missing, "cannot open (No such file or directory)");
    expect_error([&] { read_image(folder); }, folder, "is a directory");

    const std::string empty = folder + "/empty.png";
    write_bytes(empty, {});
    expect_error([&] { read_image(empty); }, empty, "empty file");

    const std::string truncated = folder + "/truncated.png";
    for (const std::size_t length :
         {std::size_t(4), std::size_t(8), std::size_t(20), std::size_t(33), std::size_t(60),
          bytes.size() / 2, bytes.size() - 12, bytes.size() - 1}) {
        SCOPED_TRACE("truncated to " + std::to_string(length) + " bytes");
        write_bytes(truncated, std::vector<std::uint8_t>(bytes.begin(),
                                                         bytes.begin() + std::ptrdiff_t(length)));
        expect_error([&] { read_image(truncated); }, truncated, "truncated PNG data");
    }

    const std::string garbage = folder + "/garbage.png";
    std::vector<std::uint8_t> noise(1000);
    std::mt19937 random(3);
    for (auto& byte : noise) byte = std::uint8_t(random());
    noise[0] = 'G';
    write_bytes(garbage, noise);
    expect_error([&] { read_image(garbage); }, garbage, "unknown image format");

    std::copy(bytes.begin(), bytes.begin() + 8, noise.begin());  // PNG signature, then noise
    write_bytes(garbage, noise);
    expect_error([&] { read_image(garbage); }, garbage, "corrupt PNG data");

    std::vector<std::uint8_t> bad_crc = bytes;
    bad_crc[40] ^= 0xFF;  // inside the first IDAT chunk
    const std::string corrupt = folder + "/corrupt.png";
    write_bytes(corrupt, bad_crc);
    expect_error([&] { read_image(corrupt); }, corrupt, "corrupt PNG data");

    std::vector<std::uint8_t> zero_width = bytes;
    patch_png_size(zero_width, 0, 23);
    const std::string zero = folder + "/zero.png";
    write_bytes(zero, zero_width);
    expect_error([&] { read_image(zero); }, zero, "image width or height is 0 (0x23)");
}

TEST(Png, DecompressionBombIsRefusedBeforeAllocating) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/bomb.png";
    write_png(path, Image(16, 16, 4, 0.5f), 8);
    std::vector<std::uint8_t> bytes = read_bytes(path);
    patch_png_size(bytes, 100000, 100000);
    write_bytes(path, bytes);
    test::reset_largest_allocation();
    expect_error([&] { read_image(path); }, path,
                 "image size 100000x100000 exceeds the limit of 16384 texels per side");
    EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);

    ReadOptions small;
    small.max_dimension = 15;
    write_png(path, Image(16, 3, 1, 0.5f), 8);
    expect_error([&] { read_image(path, small); }, path, "exceeds the limit of 15");
    small.max_dimension = 16;
    EXPECT_EQ(read_image(path, small).width, 16);
}

TEST(ImageIo, ReadingNeverModifiesTheInput) {
    const std::string folder = scratch_folder();
    write_png(folder + "/a.png", quantised_image(5, 3, 4, 255, 1), 8);
    write_exr(folder + "/a.exr", float_image(5, 3, 3, 2));
    write_pfm(folder + "/a.pfm", float_image(5, 3, 3, 3));
    for (const char* name : {"/a.png", "/a.exr", "/a.pfm"}) {
        const std::string path = folder + name;
        std::filesystem::permissions(
            path, std::filesystem::perms::owner_read | std::filesystem::perms::group_read);
        const std::vector<std::uint8_t> before = read_bytes(path);
        const auto time_before = std::filesystem::last_write_time(path);
        EXPECT_NO_THROW(read_image(path)) << name;
        EXPECT_EQ(read_bytes(path), before) << name;
        EXPECT_EQ(std::filesystem::last_write_time(path), time_before) << name;
    }
}

TEST(ImageIo, FormatIsChosenByContentNotExtension) {
    const std::string folder = scratch_folder();
    const Image image = float_image(3, 2, 3, 9);
    write_exr(folder + "/really_exr.png", image);
    write_pfm(folder + "/really_pfm.exr", image);
    expect_same_pixels(read_image(folder + "/really_exr.png"), image);
    expect_same_pixels(read_image(folder + "/really_pfm.exr"), image);
}

// ---- OpenEXR ----

TEST(Exr, RoundTripsOneToFourChannels) {
    const std::string folder = scratch_folder();
    for (int channels = 1; channels <= 4; ++channels) {
        for (const auto& size : {std::pair{1, 1}, std::pair{17, 9}, std::pair{6, 33}}) {
            SCOPED_TRACE(std::to_string(channels) + " channels");
            const Image image =
                float_image(size.first, size.second, channels, unsigned(channels + size.first));
            const std::string path = folder + "/image.exr";
            write_exr(path, image);
            expect_same_pixels(read_image(path), image);
        }
    }
}

TEST(Exr, ReadsHalfTiledAndOrdersChannels) {
    const std::string folder = scratch_folder();
    RawExr half;
    half.width = 3;
    half.height = 2;
    half.names = {"A", "B", "G", "R"};
    half.planes = {{1, 1, 1, 0.5f, 0.5f, 0.5f},
                   {0.25f, -2, 1024, 0, 0, 0},
                   {0, 0, 0, 0, 0, 7},
                   {1, 2, 3, 4, 5, 6}};
    half.file_pixel_type = TINYEXR_PIXELTYPE_HALF;
    write_raw_exr(folder + "/half.exr", half);
    const Image rgba = read_image(folder + "/half.exr");
    ASSERT_EQ(rgba.channels, 4);
    EXPECT_EQ(rgba.at(2, 1, 0), 6.0f);     // R
    EXPECT_EQ(rgba.at(2, 1, 1), 7.0f);     // G
    EXPECT_EQ(rgba.at(2, 0, 2), 1024.0f);  // B
    EXPECT_EQ(rgba.at(1, 0, 2), -2.0f);
    EXPECT_EQ(rgba.at(0, 1, 3), 0.5f);  // A

    RawExr tiled;
    tiled.width = 10;
    tiled.height = 7;
    tiled.names = {"Y"};
    tiled.planes.resize(1);
    for (int i = 0; i < tiled.width * tiled.height; ++i) tiled.planes[0].push_back(float(i) * 0.5f);
    tiled.tile_size = 4;
    write_raw_exr(folder + "/tiled.exr", tiled);
    const Image tiles = read_image(folder + "/tiled.exr");
    ASSERT_EQ(tiles.channels, 1);
    ASSERT_EQ(tiles.width, 10);
    ASSERT_EQ(tiles.height, 7);
    for (int i = 0; i < 70; ++i) ASSERT_EQ(tiles.pixels[std::size_t(i)], float(i) * 0.5f) << i;
}

TEST(Exr, NonFiniteValuesAreRefusedWithTheirTexel) {
    const std::string folder = scratch_folder();
    RawExr raw;
    raw.width = 4;
    raw.height = 3;
    raw.names = {"B", "G", "R"};
    raw.planes.assign(3, std::vector<float>(12, 0.25f));
    raw.planes[1][2 * 4 + 3] = std::numeric_limits<float>::quiet_NaN();  // texel (3, 2), G
    const std::string nan_path = folder + "/nan.exr";
    write_raw_exr(nan_path, raw);
    expect_error([&] { read_image(nan_path); }, nan_path, "NaN at texel (3, 2)");

    raw.planes[1][2 * 4 + 3] = 0.0f;
    raw.planes[0][1 * 4 + 0] = std::numeric_limits<float>::infinity();  // texel (0, 1), B
    const std::string inf_path = folder + "/inf.exr";
    write_raw_exr(inf_path, raw);
    expect_error([&] { read_image(inf_path); }, inf_path, "infinity at texel (0, 1)");
}

TEST(Exr, HostileFilesThrowNamingFileAndCause) {
    const std::string folder = scratch_folder();
    const std::string good = folder + "/good.exr";
    write_exr(good, float_image(21, 13, 3, 5));
    const std::vector<std::uint8_t> bytes = read_bytes(good);

    const std::string truncated = folder + "/truncated.exr";
    write_bytes(truncated, std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + 2));
    expect_error([&] { read_image(truncated); }, truncated, "truncated OpenEXR data");
    for (const std::size_t length :
         {std::size_t(8), std::size_t(60), std::size_t(200), bytes.size() / 2, bytes.size() - 10}) {
        SCOPED_TRACE("truncated to " + std::to_string(length) + " bytes");
        write_bytes(truncated, std::vector<std::uint8_t>(bytes.begin(),
                                                         bytes.begin() + std::ptrdiff_t(length)));
        expect_error([&] { read_image(truncated); }, truncated, "truncated or corrupt OpenEXR");
    }

    RawExr tiled;
    tiled.width = 9;
    tiled.height = 6;
    tiled.names = {"B", "G", "R"};
    tiled.planes.assign(3, std::vector<float>(54, 0.5f));
    tiled.tile_size = 4;
    write_raw_exr(folder + "/tiled.exr", tiled);
    const std::vector<std::uint8_t> tiled_bytes = read_bytes(folder + "/tiled.exr");
    for (const std::size_t length :
         {tiled_bytes.size() / 2, tiled_bytes.size() - 10, tiled_bytes.size() - 1}) {
        SCOPED_TRACE("tiled, truncated to " + std::to_string(length) + " bytes");
        write_bytes(truncated,
                    std::vector<std::uint8_t>(tiled_bytes.begin(),
                                              tiled_bytes.begin() + std::ptrdiff_t(length)));
        expect_error([&] { read_image(truncated); }, truncated, "truncated or corrupt OpenEXR");
    }

    // A data window of 100000 x 100000 texels: refused from the header, before decoding.
    std::vector<std::uint8_t> bomb = bytes;
    const std::string attribute("dataWindow\0box2i\0", 17);
    const auto found = std::search(bomb.begin(), bomb.end(), attribute.begin(), attribute.end());
    ASSERT_NE(found, bomb.end());
    const std::size_t box = std::size_t(found - bomb.begin()) + attribute.size() + 4;
    test::store_u32_le(bomb, box + 8, 99999);
    test::store_u32_le(bomb, box + 12, 99999);
    const std::string bomb_path = folder + "/bomb.exr";
    write_bytes(bomb_path, bomb);
    test::reset_largest_allocation();
    expect_error([&] { read_image(bomb_path); }, bomb_path, "image size 100000x100000 exceeds");
    EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);
}

// ---- PFM ----

TEST(Pfm, RoundTripsGrayAndRgb) {
    const std::string folder = scratch_folder();
    for (const int channels : {1, 3}) {
        for (const auto& size : {std::pair{1, 1}, std::pair{9, 4}, std::pair{2, 11}}) {
            const Image image = float_image(size.first, size.second, channels, unsigned(channels));
            const std::string path = folder + "/image.pfm";
            write_pfm(path, image);
            expect_same_pixels(read_image(path), image);
        }
    }
}

TEST(Pfm, WritesRowsBottomFirstLittleEndianAndDropsAlpha) {
    const std::string folder = scratch_folder();
    Image image(1, 2, 4);
    image.pixels = {1, 2, 3, 4,   // top row
                    5, 6, 7, 8};  // bottom row
    write_pfm(folder + "/rgba.pfm", image);
    const std::vector<std::uint8_t> bytes = read_bytes(folder + "/rgba.pfm");
    const std::string header = "PF\n1 2\n-1.0\n";
    ASSERT_EQ(bytes.size(), header.size() + 6 * 4);
    EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + std::ptrdiff_t(header.size())), header);
    float first;
    std::memcpy(&first, bytes.data() + header.size(), 4);
    EXPECT_EQ(first, 5.0f);  // bottom row first
    const Image read = read_image(folder + "/rgba.pfm");
    EXPECT_EQ(read.channels, 3);
    EXPECT_EQ(read.pixels, (std::vector<float>{1, 2, 3, 5, 6, 7}));

    Image two(2, 1, 2);
    two.pixels = {1, 2, 3, 4};
    write_pfm(folder + "/two.pfm", two);
    EXPECT_EQ(read_image(folder + "/two.pfm").pixels, (std::vector<float>{1, 2, 0, 3, 4, 0}));
}

TEST(Pfm, ReadsBigEndianAndFlipsRows) {
    const std::string folder = scratch_folder();
    std::string header = "Pf  2\t3 \n 1.5\n";
    std::vector<std::uint8_t> bytes(header.begin(), header.end());
    for (const float value : {5.0f, 6.0f, 3.0f, 4.0f, 1.0f, 2.0f}) {  // bottom row first
        std::uint32_t bits;
        std::memcpy(&bits, &value, 4);
        for (int shift = 24; shift >= 0; shift -= 8) bytes.push_back(std::uint8_t(bits >> shift));
    }
    write_bytes(folder + "/big.pfm", bytes);
    const Image image = read_image(folder + "/big.pfm");
    ASSERT_EQ(image.channels, 1);
    ASSERT_EQ(image.width, 2);
    ASSERT_EQ(image.height, 3);
    EXPECT_EQ(image.pixels, (std::vector<float>{1, 2, 3, 4, 5, 6}));
}

TEST(Pfm, HostileFilesThrowNamingFileAndCause) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/bad.pfm";
    const auto write_text = [&](const std::string& text, std::size_t data_bytes) {
        std::vector<std::uint8_t> bytes(text.begin(), text.end());
        bytes.resize(bytes.size() + data_bytes, 0);
        write_bytes(path, bytes);
    };
    write_text("PF\n4 4\n-1.0\n", 4 * 4 * 3 * 4 - 1);
    expect_error([&] { read_image(path); }, path, "truncated PFM data (191 of 192 bytes)");
    write_text("PF\n4 4", 0);
    expect_error([&] { read_image(path); }, path, "truncated PFM header");
    write_text("PF\n4 x4\n-1.0\n", 200);
    expect_error([&] { read_image(path); }, path, "bad PFM height 'x4'");
    write_text("PF\n0 4\n-1.0\n", 200);
    expect_error([&] { read_image(path); }, path, "image width or height is 0");
    write_text("Pf\n100000 100000\n-1.0\n", 64);
    test::reset_largest_allocation();
    expect_error([&] { read_image(path); }, path, "image size 100000x100000 exceeds the limit");
    EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);
    write_text("Pf\n2 2\n0\n", 16);
    expect_error([&] { read_image(path); }, path, "bad PFM scale");

    Image image(3, 2, 1, 1.0f);
    write_pfm(path, image);
    std::vector<std::uint8_t> bytes = read_bytes(path);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(bytes.data() + bytes.size() - 4, &nan, 4);  // last value in file: texel (2, 0)
    write_bytes(path, bytes);
    expect_error([&] { read_image(path); }, path, "NaN at texel (2, 0)");
}

TEST(ImageIo, UnknownFormatsAreNamed) {
    const std::string folder = scratch_folder();
    const std::string text = folder + "/notes.png";
    write_bytes(text, {'h', 'e', 'l', 'l', 'o'});
    expect_error([&] { read_image(text); }, text,
                 "unknown image format (expected PNG, OpenEXR, PFM");
    const std::string ktx = folder + "/map.png";
    write_bytes(ktx, {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n', 0});
    expect_error([&] { read_image(ktx); }, ktx, "is a KTX2 texture, not an image");
}

TEST(ImageIo, FlipReversesRows) {
    Image image(2, 3, 1);
    image.pixels = {1, 2, 3, 4, 5, 6};
    EXPECT_EQ(flip(image).pixels, (std::vector<float>{5, 6, 3, 4, 1, 2}));
    std::vector<std::uint8_t> bytes = {1, 2, 3, 4, 5, 6};
    flip_rows(bytes, 2);
    EXPECT_EQ(bytes, (std::vector<std::uint8_t>{5, 6, 3, 4, 1, 2}));
    flip_rows(bytes, 3);
    EXPECT_EQ(bytes, (std::vector<std::uint8_t>{4, 1, 2, 5, 6, 3}));
}

}  // namespace
}  // namespace leanfade::io
