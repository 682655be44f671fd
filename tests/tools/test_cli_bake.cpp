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
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"
#include "leanfade/io/detail/png_io.hpp"

#include <nlohmann/json.hpp>

using namespace leanfade;
using test::run_leanfade;
using test::shell_quote;
using ::testing::HasSubstr;
using ::testing::Not;
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
    const auto r =
        run_leanfade("bake " + shell_quote(a.string()) + " " + shell_quote(b.string()) +
                         " --bits 8 --out-dir " + shell_quote((dir / "out").string()) + " --json " +
                         shell_quote((dir / "out" / "summary.json").string()),
                     dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "out" / "a.ktx2"));
    EXPECT_TRUE(fs::exists(dir / "out" / "b.ktx2"));
    EXPECT_THAT(r.out, HasSubstr("height map"));
    EXPECT_THAT(r.out, HasSubstr("normal map"));
    EXPECT_THAT(test::read_text(dir / "out" / "summary.json"),
                HasSubstr("\"coarsest_anisotropy\""));
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
        const auto r =
            run_leanfade("bake " + shell_quote(in.string()) + " --threads " + t + " -o " +
                             shell_quote((dir / (std::string(t) + ".ktx2")).string()),
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
                    write_bytes(d / "junk.png",
                                {'h', 'e', 'l', 'l', 'o', ' ', 'w', 'o', 'r', 'l', 'd'});
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
                [](const fs::path& d) {
                    return "bake --strict-normals " + q(write_normal_png(d, "n.png", 0.2f));
                },
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
                [](const fs::path& d) {
                    return "bake --builtin bumps --frobnicate -o " + q(d / "x.ktx2");
                },
                "frobnicate", ""},
        BadCase{"bad_bits",
                [](const fs::path& d) {
                    return "bake --builtin bumps --bits 12 -o " + q(d / "x.ktx2");
                },
                "--bits", ""},
        BadCase{
            "bad_size",
            [](const fs::path& d) { return "bake --builtin bumps --size 0 -o " + q(d / "x.ktx2"); },
            "--size", ""},
        BadCase{"nan_strength",
                [](const fs::path& d) {
                    return "bake --builtin bumps --strength nan -o " + q(d / "x.ktx2");
                },
                "strength", ""},
        BadCase{"output_is_input",
                [](const fs::path& d) {
                    const fs::path p = write_height_png(d, "same.ktx2");  // a PNG so named
                    return "bake " + q(p) + " -o " + q(p);
                },
                "same file", "same.ktx2"},
        BadCase{"one_output_many_inputs",
                [](const fs::path& d) {
                    return "bake " + q(write_height_png(d, "a.png")) + " " +
                           q(write_height_png(d, "b.png")) + " -o " + q(d / "x.ktx2");
                },
                "--out-dir", ""},
        BadCase{"out_dir_under_a_file",
                [](const fs::path& d) {
                    return "bake " + q(write_height_png(d, "a.png")) + " --out-dir " +
                           q(d / "a.png" / "such");
                },
                "is not a folder", "such"},
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

// ---- Outputs, strength and precision rules ---------------------------------------------------

namespace {

// The bit depth a PNG file declares (IHDR byte 24).
int png_bit_depth(const fs::path& p) {
    const std::vector<std::uint8_t> bytes = read_bytes(p);
    return bytes.size() > 24 ? int(bytes[24]) : -1;
}

// An 8-bit RGB normal map of gentle bumps (the rgb of a bake's lean1), with `outliers` texels
// turned into a normal along +x at the horizon (1, 0.5, 0.5): z = 1/255 raised to 1/64, the
// issue's "one texel raised to z = 1/64" (slope 64).
fs::path write_bumpy_normal_png(const fs::path& dir, const std::string& name, int size,
                                int outliers) {
    const fs::path base = dir / (name + "_src");
    const auto r = run_leanfade("bake --builtin bumps --size " + std::to_string(size) +
                                    " --format png -o " + shell_quote(base.string() + ".png"),
                                dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    const Image lean1 = io::read_image(base.string() + ".lean1.png");
    Image normals(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            for (int c = 0; c < 3; ++c) normals.at(x, y, c) = lean1.at(x, y, c);
    for (int i = 0; i < outliers; ++i) {
        const int x = (size / 3 + 17 * i) % size, y = (size / 2 + 29 * i) % size;
        normals.at(x, y, 0) = 1.0f;
        normals.at(x, y, 1) = 0.5f;
        normals.at(x, y, 2) = 0.5f;
    }
    fs::remove(base.string() + ".lean1.png");
    fs::remove(base.string() + ".lean2.png");
    const fs::path p = dir / (name + ".png");
    io::write_png(p.string(), normals, 8);
    return p;
}

// PSNR (dB) of two sets of linear radiance images, values clamped to [0, 1] (the displayable
// range), the mean square error taken over every pixel and channel of all of them.
double psnr(const std::vector<Image>& a, const std::vector<Image>& b) {
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].pixels.size(), b[i].pixels.size());
        for (std::size_t k = 0; k < a[i].pixels.size(); ++k) {
            const double d = std::clamp(a[i].pixels[k], 0.0f, 1.0f) -
                             std::clamp(b[i].pixels[k], 0.0f, 1.0f);
            sum += d * d;
        }
        count += a[i].pixels.size();
    }
    return sum == 0.0 ? 1e9 : 10.0 * std::log10(double(count) / sum);
}

