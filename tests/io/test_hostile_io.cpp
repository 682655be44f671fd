// Regression tests of the robustness work (docs/robustness.md): the inputs the fuzz targets and
// the hostile-file matrix found, rebuilt in code, and the in-memory readers the fuzz targets use.
#include <fcntl.h>
#include <sys/stat.h>
#include <tinyexr.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "io_test_helpers.hpp"
#include "leanfade/core/detail/bake.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"

namespace leanfade::io {
namespace {

using Bytes = std::vector<std::uint8_t>;
using test::expect_error;
using test::read_bytes;
using test::scratch_folder;
using test::store_u32_le;
using test::u64_le;
using test::write_bytes;

void store_be32(Bytes& bytes, std::size_t offset, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) {
        bytes.at(offset + std::size_t(i)) = std::uint8_t(value >> (24 - 8 * i));
    }
}

void append_chunk(Bytes& png, const char* type, const Bytes& data) {
    const std::size_t start = png.size();
    png.resize(start + 4);
    store_be32(png, start, std::uint32_t(data.size()));
    png.insert(png.end(), type, type + 4);
    png.insert(png.end(), data.begin(), data.end());
    const auto crc = std::uint32_t(::crc32(0, png.data() + start + 4, uInt(data.size() + 4)));
    png.resize(png.size() + 4);
    store_be32(png, png.size() - 4, crc);
}

Bytes zlib_compress(const Bytes& data) {
    uLongf size = compressBound(uLong(data.size()));
    Bytes out(size);
    EXPECT_EQ(compress(out.data(), &size, data.data(), uLong(data.size())), Z_OK);
    out.resize(size);
    return out;
}

// A PNG declaring width x height of `color_type` / `bit_depth` with `idat` as its pixel data.
Bytes png_declaring(std::uint32_t width, std::uint32_t height, int bit_depth, int color_type,
                    const Bytes& idat) {
    Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    Bytes ihdr(13, 0);
    store_be32(ihdr, 0, width);
    store_be32(ihdr, 4, height);
    ihdr[8] = std::uint8_t(bit_depth);
    ihdr[9] = std::uint8_t(color_type);
    append_chunk(png, "IHDR", ihdr);
    append_chunk(png, "IDAT", idat);
    append_chunk(png, "IEND", {});
    return png;
}

// Found by review of the decoder, confirmed with leanfade bake: a PNG of under 100 bytes declaring
// 16384 x 16384 RGBA16 made the decoder allocate its 2 GiB of rows (2 GiB resident, 17 s) before
// libpng noticed the missing data. Deflate expands at most 1032 times, so the declared size is
// now refused from the IDAT length alone.
TEST(HostileIo, PngDeclaringMorePixelsThanItsDataCanHoldIsRefusedBeforeAllocating) {
    const std::string path = scratch_folder() + "/bomb.png";
    write_bytes(path, png_declaring(16384, 16384, 16, 6, zlib_compress(Bytes(2048, 0))));
    test::reset_largest_allocation();
    expect_error([&] { read_image(path); }, path, "too short for its 16384x16384 size");
    EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);

    // A real image near the ratio bound, with more than 16 MiB of rows (so that the bound
    // applies), is still read: 2048 x 1100 RGBA16 of zeros compresses about 1000 : 1.
    const std::string fine = scratch_folder() + "/zeros.png";
    const Bytes rows(std::size_t(1100) * (1 + 2048 * 8), 0);  // each row: filter byte, pixels
    const Bytes compressed = zlib_compress(rows);
    EXPECT_LT(compressed.size(), rows.size() / 900);
    write_bytes(fine, png_declaring(2048, 1100, 16, 6, compressed));
    const Image image = read_image(fine);
    EXPECT_EQ(image.width, 2048);
    EXPECT_EQ(image.height, 1100);
    EXPECT_EQ(image.channels, 4);
    EXPECT_EQ(*std::max_element(image.pixels.begin(), image.pixels.end()), 0.0f);
}

// The position of the single scan-line chunk of a one-chunk OpenEXR: the offset table (one
// 64-bit entry) is followed by the chunk it points to.
std::size_t only_chunk(const Bytes& exr) {
    for (std::size_t at = 8; at + 16 <= exr.size(); ++at) {
        if (u64_le(exr, at) == at + 8) return at + 8;
    }
    ADD_FAILURE() << "no chunk found";
    return 0;
}

