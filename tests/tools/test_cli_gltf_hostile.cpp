// Hostile glTF scenes and LEAN maps on the command line (docs/robustness.md, "glTF scenes"):
// every refusal is one line naming the file and the cause, exit code 1, no output written.
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "leanfade/core/error.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/png_io.hpp"
#include "test_gltf_builder.hpp"

namespace leanfade {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using scene::test::GltfStorage;
using scene::test::GltfTestFile;

fs::path gltf_hostile_folder(const std::string& name) {
    return scene::test::fresh_test_folder("cli_gltf_hostile", name);
}

std::vector<std::uint8_t> flat_normal_png() {
    std::vector<float> pixels;
    for (int i = 0; i < 16 * 16; ++i)
        for (float c : {0.6f, 0.5f, 0.9f}) pixels.push_back(c);
    return scene::test::png_bytes(16, 16, 3, pixels);
}

// One quad per material, each material with the normal texture 0 (scale 1).
GltfTestFile materials_scene(const std::vector<std::string>& names) {
    GltfTestFile file;
    file.images = {flat_normal_png()};
    for (std::size_t m = 0; m < names.size(); ++m) {
        file.materials.push_back({names[m], glm::vec4(1.0f), -1, 0, 1.0f});
        file.meshes.push_back({scene::test::unit_quad(int(m))});
    }
    return file;
}

void write_json(const fs::path& path, const json& root) {
    const std::string text = root.dump();
    scene::test::write_bytes(path.string(), std::vector<std::uint8_t>(text.begin(), text.end()));
}

// No byte below 0x20 but the final newline, no DEL, no bidirectional override, no C1 control.
bool terminal_safe(const std::string& text) {
    for (std::size_t i = 0; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if ((c < 0x20 && !(c == '\n' && i + 1 == text.size())) || c == 0x7F) return false;
        if (c == 0xC2 && i + 1 < text.size() && static_cast<unsigned char>(text[i + 1]) < 0xA0)
            return false;  // U+0080..U+009F
    }
    return text.find("\xE2\x80\xAE") == std::string::npos &&
           text.find("\xE2\x81\xA6") == std::string::npos;
}

// Exit code 1, one terminal-safe line on stderr holding every piece of `expected`.
void expect_one_line_error(const test::RunResult& r, const std::vector<std::string>& expected) {
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(terminal_safe(r.err)) << r.err;
    for (const std::string& piece : expected)
        EXPECT_NE(r.err.find(piece), std::string::npos) << "'" << piece << "' not in " << r.err;
}

// ---- File text reaches the terminal escaped ------------------------------------------------

TEST(CliGltfHostile, FileTextInMessagesIsOneEscapedLine) {
    const fs::path dir = gltf_hostile_folder("escaped");
    const std::string input = (dir / "scene.gltf").string();
    // Material names with escape sequences, OSC + BEL, a bidirectional override, a newline and
    // a NUL before the cause: the whole message, on one line.
    const std::vector<std::pair<std::string, std::string>> names = {
        {std::string("red\x1B[31mX"), "red\\x1B[31mX"},
        {std::string("t\x1B]0;owned\x07"), "t\\x1B]0;owned\\x07"},
        {std::string("abc\xE2\x80\xAE") + "gpj.exe", "abc\\xE2\\x80\\xAEgpj.exe"},
        {std::string("first\nsecond"), "first\\x0Asecond"},
        {std::string("cut\0here", 8), "cut\\x00here"},
        {std::string("c1\xC2\x9B"
                     "2J"),
         "c1\\xC2\\x9B2J"},
    };
    for (const auto& [name, shown] : names) {
        scene::test::GltfTestOutput out =
            scene::test::build_gltf(materials_scene({name}), GltfStorage::Embedded, "");
        out.json["materials"][0]["normalTexture"]["index"] = 9;
        write_json(input, out.json);
        const test::RunResult r =
            test::run_leanfade_in("bake " + test::shell_quote(input), dir, {}, test::cache_env(dir));
        expect_one_line_error(r, {input, shown, "normalTexture: texture 9 does not exist"});
    }
    // A URI with an escape sequence.
    scene::test::GltfTestOutput out =
        scene::test::build_gltf(materials_scene({"m"}), GltfStorage::Embedded, "");
    out.json["images"][0]["uri"] = std::string("\x1B]0;t\x07/../x.png");
    write_json(input, out.json);
    const test::RunResult r =
        test::run_leanfade_in("bake " + test::shell_quote(input), dir, {}, test::cache_env(dir));
    expect_one_line_error(r, {input, "\\x1B]0;t\\x07/../x.png", "leaves the glTF's folder"});
}

TEST(CliGltfHostile, BakeReportsOfHostileNamesAreEscaped) {
    const fs::path dir = gltf_hostile_folder("report");
    const std::string input = (dir / "scene.glb").string();
    scene::test::write_gltf(materials_scene({std::string("n\x1B[2J\xE2\x80\xAEx")}), input,
                            GltfStorage::Binary);
    const test::RunResult r =
        test::run_leanfade_in("bake " + test::shell_quote(input), dir, {}, test::cache_env(dir));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const std::string& line : {r.out, r.err}) {
        EXPECT_EQ(line.find('\x1B'), std::string::npos) << line;
        EXPECT_EQ(line.find("\xE2\x80\xAE"), std::string::npos) << line;
    }
    EXPECT_NE(r.out.find("n\\x1B[2J\\u{202E}x"), std::string::npos) << r.out;
    // An image file name with an escape sequence, on stdout.
    const std::string odd = std::string("odd\x1B[2Jname.png");
    scene::test::write_bytes((dir / odd).string(), flat_normal_png());
    const test::RunResult image =
        test::run_leanfade_in("bake " + test::shell_quote(odd) + " -o out.ktx2", dir, dir);
    ASSERT_EQ(image.exit_code, 0) << image.err;
    EXPECT_EQ(image.out.find('\x1B'), std::string::npos) << image.out;
    EXPECT_NE(image.out.find("odd\\x1B[2Jname.png -> out.ktx2"), std::string::npos) << image.out;
}