// LEAN renders of a map at three distances (near: magnified texels; far: coarse MIP levels),
// as linear radiance.
std::vector<Image> lean_cells(const fs::path& dir, const fs::path& map, const std::string& tag,
                              const std::string& extra_args = "") {
    const fs::path cells = dir / ("cells_" + tag);
    const auto r = run_leanfade("render --scene sphere --techniques lean --distances 1.6,4,12 "
                                "--size 128x128 --bumps " + q(map) + " --cells " + q(cells) +
                                    " -o " + q(dir / ("grid_" + tag + ".png")) + " " +
                                    extra_args,
                                dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::vector<fs::path> files;
    if (fs::is_directory(cells))
        for (const auto& e : fs::directory_iterator(cells))
            if (e.path().extension() == ".pfm") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    EXPECT_EQ(files.size(), 3u);
    std::vector<Image> images;
    for (const fs::path& f : files) images.push_back(io::read_image(f.string()));
    return images;
}

}  // namespace

TEST(CliBakeOutputs, APngNameWritesThePngPairAndOtherNamesAreRefused) {
    const fs::path dir = test::scratch_dir("bake_infer_format");
    const auto png = run_leanfade("bake --builtin bumps --size 32 -o " + q(dir / "m.png"), dir);
    ASSERT_EQ(png.exit_code, 0) << png.err;
    EXPECT_TRUE(fs::exists(dir / "m.lean1.png"));
    EXPECT_TRUE(fs::exists(dir / "m.lean2.png"));
    EXPECT_TRUE(fs::exists(dir / "m.plateau.png")) << "the plateau layer's file";
    EXPECT_FALSE(fs::exists(dir / "m.png")) << "a KTX2 file named .png";
    const auto ktx2 = run_leanfade("bake --builtin bumps --size 32 -o " + q(dir / "m.ktx2"), dir);
    ASSERT_EQ(ktx2.exit_code, 0) << ktx2.err;
    EXPECT_EQ(io::inspect_ktx2((dir / "m.ktx2").string()).levels.size(), 6u);

    for (const std::string& args :
         {"-o " + q(dir / "x.png") + " --format ktx2", "-o " + q(dir / "x.ktx2") + " --format png",
          "-o " + q(dir / "x.PNG") + " --format ktx2"}) {
        const auto r = run_leanfade("bake --builtin bumps --size 32 " + args, dir);
        EXPECT_NE(r.exit_code, 0) << args;
        EXPECT_THAT(r.err, HasSubstr("-o")) << args;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    EXPECT_EQ(file_count(dir), 4u) << "a refused run wrote something";
}

TEST(CliBakeOutputs, PngPairHasTheBitDepthOfBitsAndRefusesFloatStorages) {
    const fs::path dir = test::scratch_dir("bake_png_bits");
    for (const char* bits : {"8", "16"}) {
        const fs::path base = dir / (std::string("b") + bits);
        const auto r = run_leanfade(std::string("bake --builtin ridges --size 32 --format png ") +
                                        "--bits " + bits + " -o " + q(base),
                                    dir);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_EQ(png_bit_depth(base.string() + ".lean1.png"), std::stoi(bits));
        EXPECT_EQ(png_bit_depth(base.string() + ".lean2.png"), std::stoi(bits));
    }
    for (const char* bits : {"16f", "32f"}) {
        const auto r = run_leanfade(std::string("bake --builtin ridges --size 32 --format png ") +
                                        "--bits " + bits + " -o " + q(dir / "f"),
                                    dir);
        EXPECT_NE(r.exit_code, 0);
        EXPECT_THAT(r.err, HasSubstr("--bits"));
        EXPECT_FALSE(fs::exists(dir / "f.lean1.png"));
    }
}

TEST(CliBakeOutputs, PngPairCarriesScAndLoadsBackAsTheKtx2Map) {
    const fs::path dir = test::scratch_dir("bake_png_pair_sc");
    const fs::path input = write_height_png(dir, "h.png", 64);
    for (const char* bits : {"8", "16"}) {
        const std::string tag = std::string("h") + bits;
        const auto pair = run_leanfade("bake " + q(input) + " --strength 8 --bits " + bits +
                                           " -o " + q(dir / (tag + ".png")),
                                       dir);
        ASSERT_EQ(pair.exit_code, 0) << pair.err;
        const auto ktx2 = run_leanfade("bake " + q(input) + " --strength 8 --bits " + bits +
                                           " -o " + q(dir / (tag + ".ktx2")),
                                       dir);
        ASSERT_EQ(ktx2.exit_code, 0) << ktx2.err;
        const PackedLeanMap expected = io::read_ktx2((dir / (tag + ".ktx2")).string());
        for (const char* layer : {".lean1.png", ".lean2.png"}) {
            const PackedLeanMap loaded = io::read_lean_png_pair((dir / (tag + layer)).string());
            EXPECT_EQ(loaded.scale, expected.scale) << "sc from the text chunk";
            EXPECT_NE(loaded.scale, 1.0f);
            EXPECT_EQ(loaded.storage, expected.storage);
            ASSERT_EQ(loaded.levels.size(), expected.levels.size());
            EXPECT_EQ(loaded.levels[0].lean1, expected.levels[0].lean1);
            EXPECT_EQ(loaded.levels[0].lean2, expected.levels[0].lean2);
            EXPECT_EQ(loaded.plateau_epsilon, expected.plateau_epsilon);
            EXPECT_EQ(loaded.levels[0].plateau, expected.levels[0].plateau);
            // Coarser levels: rebuilt from the quantised top level, within one code or two.
            const float code = std::string(bits) == "8" ? 1.0f / 255.0f : 1.0f / 65535.0f;
            for (int l = 1; l < int(loaded.levels.size()); ++l)
                for (int y = 0; y < loaded.levels[std::size_t(l)].height; ++y)
                    for (int x = 0; x < loaded.levels[std::size_t(l)].width; ++x)
                        for (int s = 0; s < 2; ++s) {
                            const glm::vec4 a = fetch_packed_texel(loaded, l, s, x, y);
                            const glm::vec4 b = fetch_packed_texel(expected, l, s, x, y);
                            for (int c = 0; c < 4; ++c)
                                ASSERT_LE(std::abs(a[c] - b[c]), 2.5f * code)
                                    << bits << " level " << l << " slice " << s;
                        }
        }
    }
    // `--bumps NAME.lean1.png` renders it (the sc chunk read back), like the KTX2 map.
    const std::vector<Image> from_png = lean_cells(dir, dir / "h16.lean1.png", "png");
    const std::vector<Image> from_ktx2 = lean_cells(dir, dir / "h16.ktx2", "ktx2");
    ASSERT_EQ(from_png.size(), 3u);
    EXPECT_GT(psnr(from_png, from_ktx2), 60.0);
    // A pair whose text chunks are gone is refused, naming the file.
    const Image plain = io::read_image((dir / "h16.lean2.png").string());
    io::write_png((dir / "h16.lean2.png").string(), plain, 16);
    const auto r = run_leanfade("render --techniques lean --distances 2 --size 32x32 --bumps " +
                                    q(dir / "h16.lean1.png") + " -o " + q(dir / "no.png"),
                                dir);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_THAT(r.err, HasSubstr("h16.lean2.png"));
    EXPECT_THAT(r.err, HasSubstr("LEANFADElayout"));
    EXPECT_FALSE(fs::exists(dir / "no.png"));
}

TEST(CliBakeOutputs, BatchJsonListsFailuresAndSuccesses) {
    const fs::path dir = test::scratch_dir("bake_batch_json_failures");
    const fs::path good = write_height_png(dir, "good.png");
    write_bytes(dir / "bad.png", {'n', 'o', 't', ' ', 'a', ' ', 'p', 'n', 'g'});
    fs::create_directories(dir / "out");
    const auto r = run_leanfade("bake " + q(good) + " " + q(dir / "bad.png") + " --out-dir " +
                                    q(dir / "out") + " --json " + q(dir / "summary.json"),
                                dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    const auto json = nlohmann::json::parse(test::read_text(dir / "summary.json"));
    ASSERT_TRUE(json.is_array());
    ASSERT_EQ(json.size(), 2u);
    EXPECT_EQ(json[0]["input"], good.string());
    EXPECT_TRUE(json[0].contains("output"));
    EXPECT_FALSE(json[0].contains("error"));
    EXPECT_EQ(json[1]["input"], (dir / "bad.png").string());
    EXPECT_THAT(json[1]["error"].get<std::string>(), HasSubstr("bad.png"));
    EXPECT_FALSE(json[1].contains("output"));
}

TEST(CliStrength, ZeroIsRefusedByBakeAndRender) {
    const fs::path dir = test::scratch_dir("strength_zero");
    const auto bake = run_leanfade("bake --builtin bumps --size 16 --strength 0 -o " +
                                       q(dir / "z.ktx2"),
                                   dir);
    EXPECT_NE(bake.exit_code, 0);
    EXPECT_THAT(bake.err, HasSubstr("--strength"));
    const auto render = run_leanfade("render --bumps bumps --strength 0 --distances 2 --size "
                                     "32x32 -o " + q(dir / "z.png"),
                                     dir);
    EXPECT_NE(render.exit_code, 0);
    EXPECT_THAT(render.err, HasSubstr("--strength"));
    EXPECT_EQ(file_count(dir), 0u);
    // A negative strength renders (it inverts the heights).
    const auto negative = run_leanfade("render --bumps bumps --strength -2 --techniques lean "
                                       "--distances 2 --size 32x32 -o " + q(dir / "n.png"),
                                       dir);
    EXPECT_EQ(negative.exit_code, 0) << negative.err;
}

TEST(CliStrength, NegativeStrengthNegatesTheSlopes) {
    const fs::path dir = test::scratch_dir("strength_negative");
    const fs::path input = write_height_png(dir, "h.png", 32);
    for (const char* k : {"3", "-3"}) {
        const auto r = run_leanfade("bake " + q(input) + " --bits 32f --strength " + k + " -o " +
                                        q(dir / (std::string("k") + k + ".ktx2")),
                                    dir);
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    const LeanMap up = unpack_lean_map(io::read_ktx2((dir / "k3.ktx2").string()));
    const LeanMap down = unpack_lean_map(io::read_ktx2((dir / "k-3.ktx2").string()));
    ASSERT_EQ(up.scale, down.scale);
    float largest = 0.0f;
    for (std::size_t i = 0; i < up.levels[0].mean.size(); ++i) {
        EXPECT_NEAR(down.levels[0].mean[i].x, -up.levels[0].mean[i].x, 1e-5f);
        EXPECT_NEAR(down.levels[0].mean[i].y, -up.levels[0].mean[i].y, 1e-5f);
        EXPECT_NEAR(down.levels[0].second[i].x, up.levels[0].second[i].x, 1e-4f);
        largest = std::max(largest, std::abs(up.levels[0].mean[i].x));
    }
    EXPECT_GT(largest, 0.1f);
}

TEST(CliStrength, StrengthForANormalMapIsAnError) {
    const fs::path dir = test::scratch_dir("strength_normal_map");
    const fs::path normals = write_normal_png(dir, "n.png");
    const auto bake = run_leanfade("bake " + q(normals) + " --strength 2 -o " + q(dir / "n.ktx2"),
                                   dir);
    EXPECT_NE(bake.exit_code, 0);
    EXPECT_THAT(bake.err, HasSubstr("n.png"));
    EXPECT_THAT(bake.err, HasSubstr("--strength"));
    EXPECT_FALSE(fs::exists(dir / "n.ktx2"));
    const auto explicit_normal =
        run_leanfade("bake " + q(normals) + " --from normal --strength 2 -o " + q(dir / "n.ktx2"),
                     dir);
    EXPECT_NE(explicit_normal.exit_code, 0);
    EXPECT_THAT(explicit_normal.err, HasSubstr("--strength"));
    const auto render = run_leanfade("render --bumps " + q(normals) +
                                         " --strength 2 --distances 2 --size 32x32 -o " +
                                         q(dir / "n_render.png"),
                                     dir);
    EXPECT_NE(render.exit_code, 0);
    EXPECT_THAT(render.err, HasSubstr("--strength"));
    EXPECT_FALSE(fs::exists(dir / "n_render.png"));
    // Without --strength the normal map bakes.
    const auto plain = run_leanfade("bake " + q(normals) + " -o " + q(dir / "n.ktx2"), dir);
    EXPECT_EQ(plain.exit_code, 0) << plain.err;
}

TEST(CliStrength, UvUnitGivesTheSameSlopesAtTwiceTheResolution) {
    const fs::path dir = test::scratch_dir("strength_uv");
    // The same smooth height field sampled at 64 and 128 texels.
    for (int size : {64, 128}) {
        Image h(size, size, 1);
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const double u = (x + 0.5) / size, v = (y + 0.5) / size;
                h.at(x, y) = float(0.5 + 0.25 * std::sin(2 * M_PI * u) * std::cos(2 * M_PI * v));
            }
        io::write_png((dir / ("h" + std::to_string(size) + ".png")).string(), h, 16);
    }
    auto mean_slope = [&](int size, const std::string& unit, float strength) {
        const fs::path json = dir / ("s" + std::to_string(size) + unit + ".json");
        const auto r = run_leanfade(
            "bake " + q(dir / ("h" + std::to_string(size) + ".png")) + " --strength " +
                std::to_string(strength) + " --strength-unit " + unit + " -o " +
                q(dir / ("m" + std::to_string(size) + unit + ".ktx2")) + " --json " + q(json),
            dir);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return nlohmann::json::parse(test::read_text(json))[0]["mean_slope"].get<double>();
    };
    const double uv64 = mean_slope(64, "uv", 0.2f), uv128 = mean_slope(128, "uv", 0.2f);
    EXPECT_GT(uv64, 0.1);
    EXPECT_NEAR(uv128 / uv64, 1.0, 0.02);
    // Per texel, the same strength gives half the slopes at twice the resolution.
    const double texel64 = mean_slope(64, "texel", 2.0f), texel128 = mean_slope(128, "texel", 2.0f);
    EXPECT_NEAR(texel128 / texel64, 0.5, 0.02);
    // uv strength K = texel strength K * size.
    EXPECT_NEAR(mean_slope(64, "texel", 0.2f * 64), uv64, 1e-4 * uv64);
}

TEST(CliBakePrecision, DefaultStorageKeepsTheHighlightOfAMapWithAHorizontalTexel) {
    const fs::path dir = test::scratch_dir("bake_precision_outlier");
    const fs::path input = write_bumpy_normal_png(dir, "n", 128, 1);
    auto bake = [&](const std::string& args, const std::string& name) {
        const auto r = run_leanfade("bake " + q(input) + " " + args + " -o " +
                                        q(dir / (name + ".ktx2")),
                                    dir);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return r.out;
    };
    const std::string default_out = bake("", "default");
    EXPECT_THAT(default_out, HasSubstr("1 normals had z < 0.0156"));
    EXPECT_THAT(default_out, HasSubstr("1 texels (0.0061 %) have a slope component above sc"));
    EXPECT_THAT(default_out, HasSubstr("storage 16f")) << "auto storage: outliers need 16f";
    bake("--bits 32f", "float");
    bake("--bits 16 --sc max", "all_within");
    const std::vector<Image> truth = lean_cells(dir, dir / "float.ktx2", "float");
    const double kept = psnr(lean_cells(dir, dir / "default.ktx2", "default"), truth);
    const double lost = psnr(lean_cells(dir, dir / "all_within.ktx2", "all_within"), truth);
    EXPECT_GE(kept, 50.0) << "default storage against 32f";
    // For contrast: sc = 64 for every texel loses the highlight.
    EXPECT_LT(lost, 45.0) << "16-bit with sc = the maximum against 32f";
    RecordProperty("psnr_default_db", std::to_string(kept));
    RecordProperty("psnr_sc_max_db", std::to_string(lost));
}

// render bakes images on the fly with the same rule as bake (--bits auto by default).
TEST(CliBakePrecision, RenderBakesOnTheFlyKeepTheHighlightOfAMapWithAHorizontalTexel) {
    const fs::path dir = test::scratch_dir("render_precision_outlier");
    const fs::path input = write_bumpy_normal_png(dir, "n", 128, 1);
    const std::vector<Image> truth = lean_cells(dir, input, "float", "--bits 32f");
    const double kept = psnr(lean_cells(dir, input, "default"), truth);
    const double unorm = psnr(lean_cells(dir, input, "unorm16", "--bits 16"), truth);
    EXPECT_GE(kept, 50.0) << "render's default on-the-fly storage against 32f";
    RecordProperty("psnr_render_default_db", std::to_string(kept));
    RecordProperty("psnr_render_unorm16_db", std::to_string(unorm));
    std::printf("render on the fly, PSNR against 32f: default %.1f dB, --bits 16 %.1f dB\n", kept,
                unorm);
}

TEST(CliBakeConvention, WarnsWhenANormalMapFitsTheOtherConventionBetter) {
    const fs::path dir = test::scratch_dir("bake_convention");
    const fs::path normals = write_bumpy_normal_png(dir, "opengl", 96, 0);  // OpenGL (+Y)
    const auto right = run_leanfade("bake " + q(normals) + " -o " + q(dir / "a.ktx2"), dir);
    ASSERT_EQ(right.exit_code, 0) << right.err;
    EXPECT_EQ(right.err, "");
    const auto wrong =
        run_leanfade("bake " + q(normals) + " --directx -o " + q(dir / "b.ktx2"), dir);
    ASSERT_EQ(wrong.exit_code, 0) << wrong.err;
    EXPECT_THAT(wrong.err, HasSubstr("opengl.png looks like an OpenGL (+Y) normal map"));
    EXPECT_EQ(std::count(wrong.err.begin(), wrong.err.end(), '\n'), 1) << wrong.err;
    // Ridges along one axis fit both conventions: no warning either way.
    const fs::path base = dir / "ridges_src";
    ASSERT_EQ(run_leanfade("bake --builtin ridges --size 64 --format png -o " +
                               q(base.string() + ".png"), dir).exit_code, 0);
    Image ridges = io::read_image(base.string() + ".lean1.png");
    Image rgb(ridges.width, ridges.height, 3);
    for (int y = 0; y < rgb.height; ++y)
        for (int x = 0; x < rgb.width; ++x)
            for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = ridges.at(x, y, c);
    io::write_png((dir / "ridges.png").string(), rgb, 8);
    for (const char* flag : {"", "--directx"}) {
        const auto r = run_leanfade("bake " + q(dir / "ridges.png") + " " + flag + " -o " +
                                        q(dir / "r.ktx2"),
                                    dir);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_EQ(r.err, "") << flag;
    }
}

namespace {

// A bumpy 8-bit normal map (write_bumpy_normal_png) with the imperfections of real assets: the
// (0, 0, 0) padding a baker leaves outside the UV islands (the right quarter and the bottom
// rows), and `below` texels authored slightly below the surface (z = -0.1).
fs::path write_padded_normal_png(const fs::path& dir, const std::string& name, int size,
                                 int below, std::uint64_t& padding) {
    const Image source = io::read_image(write_bumpy_normal_png(dir, name + "_bumpy", size, 0)
                                            .string());
    Image normals = source;
    padding = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            if (x >= size * 3 / 4 || y >= size - 5) {
                for (int c = 0; c < 3; ++c) normals.at(x, y, c) = 0.0f;
                ++padding;
            }
    for (int i = 0; i < below; ++i) normals.at(3 + 5 * i, 7 + 3 * i, 2) = 115.0f / 255.0f;
    const fs::path p = dir / (name + ".png");
    io::write_png(p.string(), normals, 8);
    return p;
}

}  // namespace

TEST(CliBakeImperfectNormals, PaddingAndNegativeZAreRepairedReportedAndStoredUnlessStrict) {
    const fs::path dir = test::scratch_dir("bake_imperfect_normals");
    std::uint64_t padding = 0;
    const fs::path input = write_padded_normal_png(dir, "padded", 64, 5, padding);
    ASSERT_GT(padding, 0u);
    const fs::path json = dir / "padded.json";
    const auto r = run_leanfade("bake " + q(input) + " -o " + q(dir / "padded.ktx2") +
                                    " --json " + q(json),
                                dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string note = input.string() + ": " + std::to_string(padding) +
                             " (0, 0, 0) padding texels taken as flat, 5 texels with z <= 0 "
                             "raised (--strict-normals refuses them)";
    EXPECT_THAT(r.out, HasSubstr(note));
    const nlohmann::json summary = nlohmann::json::parse(test::read_text(json))[0];
    EXPECT_EQ(summary["padding_texels"].get<std::uint64_t>(), padding);
    EXPECT_EQ(summary["raised_normals"].get<std::uint64_t>(), 5u);
    // Stored in the file and shown by info.
    const auto info = run_leanfade("info " + q(dir / "padded.ktx2"), dir);
    ASSERT_EQ(info.exit_code, 0) << info.err;
    EXPECT_THAT(info.out, HasSubstr("LEANFADEpaddingTexels = " + std::to_string(padding)));
    EXPECT_THAT(info.out, HasSubstr("LEANFADEraisedTexels = 5"));
    const PackedLeanMap map = io::read_ktx2((dir / "padded.ktx2").string());
    EXPECT_EQ(map.normal_repairs.padding_texels, padding);
    EXPECT_EQ(map.normal_repairs.raised_texels, 5u);
    // A clean map has neither the keys nor the note.
    const auto clean = run_leanfade("bake " + q(dir / "padded_bumpy.png") + " -o " +
                                        q(dir / "clean.ktx2"),
                                    dir);
    ASSERT_EQ(clean.exit_code, 0) << clean.err;
    EXPECT_THAT(clean.out, Not(HasSubstr("padding")));
    const auto clean_info = run_leanfade("info " + q(dir / "clean.ktx2"), dir);
    EXPECT_THAT(clean_info.out, Not(HasSubstr("LEANFADEpaddingTexels")));

    // --strict-normals refuses the first such texel (rows top first: padding at x = 48), on one
    // line in the command line's words, and writes nothing.
    const auto strict = run_leanfade("bake --strict-normals " + q(input) + " -o " +
                                         q(dir / "strict.ktx2"),
                                     dir);
    EXPECT_EQ(strict.exit_code, 1);
    EXPECT_THAT(strict.err, HasSubstr("padded.png: normal with z <= 0 at texel (48, 0)"));
    EXPECT_THAT(strict.err, HasSubstr("refused by --strict-normals"));
    EXPECT_THAT(strict.err, HasSubstr("read it with --from height"));
    EXPECT_THAT(strict.err, Not(HasSubstr("'from'")));
    EXPECT_EQ(std::count(strict.err.begin(), strict.err.end(), '\n'), 1) << strict.err;
    EXPECT_FALSE(fs::exists(dir / "strict.ktx2"));

    // render --bumps bakes it on the fly with the same policy and the same note.
    const auto rendered = run_leanfade("render --scene plane --techniques lean --distances 2 "
                                       "--size 32x32 --bumps " + q(input) + " -o " +
                                           q(dir / "render.png"),
                                       dir);
    ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
    EXPECT_THAT(rendered.err, HasSubstr(note));
    const auto render_strict = run_leanfade("render --scene plane --techniques lean --distances 2 "
                                            "--size 32x32 --strict-normals --bumps " +
                                                q(input) + " -o " + q(dir / "strict.png"),
                                            dir);
    EXPECT_EQ(render_strict.exit_code, 1);
    EXPECT_THAT(render_strict.err, HasSubstr("refused by --strict-normals"));
}

// A floor of planks (flat but for a faint grain, slopes about 0.01) with 1-texel gaps between
// them whose walls are steep (slope 32 at strength 128): 4 % of the texels, no outliers (they are
// not 0.1 %), so sc = 32. 16-bit UNORM then rounds M to sc^2 / 65535 = 0.016, more than the
// base variance 1/s of every shininess above 64: the highlight of the planks is lost. --bits
// auto predicts it (auto_storage) and bakes half floats.
TEST(CliBakePrecision, DefaultStorageKeepsTheHighlightOfPlanksWithSteepGaps) {
    const fs::path dir = test::scratch_dir("bake_precision_planks");
    const int size = 256, width = 64, length = 256;
    Image height(size, size, 1);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const int column = x / width;
            const int along = (y + (length / 2) * (column % 2)) % size;  // staggered planks
            const bool gap = x % width == 0 || along % length == 0;
            const double u = double(3 * x + along) / size, v = double(along) / size;
            height.at(x, y) = gap ? 0.0f
                                  : float(0.5 + 1e-4 * std::sin(2 * M_PI * 5 * u) +
                                          0.6e-4 * std::sin(2 * M_PI * 17 * v + column));
        }
    const fs::path input = dir / "planks.png";
    io::write_png(input.string(), height, 16);
    const fs::path json = dir / "default.json";
    auto bake = [&](const std::string& args, const std::string& name) {
        const auto r = run_leanfade("bake " + q(input) + " --strength 128 " + args + " -o " +
                                        q(dir / (name + ".ktx2")),
                                    dir);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return r.out;
    };
    const std::string default_out = bake("--json " + q(json), "default");
    EXPECT_THAT(default_out, HasSubstr("storage 16f")) << default_out;
    const nlohmann::json summary = nlohmann::json::parse(test::read_text(json))[0];
    EXPECT_EQ(summary["texels_beyond_sc"].get<std::uint64_t>(), 0u);  // not the outlier rule
    EXPECT_GT(summary["scale"].get<double>(), 30.0);
    bake("--bits 32f", "float");
    bake("--bits 16", "unorm");
    const std::vector<Image> truth = lean_cells(dir, dir / "float.ktx2", "float");
    const double kept = psnr(lean_cells(dir, dir / "default.ktx2", "default"), truth);
    const double unorm = psnr(lean_cells(dir, dir / "unorm.ktx2", "unorm"), truth);
    EXPECT_GE(kept, 50.0) << "default storage against 32f";
    EXPECT_LT(unorm, 40.0) << "16-bit UNORM against 32f";  // the failure the rule avoids
    RecordProperty("psnr_default_db", std::to_string(kept));
    RecordProperty("psnr_unorm16_db", std::to_string(unorm));
    std::printf("planks, PSNR against 32f: default (16f) %.1f dB, --bits 16 %.1f dB\n", kept,
                unorm);
    // render's on-the-fly bake follows the same rule.
    const double on_the_fly =
        psnr(lean_cells(dir, input, "on_the_fly", "--strength 128"), truth);
    EXPECT_GE(on_the_fly, 50.0) << "render --bumps planks.png against the 32f bake";
}

// `bake` and `info` say how much of a map is flat and in the spike; a map with nothing flat (noise,
// with the plateaus alone forming the spike) stores no layer of zeros, and --plateau-out still
// writes its (zero) layer.
TEST(CliBakePlateauLayer, ReportsTheFlatFractionAndStoresNoEmptyLayer) {
    const fs::path dir = test::scratch_dir("bake_plateau_fraction");
    const fs::path bumps = dir / "bumps.ktx2", noise = dir / "noise.ktx2";
    const auto flat = run_leanfade("bake --builtin bumps --size 512 -o " + q(bumps), dir);
    ASSERT_EQ(flat.exit_code, 0) << flat.err;
    EXPECT_THAT(flat.out, HasSubstr("flat (two-lobe LEAN's plateaus): "));
    EXPECT_THAT(flat.out, HasSubstr("radius 2x2 texels"));
    EXPECT_EQ(io::inspect_ktx2(bumps.string()).layer_count, 3u);
    EXPECT_THAT(flat.out, HasSubstr("spike's share (two-lobe LEAN's f): "));
    EXPECT_THAT(run_leanfade("info " + q(bumps), dir).out, HasSubstr("of the texels in the spike"));
    const auto none = run_leanfade("bake --builtin noise --size 128 --spike plateaus --plateau-out " +
                                       q(dir / "noise.plateau.ktx2") + " -o " + q(noise),
                                   dir);
    ASSERT_EQ(none.exit_code, 0) << none.err;
    EXPECT_THAT(none.out, HasSubstr("no plateau layer stored"));
    EXPECT_EQ(io::inspect_ktx2(noise.string()).layer_count, 2u);
    EXPECT_THAT(run_leanfade("info " + q(noise), dir).out, HasSubstr("without a plateau layer"));
    const std::vector<Image> zero = io::read_ktx2_rgba16f((dir / "noise.plateau.ktx2").string());
    ASSERT_FALSE(zero.empty());
    for (float v : zero.front().pixels) ASSERT_EQ(v, 0.0f);
}

// The plateau layer of two-lobe LEAN is part of every bake unless --plateau-epsilon 0; `info`
// says which a map is, and a map without the layer renders two-lobe as LEAN, bit for bit.
TEST(CliBakePlateauLayer, DefaultBakesTheLayerAndEpsilonZeroBakesNone) {
    const fs::path dir = test::scratch_dir("bake_plateau_layer");
    const fs::path with = dir / "with.ktx2", without = dir / "without.ktx2";
    ASSERT_EQ(run_leanfade("bake --builtin bumps --size 64 -o " + q(with), dir).exit_code, 0);
    const auto r = run_leanfade(
        "bake --builtin bumps --size 64 --plateau-epsilon 0 -o " + q(without), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(io::inspect_ktx2(with.string()).layer_count, 3u);
    EXPECT_EQ(io::inspect_ktx2(without.string()).layer_count, 2u);
    EXPECT_EQ(io::read_ktx2(with.string()).plateau_epsilon, kDefaultPlateauEpsilon);
    EXPECT_THAT(run_leanfade("info " + q(with), dir).out, HasSubstr("with two-lobe LEAN's plateau"));
    EXPECT_THAT(run_leanfade("info " + q(without), dir).out, HasSubstr("without a plateau layer"));
    // The moments are the same either way.
    const PackedLeanMap a = io::read_ktx2(with.string()), b = io::read_ktx2(without.string());
    ASSERT_EQ(a.levels.size(), b.levels.size());
    for (std::size_t l = 0; l < a.levels.size(); ++l) {
        EXPECT_EQ(a.levels[l].lean1, b.levels[l].lean1);
        EXPECT_EQ(a.levels[l].lean2, b.levels[l].lean2);
    }
    for (const char* bad : {"-1", "nan", "inf"}) {
        const auto refused = run_leanfade(
            std::string("bake --builtin bumps --size 16 --plateau-epsilon ") + bad + " -o " +
                q(dir / "bad.ktx2"),
            dir);
        EXPECT_NE(refused.exit_code, 0) << bad;
        EXPECT_THAT(refused.err, HasSubstr("--plateau-epsilon")) << bad;
        EXPECT_FALSE(fs::exists(dir / "bad.ktx2"));
    }
    const auto no_layer_out = run_leanfade("bake --builtin bumps --size 16 --plateau-epsilon 0 -o " +
                                               q(dir / "x.ktx2") + " --plateau-out " +
                                               q(dir / "x.plateau.ktx2"),
                                           dir);
    EXPECT_NE(no_layer_out.exit_code, 0);
    EXPECT_THAT(no_layer_out.err, HasSubstr("--plateau-out"));
}
