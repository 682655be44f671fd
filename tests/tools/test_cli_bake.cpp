// `leanfade bake` and `leanfade info` end to end, including every kind of bad input: each gives a
// one-line error naming the file and the cause, a non-zero exit, no output file, and the input
// unchanged.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <filesystem>
#include <fstream>
#include <vector>

#include "tools_test_helpers.hpp"
#include "leanfade/core/procedural.hpp"
#include "leanfade/io/image_io.hpp"

using namespace leanfade;
using test::run_leanfade;
using test::shell_quote;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace {

std::uint32_t crc32(const std::uint8_t* data, std::size_t n, std::uint32_t crc = 0) {
    crc = ~crc;
    for (std::size_t i = 0; i < n; ++i) {
        crc ^= data[i];
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

void put_be32(std::vector<std::uint8_t>& v, std::uint32_t x) {
    for (int s = 24; s >= 0; s -= 8) v.push_back(std::uint8_t(x >> s));
}

void add_chunk(std::vector<std::uint8_t>& png, const char* type,
               const std::vector<std::uint8_t>& data) {
    put_be32(png, std::uint32_t(data.size()));
    std::vector<std::uint8_t> body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    png.insert(png.end(), body.begin(), body.end());
    put_be32(png, crc32(body.data(), body.size()));
}

// A PNG whose header declares w x h RGB pixels (no pixel data: a decoder must refuse the size
// from the header alone, before allocating).
std::vector<std::uint8_t> png_header_only(std::uint32_t w, std::uint32_t h) {
    std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    std::vector<std::uint8_t> ihdr;
    put_be32(ihdr, w);
    put_be32(ihdr, h);
    ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});
    add_chunk(png, "IHDR", ihdr);
    add_chunk(png, "IEND", {});
    return png;
}

void write_bytes(const fs::path& p, const std::vector<std::uint8_t>& bytes) {
    std::ofstream out(p, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

std::vector<std::uint8_t> read_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

fs::path write_height_png(const fs::path& dir, const std::string& name, int size = 32) {
    Image h = make_builtin_height("bumps", size, 4);
    float hi = 0;
    for (float v : h.pixels) hi = std::max(hi, v);
    for (float& v : h.pixels) v /= hi;
    const fs::path p = dir / name;
    io::write_png(p.string(), h, 16);
    return p;
}

fs::path write_normal_png(const fs::path& dir, const std::string& name, float z_encoded = 1.0f) {
    Image n(8, 8, 3);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
            n.at(x, y, 0) = 0.5f + 0.05f * float(x % 3);
            n.at(x, y, 1) = 0.5f - 0.04f * float(y % 2);
            n.at(x, y, 2) = z_encoded;
        }
    const fs::path p = dir / name;
    io::write_png(p.string(), n, 8);
    return p;
}

std::size_t file_count(const fs::path& dir) {
    std::size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.is_regular_file() ? 1 : 0;
    return n;
}

}  // namespace

TEST(CliBake, BuiltinBakesAKtx2AndPrintsASummary) {
    const fs::path dir = test::scratch_dir("bake_builtin");
    const fs::path out = dir / "bumps.ktx2";
    const auto r = run_leanfade("bake --builtin bumps --size 64 -o " + shell_quote(out.string()),
                                dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(out));
    EXPECT_THAT(r.out, HasSubstr("64x64, 7 levels"));
    EXPECT_THAT(r.out, HasSubstr("sc = "));
    EXPECT_THAT(r.out, HasSubstr("anisotropy"));
    EXPECT_EQ(r.err, "");  // not a terminal: no progress line

    const auto info = run_leanfade("info " + shell_quote(out.string()), dir);
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_THAT(info.out, HasSubstr("R16G16B16A16_UNORM"));
    EXPECT_THAT(info.out, HasSubstr("LEANFADEscale"));
}

TEST(CliBake, BatchWritesOneOutputPerInputIntoOutDir) {
    const fs::path dir = test::scratch_dir("bake_batch");
    const fs::path a = write_height_png(dir, "a.png");
    const fs::path b = write_normal_png(dir, "b.png");
    fs::create_directories(dir / "out");
    const auto r = run_leanfade("bake " + shell_quote(a.string()) + " " + shell_quote(b.string()) +
                                    " --bits 8 --out-dir " + shell_quote((dir / "out").string()) +
                                    " --json " + shell_quote((dir / "out" / "summary.json").string()),
                                dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "out" / "a.ktx2"));
    EXPECT_TRUE(fs::exists(dir / "out" / "b.ktx2"));
    EXPECT_THAT(r.out, HasSubstr("height map"));
    EXPECT_THAT(r.out, HasSubstr("normal map"));
    EXPECT_THAT(test::read_text(dir / "out" / "summary.json"), HasSubstr("\"coarsest_anisotropy\""));
}

