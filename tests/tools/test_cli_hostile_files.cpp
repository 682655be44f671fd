// Hostile input files through the real `leanfade` executable, continued (docs/robustness.md,
// "Hostile inputs from files"): tiled OpenEXR headers tinyexr asserts on, decompression bombs
// bounded by their decoded size, text inputs that are not regular files, LEAN maps `info` and
// `--bumps` must both refuse before printing anything, and file text escaped in messages. Every
// file is made here; each run is bounded in time and in resident memory.
#include <fcntl.h>
#include <sys/stat.h>
#include <tinyexr.h>
#include <unistd.h>
#include <zlib.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hostile_bytes.hpp"
#include "tools_test_helpers.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"

using namespace leanfade;
using test::shell_quote;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace {

using test::append_chunk;
using test::exr_bytes;
using test::Bytes;
using test::kMaxRssKib;
using test::load_le64;
using test::q;
using test::read_bytes;
using test::store_be32;
using test::store_le32;
using test::store_le64;
using test::write_bytes;
using test::zlib_compress;

// A 1-bit palette PNG of side x side whose pixel data is `rows` bytes of zeros, compressed.
Bytes palette_png(std::uint32_t side, std::size_t rows, bool transparency) {
    Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    Bytes ihdr(13, 0);
    store_be32(ihdr, 0, side);
    store_be32(ihdr, 4, side);
    ihdr[8] = 1;  // bit depth
    ihdr[9] = 3;  // palette
    append_chunk(png, "IHDR", ihdr);
    append_chunk(png, "PLTE", {0, 0, 0, 255, 255, 255});
    if (transparency) append_chunk(png, "tRNS", {0});
    append_chunk(png, "IDAT", zlib_compress(Bytes(rows, 0)));
    append_chunk(png, "IEND", {});
    return png;
}

// A tiled 8 x 8 one-channel OpenEXR (4 x 4 tiles), and the offsets of the data of its "tiles"
// and "dataWindow" attributes.
struct TiledExr {
    Bytes bytes;
    std::size_t tiles = 0, window = 0;
};

std::size_t attribute(const Bytes& exr, const std::string& name, const std::string& type) {
    const std::string needle = name + std::string(1, '\0') + type + std::string(1, '\0');
    const auto at = std::search(exr.begin(), exr.end(), needle.begin(), needle.end());
    if (at == exr.end()) throw Error("exr", "test file has no " + name);
    return std::size_t(at - exr.begin()) + needle.size() + 4;
}

TiledExr tiled_exr() {
    constexpr int kSide = 8, kTile = 4;
    std::vector<std::vector<float>> planes(4, std::vector<float>(kTile * kTile, 0.5f));
    std::vector<unsigned char*> plane_pointers;
    for (auto& plane : planes)
        plane_pointers.push_back(reinterpret_cast<unsigned char*>(plane.data()));
    std::vector<EXRTile> tiles(4);
    for (int i = 0; i < 4; ++i) {
        tiles[std::size_t(i)].offset_x = i % 2;
        tiles[std::size_t(i)].offset_y = i / 2;
        tiles[std::size_t(i)].width = kTile;
        tiles[std::size_t(i)].height = kTile;
        tiles[std::size_t(i)].images = &plane_pointers[std::size_t(i)];
    }
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
    header.data_window.max_x = header.data_window.max_y = kSide - 1;
    header.display_window = header.data_window;
    EXRImage image;
    InitEXRImage(&image);
    image.tiles = tiles.data();
    image.num_tiles = 4;
    image.width = kSide;
    image.height = kSide;
    image.num_channels = 1;
    TiledExr exr;
    exr.bytes = exr_bytes(image, header);
    exr.tiles = attribute(exr.bytes, "tiles", "tiledesc");
    exr.window = attribute(exr.bytes, "dataWindow", "box2i");
    return exr;
}

Bytes lean_map_bytes(const fs::path& dir) {
    return test::lean_map_bytes(dir, Storage::Float16);
}

// Replaces the first `from` in `bytes` by `to` (same length).
void replace_text(Bytes& bytes, const std::string& from, const std::string& to) {
    const auto at = std::search(bytes.begin(), bytes.end(), from.begin(), from.end());
    if (at == bytes.end() || from.size() != to.size())
        throw Error("test", "cannot replace " + from);
    std::copy(to.begin(), to.end(), at);
}

bool has_control_characters(const std::string& text) {
    return std::any_of(text.begin(), text.end(), [](char c) {
        const auto byte = static_cast<unsigned char>(c);
        return (byte < 0x20 && c != '\n') || byte == 0x7F;
    });
}

// Runs leanfade; expects exit code 1, one line on stderr naming `file` with `cause`, no control
// characters in it, nothing on stdout, within 20 s and kMaxRssKib.
void expect_refused(const std::string& args, const fs::path& dir, const std::string& file,
                    const std::string& cause) {
    SCOPED_TRACE(args);
    const test::RunResult r = test::run_leanfade_bounded(args, dir, 20);
    EXPECT_NE(r.exit_code, 124) << "timed out (a hang)";
    EXPECT_LT(r.exit_code, 128) << "killed by a signal (a crash): " << r.err;
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr(file + ": ")) << "the message must name the file";
    EXPECT_THAT(r.err, HasSubstr(cause));
    EXPECT_FALSE(has_control_characters(r.err)) << r.err;
    EXPECT_EQ(r.out, "") << "nothing is printed for a refused file";
    EXPECT_GT(r.max_rss_kib, 0);
    EXPECT_LT(r.max_rss_kib, leanfade::test::memory_bound_kib(kMaxRssKib))
        << "a small hostile file made leanfade hold " << r.max_rss_kib << " KiB";
}

