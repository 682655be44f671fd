// `leanfade bake --roughness-out / --anisotropy-out` end to end (docs/roughness.md): the KTX2 files
// read back with the project's KTX2 reader as plain 2D RGBA8 textures with every level, their
// texels equal the core's roughness MIPs of the same input, a PNG per level, a glTF
// metallic-roughness input changes in G only, and bad flags or inputs write nothing.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>

#include <glm/gtc/packing.hpp>

#include "leanfade/core/lean_map.hpp"
#include "leanfade/core/detail/plateau.hpp"
#include "leanfade/core/detail/procedural.hpp"
#include "leanfade/core/roughness.hpp"
#include "leanfade/io/detail/basis_universal.hpp"
#include "leanfade/io/detail/block_compression.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"
#include "leanfade/io/detail/png_io.hpp"
#include "tools_test_helpers.hpp"

using namespace leanfade;
using test::run_leanfade;
using test::shell_quote;
using ::testing::HasSubstr;
namespace fs = std::filesystem;

namespace {

// A 32 x 32 height map with bumps, as a 16-bit grey PNG.
fs::path write_height_map(const fs::path& dir) {
    Image height = make_builtin_height("bumps", 32, 3);
    const fs::path path = dir / "height.png";
    io::write_png(path.string(), height, 16);
    return path;
}

// The roughness MIPs the core computes for the same file and base roughness.
std::vector<RoughnessLevel> expected_levels(const fs::path& height_png, float r0,
                                            const Image* map = nullptr) {
    const Image height = io::read_image(height_png.string());
    BakeOptions options;
    const LeanMap lean = bake_lean_map(height, BakeSource::Height, options).map;
    RoughnessOptions ro;
    ro.base_roughness = r0;
    ro.roughness_map = map;
    return roughness_mips(lean, ro);
}

std::string file_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

int byte(float v) {
    return int(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
}

TEST(CliBakeRoughness, WritesKtx2AndPngLevelsOfTheCoreRoughnessMips) {
    const fs::path dir = test::scratch_dir("bake_roughness");
    const fs::path height = write_height_map(dir);
    const fs::path rough = dir / "rough.ktx2", aniso = dir / "aniso.ktx2";
    const auto r = run_leanfade("bake " + shell_quote(height.string()) + " -o " +
                                    shell_quote((dir / "map.ktx2").string()) +
                                    " --roughness-out " + shell_quote(rough.string()) +
                                    " --roughness 0.3 --roughness-levels --anisotropy-out " +
                                    shell_quote(aniso.string()),
                                dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_TRUE(fs::exists(dir / "map.ktx2"));

    const std::vector<RoughnessLevel> want = expected_levels(height, 0.3f);
    const std::vector<io::Rgba8Level> mr = io::read_ktx2_rgba8(rough.string());
    const std::vector<io::Rgba8Level> normal =
        io::read_ktx2_rgba8((dir / "rough.normal.ktx2").string());
    const std::vector<io::Rgba8Level> an = io::read_ktx2_rgba8(aniso.string());
    ASSERT_EQ(mr.size(), want.size());  // 32 x 32: 6 levels
    ASSERT_EQ(mr.size(), 6u);
    ASSERT_EQ(normal.size(), want.size());
    ASSERT_EQ(an.size(), want.size());
    const io::Ktx2Info info = io::inspect_ktx2(rough.string());
    EXPECT_EQ(info.vk_format, io::kVkFormatR8G8B8A8Unorm);
    EXPECT_EQ(info.layer_count, 0u);
    EXPECT_EQ(info.data_format.transfer_function, 1u);  // linear: data, not colour
    // Each file says what it holds (docs/ktx2.md).
    for (const auto& [file, content] :
         {std::pair{rough, "roughness v1"}, std::pair{dir / "rough.normal.ktx2", "normal v1"},
          std::pair{aniso, "anisotropy v1"}}) {
        // The description outlives the pointer into it (a temporary's was read after free).
        const io::Ktx2Info described = io::inspect_ktx2(file.string());
        const std::string* value = described.find(io::kKeyTextureContent);
        ASSERT_NE(value, nullptr) << file;
        EXPECT_EQ(*value, content);
    }
    double coarse_r = 0.0;
    for (std::size_t l = 0; l < want.size(); ++l) {
        ASSERT_EQ(mr[l].width, want[l].width);
        for (std::size_t t = 0; t < want[l].alpha.size(); ++t) {
            const std::uint8_t* texel = &mr[l].texels[4 * t];
            EXPECT_EQ(texel[1], byte(std::sqrt(want[l].alpha[t]))) << "level " << l;
            EXPECT_EQ(texel[0], 255);  // occlusion none (ORM)
            EXPECT_EQ(texel[2], 0);    // metallic 0
            EXPECT_EQ(texel[3], 255);
            const glm::vec3 n = want[l].normal[t];
            EXPECT_EQ(normal[l].texels[4 * t], byte(0.5f * n.x + 0.5f));
            EXPECT_EQ(normal[l].texels[4 * t + 2], byte(0.5f * n.z + 0.5f));
            EXPECT_EQ(an[l].texels[4 * t + 2],
                      byte(anisotropy_strength(want[l].alpha_t[t], want[l].alpha_b[t])));
        }
        if (l + 1 == want.size()) coarse_r = mr[l].texels[1] / 255.0;
        // A PNG per level, equal to the KTX2 level.
        const Image png =
            io::read_image((dir / "rough.levels" / ("roughness_mip" + std::to_string(l) + ".png"))
                               .string());
        ASSERT_EQ(png.width, mr[l].width);
        EXPECT_EQ(byte(png.at(0, 0, 1)), mr[l].texels[1]);
        EXPECT_TRUE(fs::exists(dir / "rough.levels" / ("normal_mip" + std::to_string(l) + ".png")));
        EXPECT_TRUE(
            fs::exists(dir / "rough.levels" / ("anisotropy_mip" + std::to_string(l) + ".png")));
    }
    // The bumps' slope variance raises the coarse roughness above the base 0.3.
    EXPECT_GT(coarse_r, 0.35);
}

// With a glTF metallic-roughness texture as the base, only G changes: R, B, A of level 0 are the
// input's bytes, and G is the input's r where the bumps are flat at level 0.
TEST(CliBakeRoughness, MetallicRoughnessInputChangesOnlyG) {
    const fs::path dir = test::scratch_dir("bake_roughness_gltf");
    const fs::path height = write_height_map(dir);
    Image mr_in(32, 32, 4);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            mr_in.at(x, y, 0) = float((x * 7) % 256) / 255.0f;       // occlusion
            mr_in.at(x, y, 1) = float(40 + (x + y) % 100) / 255.0f;  // roughness
            mr_in.at(x, y, 2) = float((y * 5) % 256) / 255.0f;       // metallic
            mr_in.at(x, y, 3) = float(200 + (x % 50)) / 255.0f;
        }
    const fs::path input = dir / "mr.png";
    io::write_png(input.string(), mr_in, 8);
    const Image read_back = io::read_image(input.string());
    const fs::path rough = dir / "rough.ktx2";
    const auto r = run_leanfade("bake " + shell_quote(height.string()) + " -o " +
                                    shell_quote((dir / "map.ktx2").string()) +
                                    " --roughness-out " + shell_quote(rough.string()) +
                                    " --roughness-map " + shell_quote(input.string()),
                                dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::vector<io::Rgba8Level> mr = io::read_ktx2_rgba8(rough.string());
    Image base(32, 32, 1);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) base.at(x, y) = read_back.at(x, y, 1);
    const std::vector<RoughnessLevel> want = expected_levels(height, 0.0f, &base);
    int g_changed = 0;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const std::uint8_t* t = &mr[0].texels[4 * std::size_t(y * 32 + x)];
            EXPECT_EQ(t[0], byte(read_back.at(x, y, 0)));
            EXPECT_EQ(t[2], byte(read_back.at(x, y, 2)));
            EXPECT_EQ(t[3], byte(read_back.at(x, y, 3)));
            EXPECT_EQ(t[1], byte(std::sqrt(want[0].alpha[std::size_t(y * 32 + x)])));
            if (t[1] != byte(read_back.at(x, y, 1))) ++g_changed;
        }
    // Level 0 has no slope variance (one slope per texel): G is the input's r, up to rounding.
    EXPECT_LE(g_changed, 32 * 32 / 10);
    // Coarser levels: G grows with the filtered variance, R B A are the input filtered.
    EXPECT_GT(mr.back().texels[1], mr[0].texels[1] / 2);
}

TEST(CliBakeRoughness, RoughnessMapOfAnotherSizeIsResampled) {
    // An 8 x 8 map of r = 0.5 beside the 32 x 32 height map: resampled (as a glTF's
    // metallic-roughness texture is), so every level-0 texel has G = 0.5 (no slope variance
    // within one texel).
    const fs::path dir = test::scratch_dir("bake_roughness_resampled");
    const fs::path height = write_height_map(dir);
    io::write_png((dir / "small.png").string(), Image(8, 8, 1, 0.5f), 8);
    const fs::path rough = dir / "rough.ktx2";
    const auto r = run_leanfade("bake " + shell_quote(height.string()) + " --roughness-out " +
                                    shell_quote(rough.string()) + " --roughness-map " +
                                    shell_quote((dir / "small.png").string()),
                                dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::vector<io::Rgba8Level> mr = io::read_ktx2_rgba8(rough.string());
    ASSERT_EQ(mr.front().width, 32);
    // r = 128 / 255 as stored; G = r up to the rounding of r -> alpha -> sqrt.
    for (std::size_t t = 0; t < 32 * 32; ++t)
        EXPECT_NEAR(int(mr.front().texels[4 * t + 1]), 128, 1) << t;
}

TEST(CliBakeRoughness, BadFlagsAndInputsWriteNothing) {
    const fs::path dir = test::scratch_dir("bake_roughness_bad");
    const fs::path height = write_height_map(dir);
    const std::string base = "bake " + shell_quote(height.string()) + " -o " +
                             shell_quote((dir / "map.ktx2").string());
    const std::string rough = " --roughness-out " + shell_quote((dir / "rough.ktx2").string());
    struct Bad {
        std::string args;
        std::string message;
    };
    Image small(8, 8, 1, 0.5f);
    io::write_png((dir / "small.png").string(), small, 8);
    // A float map with a roughness beyond 1: the library's error names the map's file (the map is
    // resampled to the LEAN map's size first, so the value reported is an interpolated one).
    Image over(8, 8, 1, 0.5f);
    over.at(3, 2) = 1.5f;
    io::write_pfm((dir / "over.pfm").string(), over);
    const Bad cases[] = {
        {rough + " --roughness-map " + shell_quote((dir / "over.pfm").string()),
         "over.pfm: roughness 1."},
        {rough + " --roughness 1.5", "--roughness"},
        {rough + " --roughness 0.2 --roughness-map " + shell_quote((dir / "small.png").string()),
         "not both"},
        {rough + " --roughness-map " + shell_quote((dir / "missing.png").string()), "missing.png"},
        {rough + " --bake-roughness 100", "--roughness-out"},
        {" --roughness 0.2", "--roughness"},
        {" --roughness-out " + shell_quote((dir / "rough.png").string()), "ktx2"},
        {" --compress bc", "--compress"},
        {" --roughness-out " + shell_quote((dir / "rough.dds").string()) + " --compress basis",
         "DDS has no Basis Universal"},
        {rough + " --compress ''", "--compress"},
        // The names only: the enumerators' numbers are no values of the flags.
        {rough + " --compress 1", "--compress"},
        {rough + " --supercompression 0", "--supercompression"},
        {" --roughness-out " + shell_quote((dir / "rough.dds").string()) + " --compress astc",
         "DDS has no ASTC"},
    };
    for (const Bad& c : cases) {
        const auto r = run_leanfade(base + c.args, dir);
        EXPECT_NE(r.exit_code, 0) << c.args;
        EXPECT_THAT(r.err, HasSubstr(c.message)) << c.args;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(dir / "rough.ktx2")) << c.args;
        EXPECT_FALSE(fs::exists(dir / "map.ktx2")) << c.args;
        EXPECT_FALSE(fs::exists(dir / "rough.levels")) << c.args;
    }
}

// --compress bc|astc: the engine textures as block-compressed KTX2 (checked by vkFormat) or DDS,
// every level decoding within the stated error (docs/compression.md) of the uncompressed file's
// level; the LEAN map is the same bytes as without --compress.
TEST(CliBakeRoughness, CompressWritesBlockCompressedLevelsOfTheUncompressedTextures) {
    const fs::path dir = test::scratch_dir("bake_roughness_compress");
    const fs::path height = write_height_map(dir);
    const auto bake = [&](const std::string& name, const std::string& extension,
                          const std::string& compress) {
        const auto r = run_leanfade(
            "bake " + shell_quote(height.string()) + " -o " +
                shell_quote((dir / (name + ".map.ktx2")).string()) + " --roughness 0.3" +
                " --roughness-out " + shell_quote((dir / (name + extension)).string()) +
                " --anisotropy-out " + shell_quote((dir / (name + ".aniso" + extension)).string()) +
                compress,
            dir);
        EXPECT_EQ(r.exit_code, 0) << r.err;
    };
    bake("plain", ".ktx2", "");
    bake("bc", ".ktx2", " --compress bc");
    bake("astc", ".ktx2", " --compress astc");
    bake("dds", ".dds", " --compress bc");
    EXPECT_EQ(file_bytes(dir / "plain.map.ktx2"), file_bytes(dir / "bc.map.ktx2"));
    const struct {
        std::string suffix;
        io::EngineTexture texture;
        std::uint32_t bc_vk, astc_vk, dxgi;
        int tolerance;  // largest difference of a stored channel, 8-bit codes
    } files[] = {{".ktx2", io::EngineTexture::Roughness, 139, 157, 80, 12},
                 {".normal.ktx2", io::EngineTexture::Normal, 141, 157, 83, 20},
                 {".aniso.ktx2", io::EngineTexture::Anisotropy, 131, 157, 71, 255}};
    for (const auto& f : files) {
        const std::vector<io::Rgba8Level> plain = io::read_ktx2_rgba8((dir / ("plain" + f.suffix)).string());
        for (const io::BlockCompression c : {io::BlockCompression::Bc, io::BlockCompression::Astc}) {
            const std::string path = (dir / (io::to_string(c) + f.suffix)).string();
            EXPECT_EQ(io::inspect_ktx2(path).vk_format,
                      c == io::BlockCompression::Bc ? f.bc_vk : f.astc_vk) << path;
            const auto levels = io::read_ktx2_compressed(path, io::block_format(c, f.texture));
            ASSERT_EQ(levels.size(), plain.size()) << path;
            const auto decoded = io::decompress_levels(levels, c, f.texture);
            for (std::size_t l = 0; l < plain.size(); ++l) {
                int largest = 0;
                for (std::size_t i = 0; i < plain[l].texels.size(); i += 4)
                    for (int ch = 0; ch < 2; ++ch) {
                        // Roughness: G; normals: x, y.
                        const std::size_t at = i + std::size_t(f.texture == io::EngineTexture::Roughness ? 1 : ch);
                        largest = std::max(largest, std::abs(int(plain[l].texels[at]) - int(decoded[l].texels[at])));
                    }
                EXPECT_LE(largest, f.tolerance) << path << " level " << l;
            }
        }
        const std::string dds_suffix = f.suffix.substr(0, f.suffix.size() - 5) + ".dds";
        const io::DdsFile dds = io::read_dds((dir / ("dds" + dds_suffix)).string());
        EXPECT_EQ(dds.dxgi_format, f.dxgi);
        const auto bc = io::read_ktx2_compressed((dir / ("bc" + f.suffix)).string(),
                                                 io::block_format(io::BlockCompression::Bc, f.texture));
        ASSERT_EQ(dds.levels.size(), bc.size());
        for (std::size_t l = 0; l < bc.size(); ++l) EXPECT_EQ(dds.levels[l].blocks, bc[l].blocks);
    }
    // `info` reads them.
    const auto info = run_leanfade("info " + shell_quote((dir / "bc.normal.ktx2").string()), dir);
    EXPECT_EQ(info.exit_code, 0) << info.err;
    EXPECT_THAT(info.out, HasSubstr("VK_FORMAT_BC5_UNORM_BLOCK"));
    EXPECT_THAT(info.out, HasSubstr("KTXswizzle = rg01"));
}

// --compress basis: Basis Universal UASTC KTX2 (what glTF's KHR_texture_basisu takes), every
// level of the uncompressed chain, Zstandard-supercompressed, described as non-colour data
// (primaries unspecified, linear), RGB; transcoded by three.js's Basis Universal transcoder (not
// the encoder that wrote them), each level within UASTC's error of the uncompressed level
// (measured on this map: at most 3 codes in roughness, 13 in a normal's x and y; the
// anisotropy file is checked for its container only).
TEST(CliBakeRoughness, CompressBasisWritesUastcOfEveryLevelOfTheUncompressedTextures) {
    ASSERT_NE(std::string(LEANFADE_NODE).find('/'), std::string::npos) << "Node.js is missing";
    const fs::path dir = test::scratch_dir("bake_roughness_basis");
    const fs::path height = write_height_map(dir);
    for (const std::string name : {"plain", "basis"}) {
        const auto r = run_leanfade(
            "bake " + shell_quote(height.string()) + " --roughness 0.3 --roughness-out " +
                shell_quote((dir / (name + ".ktx2")).string()) + " --anisotropy-out " +
                shell_quote((dir / (name + ".aniso.ktx2")).string()) +
                (name == "basis" ? " --compress basis" : ""),
            dir);
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    const struct {
        std::string suffix;
        int channels;   // channels compared: roughness G; normal x, y
        int first;
        int tolerance;  // largest difference, 8-bit codes
    } files[] = {{".ktx2", 1, 1, 8}, {".normal.ktx2", 2, 0, 16}, {".aniso.ktx2", 0, 0, 0}};
    for (const auto& f : files) {
        const std::vector<io::Rgba8Level> plain =
            io::read_ktx2_rgba8((dir / ("plain" + f.suffix)).string());
        const std::string path = (dir / ("basis" + f.suffix)).string();
        const io::UastcFileInfo info = io::inspect_ktx2_uastc(path);
        EXPECT_EQ(info.width, plain[0].width) << path;
        EXPECT_EQ(info.height, plain[0].height) << path;
        EXPECT_EQ(info.levels, int(plain.size())) << path;
        EXPECT_TRUE(info.zstd) << path;
        EXPECT_TRUE(info.linear) << path;
        EXPECT_TRUE(info.primaries_unspecified) << path;
        EXPECT_FALSE(info.alpha) << path;
        // Transcoded by three.js's transcoder into level<N>.rgba.
        const fs::path out = dir / ("decoded" + f.suffix);
        fs::create_directories(out);
        const std::string command =
            shell_quote(LEANFADE_NODE) + " " + shell_quote(LEANFADE_UASTC_DECODER) + " " +
            shell_quote(LEANFADE_BASIS_TRANSCODER) + " " + shell_quote(path) + " " +
            shell_quote(out.string()) + " >" + shell_quote((out / "report.json").string());
        ASSERT_EQ(std::system(command.c_str()), 0) << command;
        const nlohmann::json report = nlohmann::json::parse(test::read_text(out / "report.json"));
        ASSERT_EQ(report["levels"], plain.size()) << path;
        for (std::size_t l = 0; l < plain.size(); ++l) {
            const std::string texels = test::read_text(out / ("level" + std::to_string(l) + ".rgba"));
            ASSERT_EQ(texels.size(), plain[l].texels.size()) << path << " level " << l;
            int largest = 0;
            for (std::size_t i = 0; i < texels.size(); i += 4)
                for (int c = f.first; c < f.first + f.channels; ++c)
                    largest = std::max(largest, std::abs(int(std::uint8_t(texels[i + std::size_t(c)])) -
                                                         int(plain[l].texels[i + std::size_t(c)])));
            std::printf("basis%s level %zu: largest difference %d codes\n", f.suffix.c_str(), l,
                        largest);
            EXPECT_LE(largest, f.tolerance) << path << " level " << l;
        }
    }
}

}  // namespace

// `--plateau-out`: the LEAN map's plateau layer of two-lobe LEAN decoded, every level, as half
// floats: the values `leanfade render` uploads when it loads the same map.
TEST(CliBakePlateau, WritesThePlateauMipsOfTheStoredMapAsHalfFloats) {
    const fs::path dir = test::scratch_dir("bake_plateau");
    const fs::path height = write_height_map(dir);
    for (const char* format : {"map.ktx2", "map.png"}) {
        const fs::path plateau = dir / (std::string(format) + ".plateau.ktx2");
        const auto r = run_leanfade("bake " + shell_quote(height.string()) + " -o " +
                                        shell_quote((dir / format).string()) + " --plateau-out " +
                                        shell_quote(plateau.string()),
                                    dir);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_THAT(r.out, HasSubstr(plateau.string())) << "bake names every file it wrote";
        const PackedLeanMap stored =
            std::string(format) == "map.ktx2"
                ? io::read_ktx2((dir / format).string())
                : io::read_lean_png_pair((dir / "map.lean1.png").string());
        // The map's own plateau layer, decoded. A PNG pair's coarser levels are rebuilt when it is
        // read (io::read_lean_png_pair), within a code of the levels the bake wrote.
        const std::vector<Image> want = unpack_plateau_layer(stored);
        const std::vector<Image> got = io::read_ktx2_rgba16f(plateau.string());
        ASSERT_EQ(got.size(), want.size());
        const bool ktx2 = std::string(format) == "map.ktx2";
        const float code = 1.0f / 65535.0f, sc = stored.scale;
        const float steps[4] = {code, 2.0f * sc * code, 2.0f * sc * code, 2.0f * sc * sc * code};
        double plateau_fraction = 0.0;
        for (std::size_t l = 0; l < want.size(); ++l) {
            ASSERT_EQ(got[l].width, want[l].width);
            for (std::size_t i = 0; i < want[l].pixels.size(); ++i) {
                const float half = glm::unpackHalf1x16(glm::packHalf1x16(want[l].pixels[i]));
                if (ktx2 || l == 0)
                    ASSERT_EQ(got[l].pixels[i], half) << format << " level " << l << " value " << i;
                else
                    ASSERT_NEAR(got[l].pixels[i], half,
                                1.01f * steps[i % 4] + 1e-3f * std::abs(half))
                        << format << " level " << l << " value " << i;
            }
        }
        plateau_fraction = got.back().pixels[0];
        // The bumps set has flat ground between its bumps: a plateau fraction strictly inside
        // (0, 1) at the coarsest level.
        EXPECT_GT(plateau_fraction, 0.05) << format;
        EXPECT_LT(plateau_fraction, 0.95) << format;
        const io::Ktx2Info described = io::inspect_ktx2(plateau.string());
        const std::string* content = described.find(io::kKeyTextureContent);
        ASSERT_NE(content, nullptr);
        EXPECT_EQ(*content, "plateau v1");
    }
    // Refused before anything is written: not a .ktx2, or with a batch.
    const auto png = run_leanfade("bake " + shell_quote(height.string()) + " -o " +
                                      shell_quote((dir / "other.ktx2").string()) +
                                      " --plateau-out " + shell_quote((dir / "p.png").string()),
                                  dir);
    EXPECT_NE(png.exit_code, 0);
    EXPECT_THAT(png.err, HasSubstr(".ktx2"));
    EXPECT_FALSE(fs::exists(dir / "other.ktx2"));
    const auto batch = run_leanfade("bake " + shell_quote(height.string()) + " " +
                                        shell_quote(height.string()) + " --out-dir " +
                                        shell_quote((dir / "batch").string()) +
                                        " --plateau-out " + shell_quote((dir / "b.ktx2").string()),
                                    dir);
    EXPECT_NE(batch.exit_code, 0);
    EXPECT_THAT(batch.err, HasSubstr("--plateau-out"));
    EXPECT_FALSE(fs::exists(dir / "b.ktx2"));
}

// Engine outputs alone: --roughness-out without -o or --out-dir writes the KTX2 files and nothing
// else (no LEAN map, no PNG levels unless --roughness-levels), the same bytes as with a LEAN map.
TEST(CliBakeRoughness, WithoutALeanMapAskedOnlyTheEngineFilesAreWritten) {
    const fs::path dir = test::scratch_dir("bake_roughness_alone");
    const fs::path height = write_height_map(dir);
    fs::create_directories(dir / "alone");
    const auto alone = run_leanfade("bake " + shell_quote(height.string()) + " --roughness-out " +
                                        shell_quote((dir / "alone" / "r.ktx2").string()) +
                                        " --roughness 0.3",
                                    dir);
    ASSERT_EQ(alone.exit_code, 0) << alone.err;
    std::set<std::string> files;
    for (const auto& e : fs::directory_iterator(dir / "alone")) files.insert(e.path().filename().string());
    EXPECT_EQ(files, (std::set<std::string>{"r.ktx2", "r.normal.ktx2"}));
    EXPECT_FALSE(fs::exists(dir / "height.ktx2")) << "no LEAN map beside the input";
    EXPECT_THAT(alone.out, HasSubstr("wrote " + (dir / "alone" / "r.ktx2").string()));
    const auto with_map = run_leanfade("bake " + shell_quote(height.string()) + " -o " +
                                           shell_quote((dir / "m.ktx2").string()) +
                                           " --roughness-out " +
                                           shell_quote((dir / "r.ktx2").string()) + " --roughness 0.3",
                                       dir);
    ASSERT_EQ(with_map.exit_code, 0) << with_map.err;
    EXPECT_EQ(test::read_text(dir / "alone" / "r.ktx2"), test::read_text(dir / "r.ktx2"));
    EXPECT_FALSE(fs::exists(dir / "r.levels"));
}

// --ktx2-2d: the LEAN map's layers as plain 2D KTX2 files, the same bytes as the array's layers
// with the map's keys; refused where there is no single KTX2 LEAN map.
TEST(CliBakeLayers2d, WritesEachLayerAsA2dTextureOfTheSameBytes) {
    const fs::path dir = test::scratch_dir("bake_layers_2d");
    const fs::path height = write_height_map(dir);
    const auto r = run_leanfade("bake " + shell_quote(height.string()) + " -o " +
                                    shell_quote((dir / "m.ktx2").string()) + " --bits 16f --ktx2-2d",
                                dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_THAT(r.out, HasSubstr("also wrote " + (dir / "m.lean1.ktx2").string()));
    const PackedLeanMap map = io::read_ktx2((dir / "m.ktx2").string());
    for (int layer = 0; layer < 2; ++layer) {
        const fs::path file = dir / (layer == 0 ? "m.lean1.ktx2" : "m.lean2.ktx2");
        const io::Ktx2Info info = io::inspect_ktx2(file.string());
        EXPECT_EQ(info.vk_format, io::kVkFormatR16G16B16A16Sfloat);
        EXPECT_EQ(info.layer_count, 0u);
        ASSERT_EQ(info.levels.size(), map.levels.size());
        EXPECT_EQ(*info.find(io::kScaleKey), *io::inspect_ktx2((dir / "m.ktx2").string()).find(io::kScaleKey));
        EXPECT_EQ(*info.find(io::kKeyTextureContent), layer == 0 ? "lean1 v1" : "lean2 v1");
        EXPECT_EQ(info.find(io::kLayoutKey), nullptr) << "not a LEAN map container";
        const std::string bytes = test::read_text(file);
        for (std::size_t l = 0; l < map.levels.size(); ++l) {
            const std::vector<std::uint8_t>& expected =
                layer == 0 ? map.levels[l].lean1 : map.levels[l].lean2;
            ASSERT_EQ(info.levels[l].byte_length, expected.size());
            EXPECT_EQ(bytes.compare(std::size_t(info.levels[l].byte_offset), expected.size(),
                                    reinterpret_cast<const char*>(expected.data()), expected.size()),
                      0)
                << file << " level " << l;
        }
    }
    const auto png = run_leanfade("bake " + shell_quote(height.string()) + " -o " +
                                      shell_quote((dir / "p.png").string()) + " --ktx2-2d",
                                  dir);
    EXPECT_NE(png.exit_code, 0);
    EXPECT_THAT(png.err, HasSubstr("--ktx2-2d"));
    EXPECT_FALSE(fs::exists(dir / "p.lean1.png"));
}
