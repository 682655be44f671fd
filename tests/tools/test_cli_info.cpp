// `leanfade info` on any KTX2 file: a LEAN map with its moments, leanfade's cross-term and engine
// textures named by their keys, and other writers' files (other formats, supercompressed) described
// and said not to be LEAN maps; what is not KTX2 at all, or claims to be leanfade's and is not, is
// refused with one line.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sstream>

#include <filesystem>
#include <fstream>

#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"
#include "tools_test_helpers.hpp"

using namespace leanfade;
using test::run_leanfade;
using test::shell_quote;
using ::testing::HasSubstr;
using ::testing::Not;
namespace fs = std::filesystem;

namespace {

void write_file(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

void store_u32(std::vector<std::uint8_t>& bytes, std::size_t at, std::uint32_t value) {
    for (int i = 0; i < 4; ++i) bytes.at(at + std::size_t(i)) = std::uint8_t(value >> (8 * i));
}

// A 4 x 4 RGBA8 texture with its levels, written by "another writer" (no LEANFADE key).
std::vector<std::uint8_t> other_writers_texture() {
    std::vector<io::Rgba8Level> levels = {{4, 4, std::vector<std::uint8_t>(64, 200)},
                                          {2, 2, std::vector<std::uint8_t>(16, 100)},
                                          {1, 1, std::vector<std::uint8_t>(4, 50)}};
    return io::encode_ktx2_rgba8(levels, "toktx v4.3", "other.ktx2");
}

TEST(CliInfo, DescribesEveryKindOfKtx2AndSaysWhetherItIsALeanMap) {
    const fs::path dir = test::scratch_dir("cli_info");
    const auto bake = run_leanfade("bake --builtin bumps --size 32 -o " +
                                       shell_quote((dir / "map.ktx2").string()) +
                                       " --roughness-out " +
                                       shell_quote((dir / "rough.ktx2").string()) +
                                       " --plateau-out " +
                                       shell_quote((dir / "plateau.ktx2").string()),
                                   dir);
    ASSERT_EQ(bake.exit_code, 0) << bake.err;
    ASSERT_EQ(run_leanfade("bake --cross-terms bumps,ridges --size 32 -o " +
                               shell_quote((dir / "pair.ktx2").string()),
                           dir)
                  .exit_code,
              0);
    std::vector<std::uint8_t> other = other_writers_texture();
    write_file(dir / "other.ktx2", other);
    // The same texture marked Zstandard-supercompressed and BC7 sRGB: described, not decoded.
    store_u32(other, 12, 146);  // vkFormat
    store_u32(other, 44, 2);    // supercompressionScheme
    write_file(dir / "zstd.ktx2", other);

    const struct {
        const char* file;
        std::vector<std::string> says;
    } cases[] = {
        {"map.ktx2", {"kind: a LEAN map", "moments: slope |B| mean", "LEANFADEscale = "}},
        {"pair.ktx2", {"kind: not a LEAN map: a cross-term texture", "cross terms v1"}},
        {"rough.ktx2", {"LEANFADEcontent 'roughness v1'", "VK_FORMAT_R8G8B8A8_UNORM"}},
        {"rough.normal.ktx2", {"LEANFADEcontent 'normal v1'"}},
        {"plateau.ktx2", {"LEANFADEcontent 'plateau v1'", "VK_FORMAT_R16G16B16A16_SFLOAT",
                          "layerCount 0", "levelCount 6"}},
        {"other.ktx2", {"kind: not a LEAN map (no LEANFADElayout key): a texture of another writer",
                        "KTXwriter = toktx v4.3", "level 2: 1 x 1"}},
        {"zstd.ktx2", {"supercompressionScheme 2 (Zstandard)", "VK_FORMAT_BC7_SRGB_BLOCK",
                       "a texture of another writer"}},
    };
    for (const auto& c : cases) {
        const auto r = run_leanfade("info " + shell_quote((dir / c.file).string()), dir);
        EXPECT_EQ(r.exit_code, 0) << c.file << ": " << r.err;
        EXPECT_EQ(r.err, "") << c.file;
        for (const std::string& text : c.says) EXPECT_THAT(r.out, HasSubstr(text)) << c.file;
        if (std::string(c.file) != "map.ktx2") {
            EXPECT_THAT(r.out, Not(HasSubstr("moments:"))) << c.file;
        }
    }
}

TEST(CliInfo, RefusesWhatIsNotKtx2OrIsNotWhatItsKeysClaim) {
    const fs::path dir = test::scratch_dir("cli_info_refused");
    std::ofstream(dir / "text.ktx2") << "not a texture";
    // An engine texture whose key says plateau (RGBA16F) while it holds RGBA8.
    std::vector<io::Rgba8Level> levels = {{1, 1, std::vector<std::uint8_t>(4, 1)}};
    write_file(dir / "liar.ktx2",
               io::encode_ktx2_rgba8(levels, "w", "liar.ktx2",
                                     {{io::kKeyTextureContent, "plateau v1"}}));
    for (const auto& [file, cause] : {std::pair{"text.ktx2", "not a KTX 2.0 file"},
                                      std::pair{"liar.ktx2", "expected VK_FORMAT_R16G16B16A16_SFLOAT"},
                                      std::pair{"missing.ktx2", "missing.ktx2"}}) {
        const auto r = run_leanfade("info " + shell_quote((dir / file).string()), dir);
        EXPECT_NE(r.exit_code, 0) << file;
        EXPECT_EQ(r.out, "") << file;
        EXPECT_THAT(r.err, HasSubstr(file));
        EXPECT_THAT(r.err, HasSubstr(cause));
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
}

// Before: a key/value of 120 005 characters was printed whole, as one line, though file text is cut
// everywhere else (docs/robustness.md, "Limits").
TEST(CliInfo, LongKeyValueTextIsCut) {
    const fs::path dir = test::scratch_dir("cli_info_long_text");
    std::vector<io::Rgba8Level> levels = {{1, 1, std::vector<std::uint8_t>(4, 1)}};
    const std::string long_value(120005, 'v');
    const std::string long_key = "K" + std::string(5000, 'k');
    write_file(dir / "long.ktx2",
               io::encode_ktx2_rgba8(levels, "w", "long.ktx2",
                                     {{"note", long_value}, {long_key, "short"}}));
    const auto r = run_leanfade("info " + shell_quote((dir / "long.ktx2").string()), dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::istringstream lines(r.out);
    bool value_seen = false, key_seen = false;
    for (std::string line; std::getline(lines, line);) {
        EXPECT_LE(line.size(), 2 * io::kDescribedTextBytes + 16) << line.substr(0, 80);
        if (line.starts_with("  note = ")) {
            value_seen = true;
            EXPECT_EQ(line, "  note = " + std::string(io::kDescribedTextBytes, 'v') + "...");
        }
        if (line.starts_with("  Kkkk")) {
            key_seen = true;
            EXPECT_EQ(line, "  K" + std::string(io::kDescribedTextBytes - 1, 'k') + "... = short");
        }
    }
    EXPECT_TRUE(value_seen) << r.out.substr(0, 2000);
    EXPECT_TRUE(key_seen);
}

}  // namespace