// The 16x16 one-channel ("Y") OpenEXR file of `plane` that tinyexr writes with `compression`,
// stored as `stored_type` (one chunk for PIZ and ZIP).
Bytes single_channel_exr(std::vector<float>& plane, int compression, int stored_type) {
    EXRChannelInfo channel{};
    std::strncpy(channel.name, "Y", sizeof channel.name - 1);
    int input_type = TINYEXR_PIXELTYPE_FLOAT;
    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = 1;
    header.channels = &channel;
    header.pixel_types = &input_type;
    header.requested_pixel_types = &stored_type;
    header.compression_type = compression;
    unsigned char* planes[1] = {reinterpret_cast<unsigned char*>(plane.data())};
    EXRImage image;
    InitEXRImage(&image);
    image.images = planes;
    image.width = 16;
    image.height = 16;
    image.num_channels = 1;
    unsigned char* memory = nullptr;
    const char* message = nullptr;
    const std::size_t size = SaveEXRImageToMemory(&image, &header, &memory, &message);
    EXPECT_GT(size, 0u) << (message != nullptr ? message : "");
    const std::unique_ptr<unsigned char, decltype(&std::free)> owned(memory, &std::free);
    return Bytes(memory, memory + size);
}

std::vector<float> test_plane() {
    std::vector<float> plane(16 * 16);
    for (std::size_t i = 0; i < plane.size(); ++i) plane[i] = float((i * 7919) % 251) / 251.0f;
    return plane;
}

// Found by fuzz_image_bake (ASan heap-buffer-overflow in tinyexr 1.0.1's DecompressPiz): a PIZ
// chunk whose bitmap range (minNonZero..maxNonZero, up to 8 KiB) runs past the end of the file
// was read past the end of the input buffer. tinyexr now reads zero padding there and the chunk
// is refused. Under `make sanitize` ASan checks the read (it intercepts tinyexr's memcpy).
TEST(HostileIo, ExrPizBitmapPastTheEndOfTheFileIsRefusedWithoutReadingPastTheBuffer) {
    std::vector<float> plane = test_plane();
    Bytes exr = single_channel_exr(plane, TINYEXR_COMPRESSIONTYPE_PIZ, TINYEXR_PIXELTYPE_HALF);
    ASSERT_FALSE(exr.empty());

    const std::size_t chunk = only_chunk(exr);  // int32 y, int32 data size, data
    ASSERT_GT(chunk, 0u);
    exr.resize(chunk + 16);
    store_u32_le(exr, chunk + 4, 8);            // 8 bytes of PIZ data, not 512 (uncompressed)
    store_u32_le(exr, chunk + 8, 0x1FFF0000u);  // minNonZero 0, maxNonZero 8191
    const std::string path = scratch_folder() + "/piz.exr";
    write_bytes(path, exr);
    expect_error([&] { read_image(path); }, path, "truncated or corrupt OpenEXR data");
    expect_error([&] { read_image_from_memory(exr, "piz.exr"); }, "piz.exr",
                 "truncated or corrupt OpenEXR data");
}

// Found by fuzz_image_bake (a differential check: the same OpenEXR file decoded to different
// values from one call to the next): tinyexr 1.0.1 places each scan-line chunk at the line the
// chunk names and does not check that the chunks cover the image, so a chunk naming the wrong
// line left rows of uninitialised memory in a "successfully" decoded image. Now refused.
TEST(HostileIo, ExrChunksThatLeaveRowsUncoveredAreRefused) {
    std::vector<float> plane = test_plane();
    // ZIP: 16 lines per chunk, so one chunk.
    Bytes exr = single_channel_exr(plane, TINYEXR_COMPRESSIONTYPE_ZIP, TINYEXR_PIXELTYPE_FLOAT);
    ASSERT_FALSE(exr.empty());
    // The file as written decodes to the plane.
    const Image decoded = read_image_from_memory(exr, "good.exr");
    ASSERT_EQ(decoded.pixels, plane);

    const std::size_t chunk = only_chunk(exr);  // int32 y, int32 data size, data
    ASSERT_GT(chunk, 0u);
    store_u32_le(exr, chunk, 12);  // the chunk claims lines 12-27: lines 0-11 are in no chunk
    const std::string path = scratch_folder() + "/uncovered.exr";
    write_bytes(path, exr);
    expect_error([&] { read_image(path); }, path, "corrupt OpenEXR data (line 0 is in no chunk)");
    expect_error([&] { read_image_from_memory(exr, "uncovered.exr"); }, "uncovered.exr",
                 "line 0 is in no chunk");
}

// Found by the hostile-file matrix (test_cli_hostile.cpp): a FIFO without a writer made the
// blocking open() wait forever. With a writer present (held here, so that the test cannot
// block either way) it used to be read as an "empty file".
TEST(HostileIo, FifoIsNotARegularFile) {
    const std::string path = scratch_folder() + "/pipe.png";
    ASSERT_EQ(::mkfifo(path.c_str(), 0644), 0);
    const int holder = ::open(path.c_str(), O_RDWR | O_NONBLOCK);
    ASSERT_GE(holder, 0);
    expect_error([&] { read_image(path); }, path, "is not a regular file");
    expect_error([&] { inspect_ktx2(path); }, path, "is not a regular file");
    ::close(holder);
}