// Found by an outside probe: a tiled OpenEXR whose tile size is 0 made tinyexr fail an assertion
// (SIGABRT), killing the whole batch. Refused with one line; the batch bakes the other input.
TEST(HostileInputFiles, TileSizeZeroOpenExrIsOneErrorAndTheBatchGoesOn) {
    const fs::path dir = test::scratch_dir("hostile_files_tile0");
    TiledExr exr = tiled_exr();
    store_le32(exr.bytes, exr.tiles, 0);
    write_bytes(dir / "tile0.exr", exr.bytes);
    io::write_png((dir / "good.png").string(), make_builtin_height("bumps", 16, 3), 16);
    fs::create_directory(dir / "out");
    const test::RunResult r = test::run_leanfade_bounded(
        "bake " + q(dir / "tile0.exr") + " " + q(dir / "good.png") + " --out-dir " + q(dir / "out"),
        dir, 60);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr("tile0.exr: corrupt OpenEXR header (tile size 0x4, expected 1 to "
                                 "65536 per side)\n"));
    EXPECT_THAT(r.err, HasSubstr("1 of 2 inputs failed"));
    EXPECT_TRUE(fs::exists(dir / "out" / "good.ktx2")) << "the batch went on to the good file";
    EXPECT_FALSE(fs::exists(dir / "out" / "tile0.ktx2"));
}

// Found by an outside probe: files of a few bytes that decode to gigabytes (the PNG guard counted
// compressed bytes against the pixels as stored, not as decoded), and a tiled OpenEXR whose tile
// table tinyexr allocated before reading it. Each is now one error, in bounded memory.
TEST(HostileInputFiles, DecompressionBombsAreBoundedByTheirDecodedSize) {
    const fs::path dir = test::scratch_dir("hostile_files_bombs");
    // 87 bytes: 11585² 1-bit palette (16.8 MB of rows, under the former 16 MiB threshold).
    Bytes tiny = palette_png(11585, 64, false);
    write_bytes(dir / "tiny_palette.png", tiny);
    EXPECT_LT(tiny.size(), 100u);
    // 33 KB: 16384² 1-bit palette + tRNS, its rows zeros (RGBA floats: 4 GiB).
    write_bytes(dir / "palette_trns.png", palette_png(16384, 16384 * (1 + 2048), true));
    // A tiled OpenEXR of 16384² in 1 x 1 tiles.
    TiledExr exr = tiled_exr();
    store_le32(exr.bytes, exr.window + 8, 16383);
    store_le32(exr.bytes, exr.window + 12, 16383);
    store_le32(exr.bytes, exr.tiles, 1);
    store_le32(exr.bytes, exr.tiles + 4, 1);
    write_bytes(dir / "tiles.exr", exr.bytes);

    expect_refused("bake " + q(dir / "tiny_palette.png"), dir, "tiny_palette.png",
                   "truncated or a decompression bomb");
    expect_refused("bake " + q(dir / "palette_trns.png"), dir, "palette_trns.png",
                   "PNG of 16384x16384 (3 channels once expanded) would decode to 3221225472 "
                   "bytes");  // `bake` drops the alpha of a colour image
    expect_refused("bake " + q(dir / "tiles.exr"), dir, "tiles.exr",
                   "needs 268435456 chunks, more than the");
    // `render --bumps` reads images as floats (the tiny PNG reached 1.58 GB there).
    expect_refused("render --bumps " + q(dir / "tiny_palette.png") + " -o " + q(dir / "out.png"),
                   dir, "tiny_palette.png", "truncated or a decompression bomb");
}