TEST(CliGltfHostile, PngPairTextIsEscaped) {
    const fs::path dir = gltf_hostile_folder("png_pair");
    Image image(4, 4, 4);
    for (float& v : image.pixels) v = 0.5f;
    const std::vector<std::pair<std::string, std::string>> layouts = {
        {std::string("\x1B[2Jlean"), "\\x1B[2Jlean"},
        {std::string("a\nb"), "a\\x0Ab"},
        {std::string("\xE2\x80\xAEx"), "\\xE2\\x80\\xAEx"},
    };
    for (const auto& [layout, shown] : layouts) {
        const std::string lean1 = (dir / "m.lean1.png").string();
        io::write_png_with_text(lean1, image, 8, {{io::kLayoutKey, layout}});
        io::write_png_with_text((dir / "m.lean2.png").string(), image, 8,
                                {{io::kLayoutKey, layout}});
        const test::RunResult r = test::run_leanfade_in(
            "render --bumps " + test::shell_quote(lean1) + " --size 16x16 -o " +
                test::shell_quote((dir / "out.png").string()),
            dir);
        expect_one_line_error(r, {lean1, shown});
        EXPECT_FALSE(fs::exists(dir / "out.png"));
    }
}

// ---- Material names -----------------------------------------------------------------------

TEST(CliGltfHostile, MaterialNamesThatCollideGetFreeOutputNames) {
    const std::vector<std::vector<std::string>> cases = {
        {"a", "a", "a-2"}, {"a-2", "a", "a"}, {"a b", "a_b", "a?b", "a_b-2"}, {"", "", "material"}};
    for (std::size_t c = 0; c < cases.size(); ++c) {
        const fs::path dir = gltf_hostile_folder("names" + std::to_string(c));
        GltfTestFile file = materials_scene(cases[c]);
        for (std::size_t m = 0; m < file.materials.size(); ++m)
            file.materials[m].normal_scale = 1.0f - 0.1f * float(m);  // one bake each
        const std::string input = (dir / "s.glb").string();
        scene::test::write_gltf(file, input, GltfStorage::Binary);
        fs::create_directories(dir / "out");
        const test::RunResult r =
            test::run_leanfade_in("bake " + test::shell_quote(input) + " --out-dir " +
                                      test::shell_quote((dir / "out").string()),
                                  dir, {}, test::cache_env(dir));
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_EQ(std::size_t(
                      std::distance(fs::directory_iterator(dir / "out"), fs::directory_iterator())),
                  cases[c].size())
            << r.out;
    }
}

// ---- Cross-term textures are not LEAN maps -------------------------------------------------