TEST(HostileIo, NegativePfmSizeIsCalledNegative) {
    const std::string path = scratch_folder() + "/negative.pfm";
    const std::string text = "Pf\n4 -3\n-1.0\n" + std::string(48, '\0');
    write_bytes(path, Bytes(text.begin(), text.end()));
    expect_error([&] { read_image(path); }, path, "image width or height is negative (4x-3)");
}

Bytes lean_map_file(const std::string& path) {
    BakeOptions options;
    options.threads = 1;
    const BakeResult baked =
        bake_lean_map(make_builtin_height("ridges", 16, 2), BakeSource::Height, options);
    // A float map as leanfade 0.1 wrote it (layout v1, the offset encoding): its sc is a long
    // decimal, room for the value edits below.
    write_ktx2(path, pack_lean_map(baked.map, Storage::Float16, LeanEncoding::Offset, "test"));
    return read_bytes(path);
}

// Found by the hostile-file matrix: inspect_ktx2 (leanfade info) read the level index of a file
// with more levels than its size allows, and reported the garbage offsets of the extra entries
// instead of the level count.
TEST(HostileIo, InspectRefusesLevelCountPastTheChainOfAnyKtx2) {
    const std::string path = scratch_folder() + "/levels.ktx2";
    Bytes bytes = lean_map_file(path);
    store_u32_le(bytes, 40, 6);  // levelCount of a 16 x 16 map: at most 5
    write_bytes(path, bytes);
    expect_error([&] { inspect_ktx2(path); }, path,
                 "levelCount 6 exceeds the 5 levels of a 16x16 MIP chain");
    store_u32_le(bytes, 40, 5);  // the full chain is fine
    write_bytes(path, bytes);
    EXPECT_EQ(inspect_ktx2(path).level_count, 5u);
}

// The fuzz targets read from memory: the same results, and the same errors, as from a file.
TEST(HostileIo, InMemoryReadersMatchTheFileReaders) {
    const std::string folder = scratch_folder();
    const std::string ktx2 = folder + "/map.ktx2";
    const Bytes map_bytes = lean_map_file(ktx2);
    const PackedLeanMap from_file = read_ktx2(ktx2);
    const PackedLeanMap from_memory = read_ktx2_from_memory(map_bytes, "map.ktx2");
    ASSERT_EQ(from_memory.levels.size(), from_file.levels.size());
    for (std::size_t i = 0; i < from_file.levels.size(); ++i) {
        EXPECT_EQ(from_memory.levels[i].lean1, from_file.levels[i].lean1);
        EXPECT_EQ(from_memory.levels[i].lean2, from_file.levels[i].lean2);
    }
    EXPECT_EQ(from_memory.scale, from_file.scale);
    EXPECT_EQ(describe(inspect_ktx2_from_memory(map_bytes, ktx2)), describe(inspect_ktx2(ktx2)));

    const std::string png = folder + "/h.png";
    write_png(png, make_builtin_height("noise", 9, 3), 16);
    const Bytes png_bytes = read_bytes(png);
    EXPECT_EQ(read_image_from_memory(png_bytes, png).pixels, read_image(png).pixels);

    expect_error([&] { read_image_from_memory({}, "none.png"); }, "none.png", "empty file");
    expect_error([&] { read_ktx2_from_memory({}, "none.ktx2"); }, "none.ktx2", "empty file");
    const Bytes cut(map_bytes.begin(), map_bytes.begin() + 60);
    expect_error([&] { inspect_ktx2_from_memory(cut, "cut.ktx2"); }, "cut.ktx2",
                 "truncated KTX2 header");
    ReadOptions small;
    small.max_dimension = 8;
    expect_error([&] { read_image_from_memory(png_bytes, "h.png", small); }, "h.png",
                 "exceeds the limit of 8 texels per side");
}

// --- Memory bounded by the decoded size ----------------------------------------------------

// A PNG of `color_type` / `bit_depth` declaring width x height whose rows are all zeros (each row
// a filter byte and its zero samples), compressed as one IDAT; with a PLTE (and tRNS) chunk for
// palette images.
Bytes zero_png(std::uint32_t width, std::uint32_t height, int bit_depth, int color_type,
               bool transparency) {
    const int samples = color_type == 2 ? 3 : color_type == 4 ? 2 : color_type == 6 ? 4 : 1;
    const std::size_t row_bytes = (std::size_t(width) * std::size_t(samples * bit_depth) + 7) / 8;
    Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    Bytes ihdr(13, 0);
    store_be32(ihdr, 0, width);
    store_be32(ihdr, 4, height);
    ihdr[8] = std::uint8_t(bit_depth);
    ihdr[9] = std::uint8_t(color_type);
    append_chunk(png, "IHDR", ihdr);
    if (color_type == 3) {
        append_chunk(png, "PLTE", {0, 0, 0, 255, 255, 255});
        if (transparency) append_chunk(png, "tRNS", {0});
    }
    append_chunk(png, "IDAT", zlib_compress(Bytes((1 + row_bytes) * height, 0)));
    append_chunk(png, "IEND", {});
    return png;
}

