// Hostile input files through the real `leanfade bake` and `leanfade info` executables (the
// matrix of test_cli_bake.cpp continued with broken and malicious files, all generated here):
// each gives a one-line error naming the file and the cause, exit code 1, no output file, every
// file of the folder unchanged, within a time bound and a memory bound. Then determinism: every
// storage, height and normal maps, any thread count, byte-identical files.
#include <sys/stat.h>
#include <sys/types.h>
#include <tinyexr.h>
#include <unistd.h>
#include <zlib.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <variant>
#include <vector>

#include "hostile_bytes.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/version.hpp"
#include "tools_test_helpers.hpp"

using namespace leanfade;
using test::shell_quote;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace {

using test::Bytes;
using test::kMaxRssKib;
using test::load_be32;
using test::load_le32;
using test::q;
using test::read_bytes;
using test::store_be32;
using test::store_le32;
using test::store_le64;
using test::write_bytes;
using test::zlib_compress;
using test::append_chunk;
using test::exr_bytes;

void write_text(const fs::path& path, const std::string& text) {
    write_bytes(path, Bytes(text.begin(), text.end()));
}

// --- PNG -----------------------------------------------------------------------------------------

// Offset of the first chunk of `type` (its length field); throws when there is none.
std::size_t find_chunk(const Bytes& png, const char* type) {
    for (std::size_t at = 8; at + 8 <= png.size(); at += 12 + load_be32(png, at)) {
        if (std::memcmp(png.data() + at + 4, type, 4) == 0) return at;
    }
    throw Error("png", std::string("test PNG has no ") + type + " chunk");
}

// A smooth height map in [0, 1] (1 channel) or a normal map 0.5 n + 0.5 (3 channels).
Image test_image(int width, int height, int channels) {
    Image image(width, height, channels);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float a =
                std::sin(0.37f * float(x) + 0.11f * float(y)) * std::cos(0.23f * float(y));
            if (channels < 3) {
                for (int c = 0; c < channels; ++c) image.at(x, y, c) = 0.5f + 0.45f * a;
                continue;
            }
            const float nx = 0.4f * a, ny = 0.3f * std::cos(0.31f * float(x));
            image.at(x, y, 0) = 0.5f * nx + 0.5f;
            image.at(x, y, 1) = 0.5f * ny + 0.5f;
            image.at(x, y, 2) = 0.5f * std::sqrt(1.0f - nx * nx - ny * ny) + 0.5f;
        }
    }
    return image;
}

fs::path write_png(const fs::path& dir, const std::string& name, const Image& image, int bits) {
    const fs::path path = dir / name;
    io::write_png(path.string(), image, bits);
    return path;
}

// --- OpenEXR -------------------------------------------------------------------------------------

// A 1-channel ("Y") float OpenEXR without compression, written by tinyexr itself: it stores NaN
// and infinity, which io::write_exr refuses to write.
Bytes exr_with_values(int width, int height, const std::vector<float>& values) {
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
    std::vector<float> plane = values;
    unsigned char* planes[1] = {reinterpret_cast<unsigned char*>(plane.data())};
    EXRImage image;
    InitEXRImage(&image);
    image.images = planes;
    image.width = width;
    image.height = height;
    image.num_channels = 1;
    return exr_bytes(image, header);
}

// --- PFM -----------------------------------------------------------------------------------------

Bytes pfm(const std::string& header, const std::vector<float>& values) {
    Bytes bytes(header.begin(), header.end());
    const auto* raw = reinterpret_cast<const std::uint8_t*>(values.data());
    bytes.insert(bytes.end(), raw, raw + 4 * values.size());  // little-endian host
    return bytes;
}

// --- KTX2 ----------------------------------------------------------------------------------------

// Header field offsets (KTX 2.0 §3) and the level index.
constexpr std::size_t kVkFormat = 12, kPixelWidth = 20, kPixelHeight = 24, kLayerCount = 32,
                      kLevelCount = 40, kSupercompression = 44, kDfdOffset = 48, kKvdOffset = 56,
                      kLevelIndex = 80;

Bytes lean_map_bytes(const fs::path& dir) {
    return test::lean_map_bytes(dir, Storage::Unorm16);
}

// A valid LEAN map edited by `edit`, written to dir/name; returns the `info` arguments.
std::string hostile_ktx2(const fs::path& dir, const std::string& name,
                         const std::function<void(Bytes&)>& edit) {
    Bytes bytes = lean_map_bytes(dir);
    edit(bytes);
    write_bytes(dir / name, bytes);
    return "info " + q(dir / name);
}