TEST(CliGltfHostile, CrossTermTextureIsRefusedWhereALeanMapIsRead) {
    const fs::path dir = gltf_hostile_folder("cross_terms");
    const test::RunResult baked =
        test::run_leanfade_in("bake --cross-terms bumps,noise --size 16 -o pair.ktx2", dir, dir);
    ASSERT_EQ(baked.exit_code, 0) << baked.err;
    const std::string pair = (dir / "pair.ktx2").string();
    EXPECT_EQ(io::read_cross_term_ktx2(pair).levels.size(), 5u);
    try {
        io::read_ktx2(pair);
        ADD_FAILURE() << "read_ktx2 read a cross-term texture";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("is a cross-term texture"), std::string::npos)
            << e.what();
    }
    // `info` describes it as what it is.
    const test::RunResult info = test::run_leanfade_in("info pair.ktx2", dir, dir);
    EXPECT_EQ(info.exit_code, 0) << info.err;
    EXPECT_NE(info.out.find("kind: not a LEAN map: a cross-term texture"), std::string::npos)
        << info.out;
    const test::RunResult render =
        test::run_leanfade_in("render --bumps pair.ktx2 --size 16x16 -o out.png", dir, dir);
    expect_one_line_error(render, {"pair.ktx2", "is a cross-term texture"});
    EXPECT_FALSE(fs::exists(dir / "out.png"));
    // And the other way round: a LEAN map is not a cross-term texture.
    ASSERT_EQ(
        test::run_leanfade_in("bake --builtin bumps --size 16 -o map.ktx2", dir, dir).exit_code, 0);
    EXPECT_THROW(io::read_cross_term_ktx2((dir / "map.ktx2").string()), Error);
}

// ---- sc beyond any bake -------------------------------------------------------------------

TEST(CliGltfHostile, ScaleBeyondAnyBakeIsRefusedNamingTheFile) {
    const fs::path dir = gltf_hostile_folder("sc");
    ASSERT_EQ(
        test::run_leanfade_in("bake --builtin bumps --size 16 --bits 16 -o map.ktx2", dir, dir)
            .exit_code,
        0);
    ASSERT_EQ(test::run_leanfade_in("bake --builtin bumps --size 16 --bits 8 --format png -o "
                                    "pair.png",
                                    dir, dir)
                  .exit_code,
              0);
    PackedLeanMap map = io::read_ktx2((dir / "map.ktx2").string());
    PackedLeanMap pair = io::read_lean_png_pair((dir / "pair.lean1.png").string());
    // The largest sc a bake writes is read.
    map.scale = kMaxLeanScale;
    io::write_ktx2((dir / "largest.ktx2").string(), map);
    EXPECT_EQ(io::read_ktx2((dir / "largest.ktx2").string()).scale, kMaxLeanScale);
    for (float sc : {1.1e6f, 1e12f, 1e20f, 3e38f}) {
        map.scale = sc;
        io::write_ktx2((dir / "sc.ktx2").string(), map);
        pair.scale = sc;
        io::write_lean_png_pair((dir / "sc.lean1.png").string(), (dir / "sc.lean2.png").string(),
                                pair, {}, (dir / "sc.plateau.png").string());
        for (const std::string& command :
             {std::string("info sc.ktx2"),
              std::string("render --bumps sc.ktx2 --size 16x16 -o o.png"),
              std::string("render --bumps sc.lean1.png --size 16x16 -o o.png")}) {
            const test::RunResult r = test::run_leanfade_in(command, dir, dir);
            expect_one_line_error(
                r, {command.find("lean1") != std::string::npos ? "sc.lean1.png" : "sc.ktx2",
                    "exceeds the largest sc a bake writes"});
            EXPECT_EQ(r.out, "") << command;
            EXPECT_FALSE(fs::exists(dir / "o.png"));
        }
    }
}

// ---- Files whose JSON or instances would take memory or stack without bound ----------------