// Found by an outside probe: the deflate guard counted the compressed bytes against the pixels
// as stored, not as decoded. An 87-byte 1-bit palette PNG of 11585² (16.8 MB of rows, under the
// guard's 16 MiB) decoded to 1.6 GB of RGB floats (794 MB in `bake`); a 33 KB 16384² 1-bit
// palette + tRNS file (33.5 MB of rows, within 1032 x its IDAT) to 4.2 GB of RGBA floats. The
// decoded size (after the palette and low-bit expansions) is now bounded by the compressed data,
// for the float and the compact reads alike, before any row is allocated.
TEST(HostileIo, PaletteBombsAreRefusedByTheirDecodedSize) {
    const std::string folder = scratch_folder();
    Bytes tiny = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    Bytes ihdr(13, 0);
    store_be32(ihdr, 0, 11585);
    store_be32(ihdr, 4, 11585);
    ihdr[8] = 1;  // bit depth
    ihdr[9] = 3;  // palette
    append_chunk(tiny, "IHDR", ihdr);
    append_chunk(tiny, "PLTE", {0, 0, 0});
    append_chunk(tiny, "IDAT", zlib_compress(Bytes(4, 0)));  // a stream that ends too soon
    append_chunk(tiny, "IEND", {});
    EXPECT_LT(tiny.size(), 100u);
    const std::string tiny_path = folder + "/tiny_palette.png";
    write_bytes(tiny_path, tiny);

    const Bytes large = zero_png(16384, 16384, 1, 3, true);
    EXPECT_LT(large.size(), 40000u);
    const std::string large_path = folder + "/palette_trns.png";
    write_bytes(large_path, large);

    for (const std::string& path : {tiny_path, large_path}) {
        SCOPED_TRACE(path);
        test::reset_largest_allocation();
        expect_error([&] { read_image(path); }, path, "truncated or a decompression bomb");
        expect_error([&] { read_image_compact(path); }, path, "truncated or a decompression bomb");
        EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);
    }
    expect_error([&] { read_image(large_path); }, large_path,
                 "PNG of 16384x16384 (4 channels once expanded) would decode to 4294967296 bytes "
                 "from ");
}

// The bound does not refuse images of real content, however large: a 4096 x 1024 1-bit palette
// image of random bits (50 MB of RGB floats from 0.5 MB of pixel data) is read.
TEST(HostileIo, LargePaletteImageOfRealContentIsRead) {
    const std::string path = scratch_folder() + "/random_palette.png";
    std::uint32_t state = 12345;
    const std::size_t row_bytes = 4096 / 8;
    Bytes rows((1 + row_bytes) * 1024, 0);
    for (std::size_t i = 0; i < rows.size(); ++i) {
        state = state * 1664525u + 1013904223u;
        if (i % (1 + row_bytes) != 0) rows[i] = std::uint8_t(state >> 24);  // not filter bytes
    }
    Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    Bytes ihdr(13, 0);
    store_be32(ihdr, 0, 4096);
    store_be32(ihdr, 4, 1024);
    ihdr[8] = 1;
    ihdr[9] = 3;
    append_chunk(png, "IHDR", ihdr);
    append_chunk(png, "PLTE", {0, 0, 0, 255, 255, 255});
    append_chunk(png, "IDAT", zlib_compress(rows));
    append_chunk(png, "IEND", {});
    write_bytes(path, png);
    const Image image = read_image(path);
    ASSERT_EQ(image.width, 4096);
    ASSERT_EQ(image.height, 1024);
    ASSERT_EQ(image.channels, 3);
    const int first_bit = rows[1] >> 7;  // texel (0, 0)
    EXPECT_EQ(image.at(0, 0, 0), float(first_bit));
}