// Offset of the value of key/value entry `key` in a KTX2 file.
std::size_t key_value_offset(const Bytes& bytes, const std::string& key) {
    const std::string needle = key + std::string(1, '\0');
    const auto at = std::search(bytes.begin() + std::ptrdiff_t(load_le32(bytes, kKvdOffset)),
                                bytes.end(), needle.begin(), needle.end());
    if (at == bytes.end()) throw Error("ktx2", "test map has no key " + key);
    return std::size_t(at - bytes.begin()) + needle.size();
}

// --- The matrix ----------------------------------------------------------------------------------

struct HostileCase {
    std::string name;
    // Creates the hostile file(s) in the folder; returns the leanfade arguments.
    std::function<std::string(const fs::path& dir)> make;
    std::string cause;  // what the message must say
    std::string file;   // the file name the message must give
};

std::ostream& operator<<(std::ostream& out, const HostileCase& c) {
    return out << c.name;
}

// Everything observable about a folder's entries: type, permissions and the bytes of regular
// files (never opening a FIFO or following a link).
std::map<std::string, std::string> snapshot(const fs::path& dir) {
    std::map<std::string, std::string> entries;
    for (const auto& entry : fs::directory_iterator(dir)) {
        const fs::file_status status = entry.symlink_status();
        std::string state = std::to_string(int(status.type())) + " " +
                            std::to_string(int(status.permissions())) + " ";
        if (status.type() == fs::file_type::symlink) {
            state += fs::read_symlink(entry.path()).string();
        } else if (status.type() == fs::file_type::regular) {
            // Readable by the test even when it made the file unreadable for leanfade.
            fs::permissions(entry.path(), fs::perms::owner_read, fs::perm_options::add);
            const Bytes bytes = read_bytes(entry.path());
            fs::permissions(entry.path(), status.permissions(), fs::perm_options::replace);
            state += std::string(bytes.begin(), bytes.end());
        }
        entries[entry.path().filename().string()] = state;
    }
    return entries;
}

class HostileFiles : public ::testing::TestWithParam<HostileCase> {};

TEST_P(HostileFiles, OneLineErrorExitOneNoOutputInputUnchangedBounded) {
    const HostileCase& c = GetParam();
    const fs::path dir = test::scratch_dir("hostile_" + c.name);
    const std::string args = c.make(dir);
    const auto before = snapshot(dir);

    const test::RunResult r = test::run_leanfade_bounded(args, dir, 20);
    EXPECT_NE(r.exit_code, 124) << "timed out (a hang): " << args;
    EXPECT_LT(r.exit_code, 128) << "killed by a signal (a crash): " << r.err;
    EXPECT_EQ(r.exit_code, 1) << "exit code 1 (a leanfade::Error) expected: " << r.err;
    ASSERT_FALSE(r.err.empty());
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr(c.file + ": ")) << "the message must name the file";
    EXPECT_THAT(r.err, HasSubstr(c.cause));
    EXPECT_GT(r.max_rss_kib, 0);
    EXPECT_LT(r.max_rss_kib, leanfade::test::memory_bound_kib(kMaxRssKib))
        << "a small hostile file made leanfade allocate " << r.max_rss_kib << " KiB";
    EXPECT_EQ(snapshot(dir), before) << "an output appeared or an input changed";
}

std::string bake(const fs::path& path) {
    return "bake " + q(path);
}