// The real `leanfade bake` on each: exit 1, one line naming the file and the cause, well within
// 512 MiB of resident memory (each took gigabytes or overflowed the stack before its check).
TEST(CliGltfHostile, ScenesThatWouldExhaustMemoryOrStackAreOneLineErrors) {
    const fs::path dir = gltf_hostile_folder("bombs");
    struct Case {
        std::string name;
        std::vector<std::uint8_t> bytes;
        std::string cause;
    };
    std::vector<Case> cases;
    {  // asset.extras 30000 levels deep: 60 KB
        json root = scene::test::build_gltf(materials_scene({"m"}), GltfStorage::Embedded, "").json;
        root["asset"]["extras"] = "@DEEP@";
        std::string text = root.dump();
        const std::string marker = "\"@DEEP@\"";
        text.replace(text.find(marker), marker.size(),
                     std::string(30000, '[') + std::string(30000, ']'));
        cases.push_back({"deep.gltf", std::vector<std::uint8_t>(text.begin(), text.end()),
                         "the JSON nests deeper than 64 levels"});
    }
    {  // 500000 empty materials, 2000000 empty nodes
        for (const auto& [key, count] :
             {std::pair<std::string, int>{"materials", 500000}, {"nodes", 2000000}}) {
            json root =
                scene::test::build_gltf(materials_scene({"m"}), GltfStorage::Embedded, "").json;
            root[key] = "@MANY@";
            std::string text = root.dump();
            std::string many = "[";
            for (int i = 0; i < count; ++i) many += i == 0 ? "{}" : ",{}";
            many += "]";
            const std::string marker = "\"@MANY@\"";
            text.replace(text.find(marker), marker.size(), many);
            cases.push_back({key + ".gltf", std::vector<std::uint8_t>(text.begin(), text.end()),
                             "'" + key + "' has " + std::to_string(count) + " elements"});
        }
    }
    {  // A 3-vertex mesh, a strip of 300000 indices, instanced by 1000 nodes: 1.2 MB
        GltfTestFile file = materials_scene({"m"});
        scene::test::GltfTestPrimitive strip = scene::test::unit_quad(0);
        strip.positions.resize(3);
        strip.normals.resize(3);
        strip.uvs.resize(3);
        strip.indices.clear();
        for (int i = 0; i < 300000; ++i) strip.indices.push_back(std::uint32_t(i % 3));
        strip.mode = 5;
        file.meshes = {{strip}};
        for (int n = 0; n < 1000; ++n) file.nodes.push_back({0, {}, {}, {double(n), 0, 0}, {}});
        const scene::test::GltfTestOutput out =
            scene::test::build_gltf(file, GltfStorage::Binary, "");
        cases.push_back({"instances.glb", scene::test::pack_glb(out.json, out.bin),
                         "triangle indices in the scene"});
    }
    {  // 1500 images naming one 1 MB buffer view, none used: read, not copied
        scene::test::GltfTestOutput out =
            scene::test::build_gltf(materials_scene({"m"}), GltfStorage::Binary, "");
        const std::size_t start = out.bin.size();
        out.bin.resize(start + (std::size_t(1) << 20), 7);
        out.json["buffers"][0]["byteLength"] = out.bin.size();
        out.json["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", start}, {"byteLength", std::size_t(1) << 20}});
        const std::size_t view = out.json["bufferViews"].size() - 1;
        for (int i = 0; i < 1500; ++i)
            out.json["images"].push_back({{"bufferView", view}, {"mimeType", "image/png"}});
        cases.push_back({"images.glb", scene::test::pack_glb(out.json, out.bin), ""});
    }
    {  // one normal image with 12 normalTexture scales: 12 bakes held and cached
        std::vector<std::string> names;
        for (int m = 0; m < 12; ++m) {
            std::string name = "m";
            name += std::to_string(m);  // not "m" + ...: GCC 12's -Wrestrict misfires on it
            names.push_back(name);
        }
        GltfTestFile file = materials_scene(names);
        for (int m = 0; m < 12; ++m) file.materials[std::size_t(m)].normal_scale = 1.0f + float(m);
        const scene::test::GltfTestOutput out =
            scene::test::build_gltf(file, GltfStorage::Binary, "");
        cases.push_back({"scales.glb", scene::test::pack_glb(out.json, out.bin),
                         "image 0: normal texture of 5 different scales, more than the limit of "
                         "4 bakes of one image"});
    }
    ::setenv("XDG_CACHE_HOME", (dir / "cache").c_str(), 1);  // inherited by the runs
    for (const Case& c : cases) {
        const fs::path input = dir / c.name;
        scene::test::write_bytes(input.string(), c.bytes);
        const test::RunResult r =
            test::run_leanfade_bounded("bake " + test::shell_quote(input.string()) + " --out-dir " +
                                           test::shell_quote(dir.string()),
                                       dir);
        EXPECT_LT(r.max_rss_kib, leanfade::test::memory_bound_kib(512 * 1024)) << c.name;
        if (c.cause.empty()) {
            EXPECT_EQ(r.exit_code, 0) << c.name << ": " << r.err;
            continue;
        }
        expect_one_line_error(r, {input.string(), c.cause});
    }
    ::unsetenv("XDG_CACHE_HOME");
}