// A tiled 8 x 8 one-channel float OpenEXR (tiles of 4 x 4, no compression), written by tinyexr
// (which writes a tiled file only from tiles: texel (x, y) holds (8 y + x) / 64).
Bytes tiled_exr() {
    constexpr int kSide = 8, kTile = 4;
    std::vector<std::vector<float>> planes;
    std::vector<unsigned char*> plane_pointers;
    std::vector<EXRTile> tiles;
    for (int ty = 0; ty < kSide / kTile; ++ty) {
        for (int tx = 0; tx < kSide / kTile; ++tx) {
            std::vector<float> plane;
            for (int y = 0; y < kTile; ++y)
                for (int x = 0; x < kTile; ++x)
                    plane.push_back(float(kSide * (ty * kTile + y) + tx * kTile + x) / 64.0f);
            planes.push_back(std::move(plane));
            EXRTile tile{};
            tile.offset_x = tx;
            tile.offset_y = ty;
            tile.width = kTile;
            tile.height = kTile;
            tiles.push_back(tile);
        }
    }
    for (auto& plane : planes)
        plane_pointers.push_back(reinterpret_cast<unsigned char*>(plane.data()));
    for (std::size_t i = 0; i < tiles.size(); ++i) tiles[i].images = &plane_pointers[i];
    EXRChannelInfo channel{};
    std::strncpy(channel.name, "Y", sizeof channel.name - 1);
    int pixel_type = TINYEXR_PIXELTYPE_FLOAT;
    EXRHeader header;
    InitEXRHeader(&header);
    header.num_channels = 1;
    header.channels = &channel;
    header.pixel_types = &pixel_type;
    header.requested_pixel_types = &pixel_type;
    header.compression_type = TINYEXR_COMPRESSIONTYPE_NONE;
    header.tiled = 1;
    header.tile_size_x = kTile;
    header.tile_size_y = kTile;
    header.tile_level_mode = TINYEXR_TILE_ONE_LEVEL;
    header.tile_rounding_mode = TINYEXR_TILE_ROUND_DOWN;
    header.data_window.max_x = header.data_window.max_y = kSide - 1;  // tiles are counted on it
    header.display_window = header.data_window;
    EXRImage image;
    InitEXRImage(&image);
    image.tiles = tiles.data();
    image.num_tiles = int(tiles.size());
    image.width = kSide;
    image.height = kSide;
    image.num_channels = 1;
    unsigned char* memory = nullptr;
    const char* message = nullptr;
    const std::size_t size = SaveEXRImageToMemory(&image, &header, &memory, &message);
    EXPECT_GT(size, 0u) << (message != nullptr ? message : "");
    const std::unique_ptr<unsigned char, decltype(&std::free)> owned(memory, &std::free);
    return Bytes(memory, memory + size);
}

// Offset of the data of the OpenEXR header attribute `name` of `type`.
std::size_t exr_attribute(const Bytes& exr, const std::string& name, const std::string& type) {
    const std::string needle = name + std::string(1, '\0') + type + std::string(1, '\0');
    const auto at = std::search(exr.begin(), exr.end(), needle.begin(), needle.end());
    if (at == exr.end()) {
        ADD_FAILURE() << "no attribute " << name;
        return 0;
    }
    return std::size_t(at - exr.begin()) + needle.size() + 4;  // after the size field
}

// Found by an outside probe: a tiled OpenEXR whose tile size is 0 made tinyexr fail an assertion
// (SIGABRT: the whole batch died). The tile description is checked before tinyexr parses the
// header: sizes of 0, level modes tinyexr asserts on, descriptions of the wrong size.
TEST(HostileIo, ExrTileDescriptionsTinyexrAssertsOnAreRefused) {
    const Bytes good = tiled_exr();
    ASSERT_FALSE(good.empty());
    EXPECT_EQ(read_image_from_memory(good, "good.exr").at(3, 2), 19.0f / 64.0f);
    const std::size_t tiles = exr_attribute(good, "tiles", "tiledesc");
    ASSERT_GT(tiles, 0u);

    const std::string folder = scratch_folder();
    Bytes zero_width = good;
    store_u32_le(zero_width, tiles, 0);
    write_bytes(folder + "/tile0.exr", zero_width);
    expect_error([&] { read_image(folder + "/tile0.exr"); }, folder + "/tile0.exr",
                 "corrupt OpenEXR header (tile size 0x4, expected 1 to 65536 per side)");
    Bytes zero_height = good;
    store_u32_le(zero_height, tiles + 4, 0);
    expect_error([&] { read_image_from_memory(zero_height, "tile_h0.exr"); }, "tile_h0.exr",
                 "tile size 4x0");
    Bytes level_mode = good;
    level_mode[tiles + 8] = 3;  // tinyexr asserts on level mode 3
    expect_error([&] { read_image_from_memory(level_mode, "mode.exr"); }, "mode.exr",
                 "corrupt OpenEXR header (tile level mode 3, rounding mode 0)");
    Bytes long_description = good;
    store_u32_le(long_description, tiles - 4, 10);  // tinyexr asserts the size is 9
    long_description.insert(long_description.begin() + std::ptrdiff_t(tiles + 9), 0);
    expect_error([&] { read_image_from_memory(long_description, "desc.exr"); }, "desc.exr",
                 "corrupt OpenEXR header (tile description of 10 bytes, expected 9)");
}