TEST(CliBake, PngFormatWritesTwo16BitPreviews) {
    const fs::path dir = test::scratch_dir("bake_png");
    const auto r = run_leanfade("bake --builtin ridges --size 32 --format png -o " +
                                    shell_quote((dir / "ridges").string()),
                                dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* layer : {"ridges.lean1.png", "ridges.lean2.png"}) {
        const Image img = io::read_image((dir / layer).string());
        EXPECT_EQ(img.width, 32);
        EXPECT_EQ(img.channels, 4);
    }
}

TEST(CliBake, SameInputGivesByteIdenticalFilesForAnyThreadCount) {
    const fs::path dir = test::scratch_dir("bake_determinism");
    const fs::path in = write_height_png(dir, "h.png", 96);
    for (const char* t : {"1", "2"}) {
        const auto r = run_leanfade("bake " + shell_quote(in.string()) + " --threads " + t +
                                        " -o " + shell_quote((dir / (std::string(t) + ".ktx2")).string()),
                                    dir);
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    const auto again = run_leanfade("bake " + shell_quote(in.string()) + " --threads 2 -o " +
                                        shell_quote((dir / "again.ktx2").string()),
                                    dir);
    ASSERT_EQ(again.exit_code, 0);
    EXPECT_EQ(read_bytes(dir / "1.ktx2"), read_bytes(dir / "2.ktx2"));
    EXPECT_EQ(read_bytes(dir / "2.ktx2"), read_bytes(dir / "again.ktx2"));
}

TEST(CliBake, ExistingOutputIsReplacedAtomically) {
    const fs::path dir = test::scratch_dir("bake_replace");
    const fs::path out = dir / "m.ktx2";
    write_bytes(out, {1, 2, 3});
    const auto r = run_leanfade("bake --builtin checker --size 16 -o " + shell_quote(out.string()),
                                dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_GT(fs::file_size(out), 100u);
    EXPECT_EQ(file_count(dir), 1u);  // no temporary left behind
}

// One bad-input case: what to create, the arguments, and what the message must say.
struct BadCase {
    std::string name;
    std::function<std::string(const fs::path& dir)> make;  // returns the arguments
    std::string expect_in_message;
    std::string expect_file;  // a path fragment the message must name ("" = the case's input)
};

class CliBakeBadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(CliBakeBadInput, OneLineErrorNonZeroExitNoOutputInputUnchanged) {
    const BadCase& c = GetParam();
    const fs::path dir = test::scratch_dir("bad_" + c.name);
    const std::string args = c.make(dir);
    // Snapshot every file before the run: none may change and none may appear.
    std::map<fs::path, std::vector<std::uint8_t>> before;
    for (const auto& e : fs::directory_iterator(dir)) before[e.path()] = read_bytes(e.path());

    const auto r = run_leanfade(args, dir);
    EXPECT_NE(r.exit_code, 0) << r.err;
    EXPECT_NE(r.exit_code, 3) << "internal error instead of a clear message: " << r.err;
    ASSERT_FALSE(r.err.empty());
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr(c.expect_in_message));
    EXPECT_THAT(r.err, HasSubstr(c.expect_file));

    std::map<fs::path, std::vector<std::uint8_t>> after;
    for (const auto& e : fs::directory_iterator(dir)) after[e.path()] = read_bytes(e.path());
    EXPECT_EQ(before, after) << "an output appeared or an input changed";
}

std::string q(const fs::path& p) { return shell_quote(p.string()); }

INSTANTIATE_TEST_SUITE_P(
    Matrix, CliBakeBadInput,
    ::testing::Values(
        BadCase{"missing", [](const fs::path& d) { return "bake " + q(d / "nope.png"); },
                "No such file", "nope.png"},
        BadCase{"empty",
                [](const fs::path& d) {
                    write_bytes(d / "empty.png", {});
                    return "bake " + q(d / "empty.png");
                },
                "empty file", "empty.png"},
        BadCase{"garbage",
                [](const fs::path& d) {
                    write_bytes(d / "junk.png", {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd'});
                    return "bake " + q(d / "junk.png");
                },
                "unknown image format", "junk.png"},
        BadCase{"truncated",
                [](const fs::path& d) {
                    const fs::path p = write_height_png(d, "t.png", 64);
                    auto bytes = read_bytes(p);
                    bytes.resize(bytes.size() / 2);
                    write_bytes(p, bytes);
                    return "bake " + q(p);
                },
                "truncated", "t.png"},
        BadCase{"zero_width",
                [](const fs::path& d) {
                    write_bytes(d / "zero.png", png_header_only(0, 16));
                    return "bake " + q(d / "zero.png");
                },
                "width or height is 0", "zero.png"},
        BadCase{"absurd_size",
                [](const fs::path& d) {
                    write_bytes(d / "huge.png", png_header_only(100000, 100000));
                    return "bake " + q(d / "huge.png");
                },
                "100000", "huge.png"},
        BadCase{"normal_below_horizon",
                [](const fs::path& d) { return "bake " + q(write_normal_png(d, "n.png", 0.2f)); },
                "z <= 0", "n.png"},
        BadCase{"normal_from_one_channel",
                [](const fs::path& d) {
                    return "bake --from normal " + q(write_height_png(d, "g.png"));
                },
                "channels", "g.png"},
        BadCase{"nan_in_pfm",
                [](const fs::path& d) {
                    Image img(4, 4, 1, 0.5f);
                    img.at(1, 2) = std::nanf("");
                    std::ofstream out(d / "nan.pfm", std::ios::binary);
                    out << "Pf\n4 4\n-1.0\n";
                    out.write(reinterpret_cast<const char*>(img.pixels.data()),
                              std::streamsize(img.pixels.size() * 4));
                    return "bake " + q(d / "nan.pfm");
                },
                "NaN", "nan.pfm"},
        BadCase{"unknown_flag",
                [](const fs::path& d) { return "bake --builtin bumps --frobnicate -o " + q(d / "x.ktx2"); },
                "frobnicate", ""},
        BadCase{"bad_bits",
                [](const fs::path& d) { return "bake --builtin bumps --bits 12 -o " + q(d / "x.ktx2"); },
                "--bits", ""},
        BadCase{"bad_size",
                [](const fs::path& d) { return "bake --builtin bumps --size 0 -o " + q(d / "x.ktx2"); },
                "--size", ""},
        BadCase{"nan_strength",
                [](const fs::path& d) {
                    return "bake --builtin bumps --strength nan -o " + q(d / "x.ktx2");
                },
                "strength", ""},
        BadCase{"output_is_input",
                [](const fs::path& d) {
                    const fs::path p = write_height_png(d, "same.png");
                    return "bake " + q(p) + " -o " + q(p);
                },
                "same file", "same.png"},
        BadCase{"one_output_many_inputs",
                [](const fs::path& d) {
                    return "bake " + q(write_height_png(d, "a.png")) + " " +
                           q(write_height_png(d, "b.png")) + " -o " + q(d / "x.ktx2");
                },
                "--out-dir", ""},
        BadCase{"missing_out_dir",
                [](const fs::path& d) {
                    return "bake " + q(write_height_png(d, "a.png")) + " --out-dir " +
                           q(d / "no" / "such");
                },
                "does not exist", "such"},
        BadCase{"info_on_png",
                [](const fs::path& d) { return "info " + q(write_height_png(d, "notktx.png")); },
                "not a KTX 2.0 file", "notktx.png"},
        BadCase{"info_truncated_ktx2",
                [](const fs::path& d) {
                    const fs::path out = d / "tmp.ktx2";
                    test::run_leanfade("bake --builtin bumps --size 16 -o " + q(out), d);
                    auto bytes = read_bytes(out);
                    fs::remove(out);
                    bytes.resize(bytes.size() - 40);
                    write_bytes(d / "cut.ktx2", bytes);
                    return "info " + q(d / "cut.ktx2");
                },
                "past the end", "cut.ktx2"}),
    [](const ::testing::TestParamInfo<BadCase>& info) { return info.param.name; });