const HostileCase kCases[] = {
    // PNG.
    {"png_bad_crc",
     [](const fs::path& d) {
         const fs::path p = write_png(d, "crc.png", test_image(8, 8, 1), 8);
         Bytes bytes = read_bytes(p);
         bytes.at(find_chunk(bytes, "IHDR") + 8 + 13 + 3) ^= 0x55;  // last byte of IHDR's CRC
         write_bytes(p, bytes);
         return bake(p);
     },
     "IHDR: CRC error", "crc.png"},
    {"png16_idat_cut_short",
     // A 16-bit PNG whose IDAT (with a valid length and CRC) holds a third of the zlib stream.
     [](const fs::path& d) {
         const fs::path p = write_png(d, "cut16.png", test_image(32, 32, 1), 16);
         const Bytes full = read_bytes(p);
         const std::size_t idat = find_chunk(full, "IDAT");
         const std::uint32_t length = load_be32(full, idat);
         Bytes png(full.begin(), full.begin() + std::ptrdiff_t(idat));
         append_chunk(png, "IDAT",
                      Bytes(full.begin() + std::ptrdiff_t(idat + 8),
                            full.begin() + std::ptrdiff_t(idat + 8 + length / 3)));
         append_chunk(png, "IEND", {});
         write_bytes(p, png);
         return bake(p);
     },
     "corrupt PNG data (Not enough image data)", "cut16.png"},
    {"png_bomb",
     // About 80 bytes declaring 16384 x 16384 RGBA of 16 bits (2 GiB of rows, 4 GiB of floats):
     // the deflate ratio bound refuses it before libpng allocates a row.
     [](const fs::path& d) {
         Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
         Bytes ihdr(13, 0);
         store_be32(ihdr, 0, 16384);
         store_be32(ihdr, 4, 16384);
         ihdr[8] = 16;  // bit depth
         ihdr[9] = 6;   // RGBA
         append_chunk(png, "IHDR", ihdr);
         append_chunk(png, "IDAT", zlib_compress(Bytes(2048, 0)));
         append_chunk(png, "IEND", {});
         write_bytes(d / "bomb.png", png);
         return bake(d / "bomb.png");
     },
     "too short for its 16384x16384 size", "bomb.png"},
    {"png_gray_alpha_as_normal_map",
     [](const fs::path& d) {
         return "bake --from normal " + q(write_png(d, "ga.png", test_image(8, 8, 2), 8));
     },
     "a normal map needs 3 or 4 channels, this image has 2", "ga.png"},
    {"png_over_max_size",
     [](const fs::path& d) {
         return "bake --max-size 32 " + q(write_png(d, "big.png", test_image(48, 20, 1), 8));
     },
     "image size 48x20 exceeds the limit of 32 texels per side", "big.png"},
    // OpenEXR.
    {"exr_truncated",
     [](const fs::path& d) {
         const fs::path p = d / "cut.exr";
         io::write_exr(p.string(), test_image(32, 32, 1));
         Bytes bytes = read_bytes(p);
         bytes.resize(bytes.size() * 3 / 5);
         write_bytes(p, bytes);
         return bake(p);
     },
     "truncated or corrupt OpenEXR data", "cut.exr"},
    {"exr_garbled_data",
     [](const fs::path& d) {
         const fs::path p = d / "garbled.exr";
         io::write_exr(p.string(), test_image(32, 32, 3));
         Bytes bytes = read_bytes(p);
         for (std::size_t i = bytes.size() / 2; i < bytes.size(); ++i) bytes[i] = 0x5A;
         write_bytes(p, bytes);
         return bake(p);
     },
     "corrupt OpenEXR data (line 16 is in no chunk)", "garbled.exr"},
    {"exr_absurd_data_window",
     [](const fs::path& d) {
         const fs::path p = d / "window.exr";
         io::write_exr(p.string(), test_image(8, 8, 1));
         Bytes bytes = read_bytes(p);
         const std::string attribute("dataWindow\0box2i\0", 17);
         const auto at =
             std::search(bytes.begin(), bytes.end(), attribute.begin(), attribute.end());
         if (at == bytes.end()) throw Error(p.string(), "test EXR has no dataWindow");
         const std::size_t box = std::size_t(at - bytes.begin()) + attribute.size() + 4;
         store_le32(bytes, box + 8, 99999);   // xMax: 100000 wide
         store_le32(bytes, box + 12, 99999);  // yMax
         write_bytes(p, bytes);
         return bake(p);
     },
     "image size 100000x100000 exceeds the limit of 16384 texels per side", "window.exr"},
    {"exr_nan",
     [](const fs::path& d) {
         std::vector<float> values(16, 0.5f);
         values[6] = std::numeric_limits<float>::quiet_NaN();  // texel (2, 1)
         write_bytes(d / "nan.exr", exr_with_values(4, 4, values));
         return bake(d / "nan.exr");
     },
     "NaN at texel (2, 1)", "nan.exr"},
    {"exr_infinity",
     [](const fs::path& d) {
         std::vector<float> values(12, 0.5f);
         values[11] = -std::numeric_limits<float>::infinity();  // texel (3, 2)
         write_bytes(d / "inf.exr", exr_with_values(4, 3, values));
         return bake(d / "inf.exr");
     },
     "infinity at texel (3, 2)", "inf.exr"},
    // PFM.
    {"pfm_bad_header",
     [](const fs::path& d) {
         write_bytes(d / "hdr.pfm", pfm("PF\nwide 4\n-1.0\n", std::vector<float>(48, 0.5f)));
         return bake(d / "hdr.pfm");
     },
     "bad PFM width 'wide'", "hdr.pfm"},
    {"pfm_negative_size",
     [](const fs::path& d) {
         write_bytes(d / "neg.pfm", pfm("Pf\n-4 4\n-1.0\n", std::vector<float>(16, 0.5f)));
         return bake(d / "neg.pfm");
     },
     "image width or height is negative (-4x4)", "neg.pfm"},
    {"pfm_short_data",
     [](const fs::path& d) {
         Bytes bytes = pfm("Pf\n4 4\n-1.0\n", std::vector<float>(16, 0.5f));
         bytes.resize(bytes.size() - 54);  // 10 of 64 data bytes left
         write_bytes(d / "short.pfm", bytes);
         return bake(d / "short.pfm");
     },
     "truncated PFM data (10 of 64 bytes)", "short.pfm"},
    {"pfm_infinity",
     [](const fs::path& d) {
         std::vector<float> values(16, 0.25f);
         values[0] = std::numeric_limits<float>::infinity();  // first row in the file = bottom
         write_bytes(d / "inf.pfm", pfm("Pf\n4 4\n-1.0\n", values));
         return bake(d / "inf.pfm");
     },
     "infinity at texel (0, 3)", "inf.pfm"},
    {"pfm_absurd_height",
     // A finite height of 3e38 among zeros: before the slope limit, B^2 overflowed, sc became
     // infinite and the packing converted NaN to an integer (undefined behaviour; found by
     // fuzz_image_bake). The first texel in row order with the spike as a neighbour is (0, 0).
     [](const fs::path& d) {
         std::vector<float> values(16, 0.0f);
         values[9] = 3e38f;  // file row 2 (rows bottom first) = image row 1: texel (1, 1)
         write_bytes(d / "steep.pfm", pfm("Pf\n4 4\n-1.0\n", values));
         return bake(d / "steep.pfm");
     },
     "slope -3.75e+37 at texel (0, 0) is steeper than the limit of 1e6", "steep.pfm"},
    {"pfm_normal_components_near_float_max",
     // Found by fuzz_image_bake (the fast path disagreed with the reference): components near
     // the float maximum are finite, but 2 n - 1 overflows, n.xy / n.z is inf / inf = NaN, and
     // the fast path's max |B| dropped the NaN: the bake "succeeded" with a NaN map. 9 texels
     // wide, so that the AVX2 scan (8 at a time) sees the bad texel too.
     [](const fs::path& d) {
         std::vector<float> values;
         for (int x = 0; x < 9; ++x) {
             const float v = x == 2 ? 3.39e38f : 0.5f;
             values.insert(values.end(), {v, v, x == 2 ? v : 1.0f});
         }
         write_bytes(d / "huge_normal.pfm", pfm("PF\n9 1\n-1.0\n", values));
         return bake(d / "huge_normal.pfm");
     },
     "at texel (2, 0) is steeper than the limit of 1e6 (normal components far outside [0, 1])",
     "huge_normal.pfm"},
    // Not images.
    {"obj_as_image",
     [](const fs::path& d) {
         write_text(d / "mesh.png", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
         return bake(d / "mesh.png");
     },
     "unknown image format (expected PNG, OpenEXR, PFM, JPEG, TGA, DDS, TIFF, PSD", "mesh.png"},
    {"ktx2_as_image",
     [](const fs::path& d) {
         write_bytes(d / "map.ktx2", lean_map_bytes(d));
         return bake(d / "map.ktx2");
     },
     "is a KTX2 texture, not an image", "map.ktx2"},
    {"directory",
     [](const fs::path& d) {
         fs::create_directory(d / "folder.png");
         return bake(d / "folder.png");
     },
     "is a directory", "folder.png"},
    {"symlink_loop",
     [](const fs::path& d) {
         fs::create_symlink("b.png", d / "a.png");
         fs::create_symlink("a.png", d / "b.png");
         return bake(d / "a.png");
     },
     "Too many levels of symbolic links", "a.png"},
    {"unreadable_or_fifo",
     // Without read permission; as root (CI) permissions do not apply, so a FIFO without a
     // writer instead, which a blocking open() would wait on forever.
     [](const fs::path& d) {
         const fs::path p = d / "locked.png";
         if (::geteuid() == 0) {
             if (::mkfifo(p.c_str(), 0644) != 0) throw Error(p.string(), "mkfifo failed");
         } else {
             write_png(d, "locked.png", test_image(8, 8, 1), 8);
             fs::permissions(p, fs::perms::none);
         }
         return bake(p);
     },
     ::geteuid() == 0 ? "is not a regular file" : "Permission denied", "locked.png"},
    // KTX2 (leanfade info).
    {"ktx2_truncated_header",
     [](const fs::path& d) {
         return hostile_ktx2(d, "short.ktx2", [](Bytes& b) { b.resize(50); });
     },
     "truncated KTX2 header", "short.ktx2"},
    {"ktx2_level_count_past_chain",
     [](const fs::path& d) {
         return hostile_ktx2(d, "levels.ktx2", [](Bytes& b) { store_le32(b, kLevelCount, 9); });
     },
     "levelCount 9 exceeds the 5 levels of a 16x16 MIP chain", "levels.ktx2"},
    {"ktx2_offset_past_end",
     [](const fs::path& d) {
         return hostile_ktx2(d, "offset.ktx2",
                             [](Bytes& b) { store_le64(b, kLevelIndex, b.size() + 64); });
     },
     "level 0 data (offset", "offset.ktx2"},
    {"ktx2_offset_overflow",
     [](const fs::path& d) {
         return hostile_ktx2(d, "wrap.ktx2", [](Bytes& b) {
             store_le64(b, kLevelIndex + 24, ~std::uint64_t(0) - 7);  // offset + length wraps
         });
     },
     "runs past the end of the file", "wrap.ktx2"},
    {"ktx2_four_layers",
     [](const fs::path& d) {
         return hostile_ktx2(d, "layers.ktx2", [](Bytes& b) { store_le32(b, kLayerCount, 4); });
     },
     "layerCount 4 (a LEAN map has 2 layers", "layers.ktx2"},
    {"ktx2_plateau_layer_missing",
     [](const fs::path& d) {
         // A two-layer map that says it has the plateau layer: its levels are too short.
         return hostile_ktx2(d, "three.ktx2", [](Bytes& b) { store_le32(b, kLayerCount, 3); });
     },
     "byteLength", "three.ktx2"},
    {"ktx2_wrong_vk_format",
     [](const fs::path& d) {
         return hostile_ktx2(d, "srgb.ktx2", [](Bytes& b) { store_le32(b, kVkFormat, 43); });
     },
     "unsupported vkFormat 43", "srgb.ktx2"},
    {"ktx2_absurd_size",
     [](const fs::path& d) {
         return hostile_ktx2(d, "huge.ktx2", [](Bytes& b) {
             store_le32(b, kPixelWidth, 100000);
             store_le32(b, kPixelHeight, 100000);
         });
     },
     "image size 100000x100000 exceeds the limit of 16384", "huge.ktx2"},
    {"ktx2_key_value_length_past_end",
     [](const fs::path& d) {
         return hostile_ktx2(d, "kvlen.ktx2",
                             [](Bytes& b) { store_le32(b, load_le32(b, kKvdOffset), 0x00FFFFFF); });
     },
     "key/value entry of 16777215 bytes runs past the key/value data", "kvlen.ktx2"},
    {"ktx2_dfd_size_mismatch",
     [](const fs::path& d) {
         return hostile_ktx2(d, "dfd.ktx2", [](Bytes& b) {
             const std::size_t dfd = load_le32(b, kDfdOffset);
             store_le32(b, dfd, load_le32(b, dfd) + 4);
         });
     },
     "dfdTotalSize", "dfd.ktx2"},
    {"ktx2_level_length_wrong",
     [](const fs::path& d) {
         return hostile_ktx2(d, "length.ktx2",
                             [](Bytes& b) { store_le64(b, kLevelIndex + 8, 16 * 16 * 8 * 2 - 8); });
     },
     "level 0 byteLength 4088", "length.ktx2"},
    {"ktx2_supercompressed",
     [](const fs::path& d) {
         return hostile_ktx2(d, "basis.ktx2",
                             [](Bytes& b) { store_le32(b, kSupercompression, 1); });
     },
     "supercompressionScheme 1 (BasisLZ) is not supported", "basis.ktx2"},
    {"ktx2_scale_not_a_number",
     [](const fs::path& d) {
         return hostile_ktx2(d, "scale.ktx2",
                             [](Bytes& b) { b.at(key_value_offset(b, "LEANFADEscale")) = 'x'; });
     },
     "bad LEANFADEscale value 'x", "scale.ktx2"},
};

INSTANTIATE_TEST_SUITE_P(Matrix, HostileFiles, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<HostileCase>& info) {
                             return info.param.name;
                         });