// Found by an outside probe: a 625-byte tiled OpenEXR made tinyexr allocate 2.17 GB before
// reporting its error (an offset for each of the 1x1 tiles its data window implied). The chunk
// table must fit in the file and the decoded tiles must be backed by its data, before tinyexr
// decodes; a single huge tile is refused as well.
TEST(HostileIo, ExrChunkTablesAndTilesLargerThanTheFileAreRefusedBeforeAllocating) {
    const Bytes good = tiled_exr();
    const std::size_t tiles = exr_attribute(good, "tiles", "tiledesc");
    const std::size_t window = exr_attribute(good, "dataWindow", "box2i");
    ASSERT_GT(tiles, 0u);
    ASSERT_GT(window, 0u);
    Bytes many = good;
    store_u32_le(many, window + 8, 16383);   // xMax
    store_u32_le(many, window + 12, 16383);  // yMax
    store_u32_le(many, tiles, 1);
    store_u32_le(many, tiles + 4, 1);
    EXPECT_LT(many.size(), 1000u);
    test::reset_largest_allocation();
    expect_error([&] { read_image_from_memory(many, "many.exr"); }, "many.exr",
                 "truncated OpenEXR data (OpenEXR of 16384x16384 in 268435456 tiles of 1x1, 1 "
                 "channels needs 268435456 chunks");
    EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);

    Bytes huge_tile = many;
    store_u32_le(huge_tile, tiles, 16384);
    store_u32_le(huge_tile, tiles + 4, 16384);
    test::reset_largest_allocation();
    expect_error([&] { read_image_from_memory(huge_tile, "huge_tile.exr"); }, "huge_tile.exr",
                 "OpenEXR of 16384x16384 in 1 tiles of 16384x16384, 1 channels would decode to "
                 "1073741824 bytes");
    EXPECT_LT(test::largest_allocation(), std::size_t(1) << 20);

    // Scan lines: a 16 x 16 ZIP file declaring 16384 x 16384 (1024 chunks of 16 lines).
    std::vector<float> plane = test_plane();
    Bytes lines = single_channel_exr(plane, TINYEXR_COMPRESSIONTYPE_ZIP, TINYEXR_PIXELTYPE_FLOAT);
    const std::size_t line_window = exr_attribute(lines, "dataWindow", "box2i");
    store_u32_le(lines, line_window + 8, 16383);
    store_u32_le(lines, line_window + 12, 16383);
    expect_error([&] { read_image_from_memory(lines, "lines.exr"); }, "lines.exr",
                 "needs 1024 chunks, more than the");
}

// Found by fuzz_image_bake once it had tiled seeds (ASan SEGV in tinyexr 1.0.1's
// ReconstructTileOffsets): a tile offset of 0 makes tinyexr rebuild the table by walking the chunks
// and trusting each one's data size, so a corrupt size sent it far past the end of its input. Such
// tables are refused before tinyexr decodes.
TEST(HostileIo, ExrTileOffsetTablesTinyexrWouldRebuildAreRefused) {
    Bytes exr = tiled_exr();  // 4 tiles: the table is 4 offsets, the first pointing right after it
    std::size_t table = 0;
    for (std::size_t at = 8; at + 32 <= exr.size(); ++at) {
        if (u64_le(exr, at) == at + 32) {
            table = at;
            break;
        }
    }
    ASSERT_GT(table, 0u);
    const std::size_t first_chunk = table + 32;
    test::store_u64_le(exr, table + 8, 0);             // tile 1: rebuild the table
    store_u32_le(exr, first_chunk + 16, 0x7FFFFFF0u);  // tile 0's data size: 2 GB
    expect_error([&] { read_image_from_memory(exr, "rebuild.exr"); }, "rebuild.exr",
                 "corrupt OpenEXR data (tile offset 1 is 0, inside the header or offset table)");
    Bytes past_end = tiled_exr();
    test::store_u64_le(past_end, table + 16, past_end.size() - 4);  // tile 2's header cut off
    expect_error([&] { read_image_from_memory(past_end, "past_end.exr"); }, "past_end.exr",
                 "truncated or corrupt OpenEXR data (tile offset 2 is ");
}