// ---- Requested outputs are written or refused ------------------------------------------------

TEST(CliHostileFlags, OptionsABakeWouldIgnoreAreRefusedByName) {
    const fs::path dir = gltf_hostile_folder("ignored_options");
    const std::vector<std::pair<std::string, std::string>> cross = {
        {"--json j.json", "--json"},
        {"--roughness-out r.ktx2", "--roughness-out"},
        {"--format png", "--format"},
        {"--bits 8", "--bits"},
        {"--wrap clamp", "--wrap"},
    };
    for (const auto& [option, name] : cross) {
        const test::RunResult r = test::run_leanfade_in(
            "bake --cross-terms bumps,noise --size 16 -o p.ktx2 " + option, dir, dir);
        expect_one_line_error(r, {name + ": does not apply to --cross-terms"});
        EXPECT_FALSE(fs::exists(dir / "p.ktx2"));
        EXPECT_FALSE(fs::exists(dir / "j.json"));
    }
    const std::string input = (dir / "s.glb").string();
    scene::test::write_gltf(materials_scene({"m"}), input, GltfStorage::Binary);
    const std::vector<std::pair<std::string, std::string>> gltf = {
        {"--roughness-out r.ktx2", "--roughness-out"},
        {"--anisotropy-out a.ktx2", "--anisotropy-out"},
        {"--roughness-out r.ktx2 --anisotropy-out a.ktx2", "--roughness-out"},
        {"--roughness-map m.png", "--roughness-map"},
        {"--roughness 0.5", "--roughness"},
        {"--sc max", "--sc"},
        {"--strength-unit uv", "--strength-unit"},
        {"--size 64", "--size"},
        {"--seed 3", "--seed"},
        {"--plateau-out p.ktx2", "--plateau-out"},
    };
    for (const auto& [option, name] : gltf) {
        const test::RunResult r = test::run_leanfade_in("bake s.glb " + option, dir, dir, test::cache_env(dir));
        expect_one_line_error(r, {name + ": does not apply to a glTF scene"});
        for (const char* file : {"s.m.ktx2", "r.ktx2", "a.ktx2", "x.ktx2"})
            EXPECT_FALSE(fs::exists(dir / file)) << option << ": " << file;
    }
    // -o names a glTF output (bake SCENE -o OUT.gltf|OUT.glb), nothing else.
    const test::RunResult ktx2 = test::run_leanfade_in("bake s.glb -o x.ktx2", dir, dir, test::cache_env(dir));
    expect_one_line_error(ktx2, {"x.ktx2: a glTF output is a .gltf or .glb file"});
    EXPECT_FALSE(fs::exists(dir / "x.ktx2"));
    // What applies is honoured: --json is written.
    const test::RunResult r =
        test::run_leanfade_in("bake s.glb --json j.json --bits 8", dir, dir, test::cache_env(dir));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "j.json"));
    EXPECT_TRUE(fs::exists(dir / "s.m.ktx2"));
}

TEST(CliHostileFlags, PresetTextureSizeObeysMaxSize) {
    const fs::path dir = gltf_hostile_folder("preset_size");
    scene::test::write_bytes((dir / "big.json").string(), [] {
        const std::string t = R"({"bumps":{"texture_size":8192}})";
        return std::vector<std::uint8_t>(t.begin(), t.end());
    }());
    const std::string preset = test::shell_quote((dir / "big.json").string());
    for (const std::string& args : {"--preset " + preset + " --max-size 1024",
                                    std::string("--texture-size 8192 --max-size 1024"),
                                    "--preset " + preset + " --max-size 1024 --scene ocean"}) {
        const test::RunResult r = test::run_leanfade_bounded(
            "render " + args + " --size 16x16 -o " + test::shell_quote((dir / "o.png").string()),
            dir);
        expect_one_line_error(r, {"--texture-size: must be in [4, 1024] (--max-size), got 8192"});
        EXPECT_LT(r.max_rss_kib, leanfade::test::memory_bound_kib(512 * 1024)) << args;
        EXPECT_FALSE(fs::exists(dir / "o.png"));
    }
}

// ---- Output folders ----------------------------------------------------------------------------