// Found by an outside probe: `--preset` on a FIFO blocked forever, on /dev/zero it grew until
// bad_alloc, a directory was "not valid JSON"; `eval --replot` read results.json the same way.
TEST(HostileInputFiles, TextInputsMustBeRegularFilesOfBoundedSize) {
    const fs::path dir = test::scratch_dir("hostile_files_text");
    ASSERT_EQ(::mkfifo((dir / "fifo.json").c_str(), 0644), 0);
    fs::create_directory(dir / "folder.json");
    expect_refused("render --preset " + q(dir / "fifo.json") + " -o " + q(dir / "a.png"), dir,
                   "fifo.json", "is not a regular file");
    expect_refused("render --preset /dev/zero -o " + q(dir / "a.png"), dir, "/dev/zero",
                   "is not a regular file");
    expect_refused("render --preset " + q(dir / "folder.json") + " -o " + q(dir / "a.png"), dir,
                   "folder.json", "is a directory, not a preset file");
    fs::create_directory(dir / "sweep");
    ASSERT_EQ(::mkfifo((dir / "sweep" / "results.json").c_str(), 0644), 0);
    expect_refused("eval --replot " + q(dir / "sweep"), dir, "results.json",
                   "is not a regular file");
    // A preset whose text holds a terminal escape sequence: escaped in the one-line message.
    std::ofstream(dir / "escape.json") << "{\"sh\\u001b[2Jading\": 1}";
    expect_refused("render --preset " + q(dir / "escape.json") + " -o " + q(dir / "a.png"), dir,
                   "escape.json", "key 'sh\\x1B[2Jading': unknown key");
}

// Found by an outside probe: `info` printed a map's header and then failed, and some broken maps
// were described by `info` or rendered by `--bumps`. Both now run the same checks, `info` all of
// them before printing: each map is one error and no output.
TEST(HostileInputFiles, InfoRefusesBrokenMapsBeforePrintingAnything) {
    const fs::path dir = test::scratch_dir("hostile_files_info");
    const Bytes good = lean_map_bytes(dir);
    write_bytes(dir / "good.ktx2", good);
    const test::RunResult ok = test::run_leanfade_bounded("info " + q(dir / "good.ktx2"), dir);
    ASSERT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_THAT(ok.out, HasSubstr("moments:"));

    constexpr std::size_t kLevelIndex = 80;
    struct Case {
        std::string file, cause;
        std::function<void(Bytes&)> edit;
    };
    const Case cases[] = {
        {"overlap.ktx2", "level 1 data (offset",
         [](Bytes& b) { store_le64(b, kLevelIndex + 24, load_le64(b, kLevelIndex)); }},
        {"in_header.ktx2", "level 4 data (offset 8, length 16) overlaps the header",
         [](Bytes& b) { store_le64(b, kLevelIndex + 4 * 24, 8); }},
        {"duplicate.ktx2", "holds the key 'LEANFADEbakedShininess' more than once",
         [](Bytes& b) {
             replace_text(b, std::string("LEANFADEroughnessBaked\0", 23),
                          std::string("LEANFADEbakedShininess\0", 23));
         }},
        {"partial.ktx2", "levelCount 3 is a partial MIP chain",
         [](Bytes& b) { store_le32(b, 40, 3); }},
        {"nan_texel.ktx2", "NaN in level 0 of lean1 at texel (0, 0)",
         [](Bytes& b) {
             const std::uint64_t level0 = load_le64(b, kLevelIndex);
             b.at(level0) = 0x00;
             b.at(level0 + 1) = 0x7E;
         }},
        {"escape.ktx2", "unsupported KTXorientation 'r\\x1B'",
         [](Bytes& b) {
             replace_text(b, std::string("KTXorientation\0rd", 17),
                          std::string("KTXorientation\0r\x1b", 17));
         }},
    };
    for (const Case& c : cases) {
        Bytes bytes = good;
        c.edit(bytes);
        write_bytes(dir / c.file, bytes);
        expect_refused("info " + q(dir / c.file), dir, c.file, c.cause);
    }
}

}  // namespace