// Found by fuzz_image_bake once it had tiled seeds (UBSan: a negative index into the image, then a
// signed overflow in tinyexr): tinyexr decodes each tile where its chunk says, unchecked. Chunks
// naming tiles outside their level's grid, and tiles no chunk decodes (two chunks naming the same
// tile), are refused.
TEST(HostileIo, ExrTilesOutsideTheImageOrInNoChunkAreRefused) {
    const Bytes good = tiled_exr();
    std::size_t table = 0;
    for (std::size_t at = 8; at + 32 <= good.size(); ++at) {
        if (u64_le(good, at) == at + 32) {
            table = at;
            break;
        }
    }
    ASSERT_GT(table, 0u);
    const std::size_t second_chunk = std::size_t(u64_le(good, table + 8));  // tile (1, 0)
    Bytes negative = good;
    store_u32_le(negative, second_chunk, 0xFFFFFFFFu);  // tile x -1
    expect_error([&] { read_image_from_memory(negative, "negative.exr"); }, "negative.exr",
                 "corrupt OpenEXR data (chunk 1 names tile (-1, 0) of level (0, 0), outside the "
                 "image)");
    Bytes far = good;  // tinyexr computed 4 * 2^29 in int (UBSan: signed overflow)
    store_u32_le(far, second_chunk, 1u << 29);
    expect_error([&] { read_image_from_memory(far, "far.exr"); }, "far.exr",
                 "chunk 1 names tile (536870912, 0) of level (0, 0), outside the image");
    Bytes level = good;
    store_u32_le(level, second_chunk + 8, 1);  // level x 1 of a one-level file
    expect_error([&] { read_image_from_memory(level, "level.exr"); }, "level.exr",
                 "chunk 1 names tile (1, 0) of level (1, 0), outside the image");
    Bytes twice = good;
    store_u32_le(twice, second_chunk, 0);  // tile (0, 0) twice, (1, 0) in no chunk
    expect_error([&] { read_image_from_memory(twice, "twice.exr"); }, "twice.exr",
                 "corrupt OpenEXR data (tile (1, 0) is in no chunk)");
}

// --- KTX2: one validation for `leanfade info` and `--bumps` ----------------------------------

// Found by an outside probe: maps that `info` described (or `--bumps` rendered) although they are
// broken. Each is refused by read_ktx2 (what `--bumps` and `info` read); the structural ones by
// inspect_ktx2 too.
TEST(HostileIo, Ktx2OverlapsDuplicateKeysPartialChainsAndNonFiniteValuesAreRefused) {
    const std::string folder = scratch_folder();
    const std::string path = folder + "/map.ktx2";
    const Bytes good = lean_map_file(path);  // 16 x 16, 5 levels, Float16
    ASSERT_NO_THROW(read_ktx2(path));
    const auto expect_refused = [&](const std::string& name, Bytes bytes,
                                    const std::string& cause, bool structural) {
        SCOPED_TRACE(name);
        const std::string file = folder + "/" + name;
        write_bytes(file, bytes);
        expect_error([&] { read_ktx2(file); }, file, cause);
        if (structural) expect_error([&] { inspect_ktx2(file); }, file, cause);
    };
    const std::size_t level_index = 80;
    Bytes overlap = good;  // level 1 starts where level 0 does
    test::store_u64_le(overlap, level_index + 24, u64_le(good, level_index));
    expect_refused("overlap.ktx2", overlap, "level 1 data (offset ", true);
    expect_refused("overlap.ktx2", overlap, "overlaps level 0 data (offset ", true);
    Bytes in_header = good;  // level 4 (1 x 1) inside the header
    test::store_u64_le(in_header, level_index + 4 * 24, 8);
    expect_refused("in_header.ktx2", in_header,
                   "level 4 data (offset 8, length 16) overlaps the header and level index "
                   "(offset 0, length 200)",
                   true);
    Bytes duplicate = good;  // LEANFADEroughnessBaked renamed LEANFADEbakedShininess
    const std::string from = std::string("LEANFADEroughnessBaked") + '\0';
    const std::string to = std::string("LEANFADEbakedShininess") + '\0';
    const auto key = std::search(duplicate.begin(), duplicate.end(), from.begin(), from.end());
    ASSERT_NE(key, duplicate.end());
    std::copy(to.begin(), to.end(), key);
    expect_refused("duplicate.ktx2", duplicate,
                   "key/value data holds the key 'LEANFADEbakedShininess' more than once", true);
    Bytes partial = good;
    store_u32_le(partial, 40, 3);  // levelCount 3 of 5
    expect_refused("partial.ktx2", partial,
                   "levelCount 3 is a partial MIP chain (a LEAN map of 16x16 has all 5 levels)",
                   false);
    Bytes nan_texel = good;  // level 2 (4 x 4): lean2, texel (1, 3), its third value
    const std::uint64_t level2 = u64_le(good, level_index + 2 * 24);
    const std::size_t at = std::size_t(level2 + 4 * 4 * 8 + (3 * 4 + 1) * 8 + 2 * 2);
    nan_texel[at] = 0x00;
    nan_texel[at + 1] = 0x7E;
    expect_refused("nan.ktx2", nan_texel, "NaN in level 2 of lean2 at texel (1, 3)", false);
    Bytes nan_scale = good;  // LEANFADEscale "nan(xx...)": a number, but not finite
    const std::string scale_key = std::string("LEANFADEscale") + '\0';
    const auto scale =
        std::search(nan_scale.begin(), nan_scale.end(), scale_key.begin(), scale_key.end());
    ASSERT_NE(scale, nan_scale.end());
    const auto value = scale + std::ptrdiff_t(scale_key.size());
    const auto value_end = std::find(value, nan_scale.end(), std::uint8_t(0));
    ASSERT_GE(value_end - value, 5);
    std::fill(value, value_end, std::uint8_t('x'));
    std::copy_n("nan(", 4, value);
    *(value_end - 1) = ')';
    expect_refused("nan_scale.ktx2", nan_scale, "bad LEANFADEscale value 'nan(x", false);
}