TEST(CliHostileFlags, OutDirIsCreatedAndRemovedAgainWhenTheRunFails) {
    const fs::path dir = gltf_hostile_folder("out_dir");
    const std::string input = (dir / "s.glb").string();
    scene::test::write_gltf(materials_scene({"m"}), input, GltfStorage::Binary);
    // Created, for an image bake and for a glTF scene.
    test::RunResult r =
        test::run_leanfade_in("bake --builtin bumps --size 16 --out-dir new/a/b", dir, dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "new/a/b/bumps.ktx2"));
    r = test::run_leanfade_in("bake s.glb --out-dir made/here", dir, dir, test::cache_env(dir));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "made/here/s.m.ktx2"));
    // A failed run removes the folders it created and nothing else.
    scene::test::write_bytes((dir / "bad.png").string(), {1, 2, 3});
    r = test::run_leanfade_in("bake bad.png --out-dir gone/too", dir, dir);
    expect_one_line_error(r, {"bad.png"});
    EXPECT_FALSE(fs::exists(dir / "gone"));
    r = test::run_leanfade_in("bake --builtin bumps --size 16 --out-dir new/c --json new/c", dir,
                              dir);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "new/c"));
    EXPECT_TRUE(fs::exists(dir / "new/a/b/bumps.ktx2"));
    // A file in the way is named.
    scene::test::write_bytes((dir / "file").string(), {1});
    r = test::run_leanfade_in("bake --builtin bumps --size 16 --out-dir file/sub", dir, dir);
    expect_one_line_error(r, {"file is not a folder"});
}

TEST(CliHostileFlags, OutputsAreReportedOncePublishedAndNamedNotTheirTemporaries) {
    const fs::path dir = gltf_hostile_folder("report_after_publish");
    // Files larger than 512 bytes cannot be written (SIGXFSZ ignored: write fails with EFBIG):
    // the PNG pair fits, the JSON summary does not.
    const test::RunResult r = test::run_leanfade_in(
        "bake --builtin bumps --size 4 --bits 8 --format png -o s.png --json s.json", dir, dir,
        "trap '' XFSZ; ulimit -f 1;");
    expect_one_line_error(r, {"s.json: write failed"});
    EXPECT_EQ(r.err.find(".tmp-"), std::string::npos) << r.err;
    EXPECT_EQ(r.out, "");  // nothing was published
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 0);
    // Without the limit the same run reports its outputs.
    const test::RunResult ok = test::run_leanfade_in(
        "bake --builtin bumps --size 4 --bits 8 --format png -o s.png --json s.json", dir, dir);
    ASSERT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_NE(ok.out.find("builtin:bumps -> s.{lean1,lean2,plateau}.png"), std::string::npos)
        << ok.out;
}

// ---- The files a glTF names are inputs -------------------------------------------------------

TEST(CliGltfHostile, OutputsMayNotReplaceTheFilesASceneNames) {
    const fs::path dir = gltf_hostile_folder("scene_inputs");
    GltfTestFile file = materials_scene({"m"});
    scene::test::write_gltf(file, (dir / "s.gltf").string(), GltfStorage::External);
    const std::string image = test::read_text(dir / "s_image0.png");
    // render -o onto the scene's texture.
    test::RunResult r = test::run_leanfade_in("render --scene s.gltf --size 16x16 -o s_image0.png",
                                              dir, dir, test::cache_env(dir));
    expect_one_line_error(r, {"s_image0.png", "is the same file as an input of this run"});
    EXPECT_EQ(test::read_text(dir / "s_image0.png"), image);
    // A GLB's external image, found in its JSON chunk.
    {
        scene::test::GltfTestOutput out = scene::test::build_gltf(file, GltfStorage::Binary, "");
        out.json["images"][0] = {{"uri", "tex.png"}};
        scene::test::write_bytes((dir / "g.glb").string(),
                                 scene::test::pack_glb(out.json, out.bin));
        scene::test::write_bytes((dir / "tex.png").string(), file.images[0]);
        r = test::run_leanfade_in("render --scene g.glb --size 16x16 -o tex.png", dir, dir,
                                  test::cache_env(dir));
        expect_one_line_error(r, {"tex.png", "is the same file as an input of this run"});
        EXPECT_EQ(scene::test::read_bytes((dir / "tex.png").string()), file.images[0]);
    }
    // bake onto a buffer named like its output, also spelt differently in the URI.
    for (const std::string uri : {"s.m.ktx2", "./s.m.ktx2", "s%2Em.ktx2"}) {
        scene::test::GltfTestOutput out = scene::test::build_gltf(file, GltfStorage::External, "s");
        out.json["buffers"][0]["uri"] = uri;
        write_json(dir / "s.gltf", out.json);
        scene::test::write_bytes((dir / "s.m.ktx2").string(), out.bin);
        r = test::run_leanfade_in("bake s.gltf", dir, dir, test::cache_env(dir));
        expect_one_line_error(r, {"s.m.ktx2", "is the same file as", "may not replace an input"});
        EXPECT_EQ(scene::test::read_bytes((dir / "s.m.ktx2").string()), out.bin) << uri;
    }
}