TEST(HostileMatrix, HasAtLeastFifteenDistinctFiles) {
    std::vector<std::string> names;
    for (const HostileCase& c : kCases) names.push_back(c.file);
    std::sort(names.begin(), names.end());
    EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end());
    EXPECT_GE(names.size(), 15u);
}

// --- Determinism ---------------------------------------------------------------------------------

struct DeterminismCase {
    std::string bits;
    bool normal_map;
};

std::ostream& operator<<(std::ostream& out, const DeterminismCase& c) {
    return out << c.bits << (c.normal_map ? " normal" : " height");
}

class Determinism : public ::testing::TestWithParam<DeterminismCase> {};

// Odd, non-square sizes, so that every MIP reduction has 3-tap rows and columns and the rows
// split unevenly between threads.
TEST_P(Determinism, SameBytesForAnyThreadCountAndRunAndAsTheLibrary) {
    const DeterminismCase& c = GetParam();
    const fs::path dir =
        test::scratch_dir("determinism_" + c.bits + (c.normal_map ? "_normal" : "_height"));
    const Image image = c.normal_map ? test_image(37, 53, 3) : test_image(61, 47, 1);
    const fs::path input = write_png(dir, "in.png", image, c.normal_map ? 8 : 16);

    std::vector<Bytes> outputs;
    for (const char* threads : {"1", "2", "2", "3"}) {
        const fs::path out = dir / ("out" + std::to_string(outputs.size()) + ".ktx2");
        const auto r = test::run_leanfade_bounded(
            "bake " + q(input) + " --bits " + c.bits + " --threads " + threads + " -o " + q(out),
            dir, 60);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        outputs.push_back(read_bytes(out));
    }
    for (std::size_t i = 1; i < outputs.size(); ++i) {
        EXPECT_EQ(outputs[i], outputs[0]) << "run " << i << " differs from run 0";
    }

    // The same bytes as the library's reference path (decode, bake, pack, write) in-process.
    const Storage storage = c.bits == "8"     ? Storage::Unorm8
                            : c.bits == "16"  ? Storage::Unorm16
                            : c.bits == "16f" ? Storage::Float16
                                              : Storage::Float32;
    BakeOptions options;
    options.threads = 1;
    const BakeResult baked =
        bake_lean_map(io::read_image(input.string()), BakeSource::Auto, options);
    const fs::path reference = dir / "reference.ktx2";
    // With the plateau layer the packed bake adds (leanfade/core/detail/plateau.hpp).
    PackedLeanMap packed =
        pack_lean_map(baked.map, storage, std::string("leanfade ") + LEANFADE_VERSION);
    // The rule takes the PNG's quantisation step (8-bit normals, 16-bit heights).
    const auto samples = std::get<UnormImage>(io::read_image_compact(input.string()));
    add_plateau_layer(packed, options.plateau_epsilon, 1,
                      source_slope_step(baked.source,
                                        samples.effective_max_code(c.normal_map ? 3 : 1),
                                        options.strength));
    // A map with nothing flat stores no layer.
    if (plateau_fraction(packed) == 0.0f) remove_plateau_layer(packed);
    // As `bake` writes by default: Zstandard level 3.
    io::WriteOptions zstd;
    zstd.supercompression = io::Supercompression::Zstandard;
    zstd.zstd_level = 3;
    io::write_ktx2(reference.string(), packed, zstd);
    EXPECT_EQ(read_bytes(reference), outputs[0]);
}

INSTANTIATE_TEST_SUITE_P(
    EveryStorage, Determinism,
    ::testing::Values(DeterminismCase{"8", false}, DeterminismCase{"16", false},
                      DeterminismCase{"16f", false}, DeterminismCase{"32f", false},
                      DeterminismCase{"8", true}, DeterminismCase{"16", true},
                      DeterminismCase{"16f", true}, DeterminismCase{"32f", true}),
    [](const ::testing::TestParamInfo<DeterminismCase>& info) {
        return (info.param.bits == "16f"   ? std::string("f16")
                : info.param.bits == "32f" ? std::string("f32")
                                           : "unorm" + info.param.bits) +
               (info.param.normal_map ? "_normal" : "_height");
    });

}  // namespace