// Found by fuzz_image_bake (fuzz/regressions/fuzz_image_bake/png_gray1_plateau_target_missing, a
// 9 x 4 1-bit gray PNG): the target gave bake_packed_to no plateau target and compared its layer
// with a float bake that did not know the samples' precision. What holds, and what the target
// now checks: baked into caller memory from its integer samples, with a target per layer, the
// map has the bytes of bake_packed of the floats told the samples' precision
// (BakeOptions::source_max_code), plateau layer included; without it the layer may differ.
TEST(HostileIo, CompactBakeIntoCallerMemoryMatchesTheFloatBakeToldItsPrecision) {
    const Bytes png{0x89, 0x50, 0x4E, 0x47, 0x0D, 0x0A, 0x1A, 0x0A, 0x00, 0x00, 0x00, 0x0D, 0x49,
                    0x48, 0x44, 0x52, 0x00, 0x00, 0x00, 0x09, 0x00, 0x00, 0x00, 0x04, 0x01, 0x00,
                    0x00, 0x00, 0x00, 0x74, 0x74, 0x28, 0x63, 0x00, 0x00, 0x00, 0x14, 0x49, 0x44,
                    0x41, 0x54, 0x08, 0x99, 0x63, 0x60, 0x50, 0x65, 0xF0, 0xCA, 0x67, 0x98, 0xB2,
                    0x93, 0xE1, 0x1E, 0x33, 0x00, 0x0E, 0x5E, 0x03, 0x0D, 0x8F, 0x0F, 0xC6, 0xC7,
                    0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4E, 0x44, 0xAE, 0x42, 0x60, 0x82};
    const auto compact = read_image_compact_from_memory(png, "fuzz.png");
    const UnormImage* samples = std::get_if<UnormImage>(&compact);
    ASSERT_NE(samples, nullptr);
    const Image floats = read_image_from_memory(png, "fuzz.png");
    for (const Storage storage :
         {Storage::Unorm8, Storage::Unorm16, Storage::Float16, Storage::Float32}) {
        SCOPED_TRACE(int(storage));
        BakeOptions options;
        options.threads = 1;
        std::vector<Bytes> layers;
        bool plateau = false;
        const PackedBakeResult to = bake_packed_to(
            [&](const PackedLeanMap& layout) {
                plateau = layout.has_plateau();
                layers.resize(3 * layout.levels.size());
                std::vector<PackedLevelTarget> targets;
                for (std::size_t l = 0; l < layout.levels.size(); ++l) {
                    const std::size_t bytes = std::size_t(layout.levels[l].width) *
                                              std::size_t(layout.levels[l].height) *
                                              std::size_t(bytes_per_texel(storage));
                    for (std::size_t k = 0; k < 3; ++k) layers[3 * l + k].assign(bytes, 0xAB);
                    targets.push_back(
                        {layers[3 * l].data(), layers[3 * l + 1].data(), layers[3 * l + 2].data()});
                }
                return targets;
            },
            *samples, BakeSource::Auto, options, storage, "test", "fuzz.png");
        ASSERT_TRUE(plateau);  // the packed bakes add the layer by default
        BakeOptions told = options;
        told.source_max_code = samples->effective_max_code(
            resolve_bake_source(BakeSource::Auto, *samples) == BakeSource::Normal ? 3 : 1);
        const PackedBakeResult expected =
            bake_packed(floats, BakeSource::Auto, told, storage, "test", "fuzz.png");
        EXPECT_EQ(to.packed.scale, expected.packed.scale);
        ASSERT_EQ(layers.size(), 3 * expected.packed.levels.size());
        for (std::size_t l = 0; l < expected.packed.levels.size(); ++l) {
            SCOPED_TRACE(l);
            EXPECT_EQ(layers[3 * l], expected.packed.levels[l].lean1);
            EXPECT_EQ(layers[3 * l + 1], expected.packed.levels[l].lean2);
            EXPECT_EQ(layers[3 * l + 2], expected.packed.levels[l].plateau);
        }
    }
}

}  // namespace
}  // namespace leanfade::io