TEST(CliGltfHostile, SymbolicLinksOutOfTheScenesFolderAreNotRead) {
    const fs::path top = gltf_hostile_folder("symlinks");
    const fs::path dir = top / "scene";
    fs::create_directories(dir);
    const std::string secret = "top secret bytes of a file outside the folder";
    scene::test::write_bytes((top / "secret.txt").string(),
                             std::vector<std::uint8_t>(secret.begin(), secret.end()));
    const GltfTestFile file = materials_scene({"m"});
    scene::test::write_gltf(file, (dir / "s.gltf").string(), GltfStorage::External);
    // The buffer, then the image, as a link out of the folder; a linked folder; a chain of links.
    fs::create_directory_symlink("..", dir / "up");
    fs::create_symlink("../secret.txt", dir / "hop");
    const std::vector<std::pair<std::string, std::string>> cases = {{"buffers", "../secret.txt"},
                                                                    {"images", "../secret.txt"},
                                                                    {"buffers", "up/secret.txt"},
                                                                    {"images", "hop"}};
    for (const auto& [key, target] : cases) {
        scene::test::GltfTestOutput out = scene::test::build_gltf(file, GltfStorage::External, "s");
        fs::remove(dir / "link.bin");
        fs::create_symlink(target, dir / "link.bin");
        out.json[key][0]["uri"] =
            key == "buffers" && target.rfind("up/", 0) == 0 ? target : "link.bin";
        write_json(dir / "s.gltf", out.json);
        const test::RunResult r = test::run_leanfade_in("bake s.gltf", dir, dir, test::cache_env(dir));
        expect_one_line_error(r, {"s.gltf", "lies outside the glTF's folder"});
        EXPECT_EQ(r.err.find("secret bytes"), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find(std::to_string(secret.size())), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "s.m.ktx2"));
    }
    // A link that stays inside the folder is read.
    fs::remove(dir / "link.bin");
    fs::create_symlink("s.bin", dir / "link.bin");
    scene::test::GltfTestOutput out = scene::test::build_gltf(file, GltfStorage::External, "s");
    out.json["buffers"][0]["uri"] = "link.bin";
    write_json(dir / "s.gltf", out.json);
    const test::RunResult r = test::run_leanfade_in("bake s.gltf", dir, dir, test::cache_env(dir));
    EXPECT_EQ(r.exit_code, 0) << r.err;
}

// ---- Shader folders ----------------------------------------------------------------------

TEST(CliHostileFlags, ShaderFoldersHoldRegularFilesOfBoundedSize) {
    const fs::path dir = gltf_hostile_folder("shader_files");
    struct Case {
        std::string name;
        std::function<void(const fs::path&)> make;
        std::string cause;
    };
    const std::vector<Case> cases = {
        {"fifo",
         [](const fs::path& src) {
             fs::remove(src / "lean_shading.glsl");
             ASSERT_EQ(::mkfifo((src / "lean_shading.glsl").c_str(), 0644), 0);
         },
         "lean_shading.glsl: is not a regular file"},
        {"dev_zero",
         [](const fs::path& src) {
             fs::remove(src / "lean_shading.glsl");
             fs::create_symlink("/dev/zero", src / "lean_shading.glsl");
         },
         // Refused by where it leads, before it is opened (docs/robustness.md).
         "lean_shading.glsl: resolves outside the shader folder"},
        {"huge_include",
         [](const fs::path& src) {
             std::ofstream out(src / "lean_shading.glsl", std::ios::app);
             const std::string line(99, '/');
             for (int i = 0; i < 100000; ++i) out << line << "\n";  // 10 MB
         },
         "lean_shading.glsl: file of 10"},
        {"many_includes",
         [](const fs::path& src) {
             std::ofstream frag(src / "scene.frag", std::ios::app);
             for (int f = 0; f < 6; ++f) {
                 frag << "#include \"big" << f << ".glsl\"\n";
                 std::ofstream big(src / ("big" + std::to_string(f) + ".glsl"));
                 const std::string line(99, '/');
                 for (int i = 0; i < 9000; ++i) big << line << "\n";  // 900 KB each
             }
         },
         "the shader source with its includes exceeds 4194304 bytes"},
    };
    for (const Case& c : cases) {
        const fs::path src = dir / c.name;
        fs::copy(fs::path(LEANFADE_SOURCE_DIR) / "shaders", src);
        c.make(src);
        const test::RunResult r = test::run_leanfade_bounded(
            "shaders --lang glsl --shaders " + test::shell_quote(src.string()) + " -o " +
                test::shell_quote((dir / (c.name + "_out")).string()),
            dir);
        expect_one_line_error(r, {c.cause});
        EXPECT_LT(r.max_rss_kib, leanfade::test::memory_bound_kib(512 * 1024)) << c.name;
        EXPECT_FALSE(fs::exists(dir / (c.name + "_out"))) << c.name;
    }
    // An output that is a regular file is named as one.
    scene::test::write_bytes((dir / "afile").string(), {1});
    const test::RunResult r = test::run_leanfade_in("shaders --lang glsl -o afile", dir, dir);
    expect_one_line_error(r, {"afile: is a regular file, not a folder"});
}

