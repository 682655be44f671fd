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
#include <vector>

#include "io_test_helpers.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/procedural.hpp"
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
    write_ktx2(path, pack_lean_map(baked.map, Storage::Float16, "test"));
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

}  // namespace
}  // namespace leanfade::io