// ---- Inputs inside the folders a run writes into --------------------------------------------

TEST(CliHostileFlags, InputsInsideOutputFoldersAreNotReplaced) {
    const fs::path dir = gltf_hostile_folder("inputs_in_folders");
    test::RunResult r = test::run_leanfade_in(
        "bake --builtin bumps --size 16 -o map.ktx2 --roughness-out X.ktx2 --roughness-levels", dir,
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_TRUE(fs::is_directory(dir / "X.levels")) << r.out;
    std::string level;
    for (const auto& entry : fs::directory_iterator(dir / "X.levels"))
        if (entry.path().extension() == ".png") level = entry.path().filename().string();
    ASSERT_FALSE(level.empty());
    const std::string before = test::read_text(dir / "X.levels" / level);
    r = test::run_leanfade_in(
        "bake X.levels/" + level + " -o y.ktx2 --roughness-out X.ktx2 --roughness-levels", dir, dir);
    expect_one_line_error(r, {"X.levels", "holds the input X.levels/" + level});
    EXPECT_EQ(test::read_text(dir / "X.levels" / level), before);
    EXPECT_FALSE(fs::exists(dir / "y.ktx2"));
    // eval's report folder may not hold its bump map either.
    fs::create_directories(dir / "EO" / "images");
    fs::copy_file(dir / "X.levels" / level, dir / "EO" / "images" / "b.png");
    r = test::run_leanfade_in("eval --bumps EO/images/b.png --out EO --size 16x16", dir, dir);
    expect_one_line_error(r, {"EO", "holds the input EO/images/b.png"});
    EXPECT_EQ(test::read_text(dir / "EO" / "images" / "b.png"), before);
}

// ---- Flags without a bound, messages without a name ----------------------------------------

TEST(CliHostileFlags, LayerFlagsAndFigureSizesAreBoundedAndNamed) {
    const fs::path dir = gltf_hostile_folder("layer_flags");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"--layers bumps,noise --layer-tiling 1e30,1",
         "--layer-tiling: each tiling must be in (0, 1e+06]"},
        {"--layers bumps,noise --layer-tiling 1,inf", "--layer-tiling"},
        {"--layers bumps,noise --layer-velocity 1e30:0,0:0",
         "--layer-velocity: each component must be in [-1e+06, 1e+06]"},
        {"--layers bumps,noise --layer-velocity 0:0,0:nan", "--layer-velocity"},
        {"--layers bumps,", "--layers: source 2 of 2 is empty"},
        {"--layers ,noise", "--layers: source 1 of 2 is empty"},
        {"--scene foo.xyz", "ocean, an .obj file or a glTF scene (.gltf, .glb)"},
        {"--distances 2:1000:1000 --size 256x256", "--distances: "},
        {"--scene ocean --views near,mid,far --size 4096x4096", "--views: "},
    };
    for (const auto& [args, cause] : cases) {
        const test::RunResult r = test::run_leanfade_bounded(
            "render " + args + (args.find("--size") == std::string::npos ? " --size 16x16" : "") +
                " -o " + test::shell_quote((dir / "o.png").string()),
            dir);
        expect_one_line_error(r, {cause});
        EXPECT_LT(r.max_rss_kib, leanfade::test::memory_bound_kib(512 * 1024)) << args;
        EXPECT_FALSE(fs::exists(dir / "o.png")) << args;
    }
}

}  // namespace
}  // namespace leanfade
