// glTF scenes on the command line: `leanfade bake FILE.gltf|.glb` bakes every normal texture
// through the LEAN-map cache; broken scenes are one-line errors with no output.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "leanfade/io/detail/basis_universal.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/io/ktx2.hpp"
#include "leanfade/io/detail/ktx2_texture.hpp"
#include "test_gltf_builder.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade {
namespace {

namespace fs = std::filesystem;
using scene::test::GltfStorage;
using scene::test::GltfTestFile;

fs::path cli_gltf_folder(const std::string& name) {
    return leanfade::test::fresh_scratch_folder("cli_gltf", name);
}

std::vector<std::uint8_t> normal_png(glm::vec3 n) {
    n = glm::normalize(n);
    std::vector<float> pixels;
    for (int i = 0; i < 16 * 16; ++i)
        for (int c = 0; c < 3; ++c) pixels.push_back(0.5f * n[c] + 0.5f);
    return scene::test::png_bytes(16, 16, 3, pixels);
}

// Three materials: two normal textures (one shared by two materials with the same scale), one
// plain material.
GltfTestFile scene_file() {
    GltfTestFile file;
    file.images = {normal_png({0.3f, 0.0f, 1.0f}), normal_png({0.0f, -0.4f, 1.0f})};
    file.materials = {{"brick wall", glm::vec4(1.0f), -1, 0, 1.0f},
                      {"metal", glm::vec4(1.0f), -1, 1, 0.5f},
                      {"brick again", glm::vec4(0.5f), -1, 0, 1.0f},
                      {"plain", glm::vec4(1.0f), -1, -1, 1.0f}};
    for (int m = 0; m < 4; ++m) file.meshes.push_back({scene::test::unit_quad(m)});
    return file;
}

TEST(CliGltf, BakeWritesEveryNormalTextureAndReusesTheCache) {
    for (GltfStorage storage : {GltfStorage::External, GltfStorage::Binary}) {
        const fs::path dir = cli_gltf_folder(storage == GltfStorage::Binary ? "glb" : "gltf");
        const std::string input =
            (dir / (storage == GltfStorage::Binary ? "scene.glb" : "scene.gltf")).string();
        scene::test::write_gltf(scene_file(), input, storage);
        fs::create_directories(dir / "out");
        const std::string args = "bake " + test::shell_quote(input) + " --out-dir " +
                                 test::shell_quote((dir / "out").string());
        const test::RunResult first = test::run_leanfade_in(args, dir, {}, test::cache_env(dir));
        ASSERT_EQ(first.exit_code, 0) << first.err;
        const fs::path brick = dir / "out" / "scene.brick_wall.ktx2";
        const fs::path metal = dir / "out" / "scene.metal.ktx2";
        ASSERT_TRUE(fs::exists(brick)) << first.out;
        ASSERT_TRUE(fs::exists(metal)) << first.out;
        // Two maps: "brick again" shares the brick texture and scale.
        EXPECT_EQ(std::distance(fs::directory_iterator(dir / "out"), fs::directory_iterator()), 2);
        EXPECT_NE(first.out.find("baked"), std::string::npos) << first.out;
        EXPECT_EQ(first.out.find("from the cache"), std::string::npos) << first.out;
        const PackedLeanMap map = io::read_ktx2(brick.string());
        EXPECT_EQ(map.levels[0].width, 16);
        EXPECT_EQ(map.levels.size(), 5u);

        const std::string before = test::read_text(brick);
        const test::RunResult second = test::run_leanfade_in(args, dir, {}, test::cache_env(dir));
        ASSERT_EQ(second.exit_code, 0) << second.err;
        EXPECT_EQ(second.out.find("baked"), std::string::npos) << second.out;
        EXPECT_NE(second.out.find("from the cache"), std::string::npos) << second.out;
        EXPECT_EQ(test::read_text(brick), before);
    }
}

TEST(CliGltf, FlagsOfImageBakesAreRefused) {
    const fs::path dir = cli_gltf_folder("flags");
    const std::string input = (dir / "scene.glb").string();
    scene::test::write_gltf(scene_file(), input, GltfStorage::Binary);
    for (const std::string flag : {"--directx", "--strength 2", "--wrap clamp"}) {
        const test::RunResult r = test::run_leanfade_in(
            "bake " + test::shell_quote(input) + " " + flag, dir, {}, test::cache_env(dir));
        EXPECT_NE(r.exit_code, 0) << flag;
        EXPECT_NE(r.err.find("does not apply to a glTF scene"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    EXPECT_FALSE(fs::exists(dir / "scene.brick_wall.ktx2"));
}

TEST(CliGltf, BrokenScenesAreOneLineErrorsWithoutOutput) {
    const fs::path dir = cli_gltf_folder("broken");
    GltfTestFile file = scene_file();
    file.meshes[1][0].indices[4] = 9;  // out of range
    const std::string input = (dir / "scene.gltf").string();
    scene::test::write_gltf(file, input, GltfStorage::Embedded);
    test::RunResult r =
        test::run_leanfade_in("bake " + test::shell_quote(input), dir, {}, test::cache_env(dir));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find(input), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("index 9 out of range"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    // A truncated normal texture: nothing is published, not even the other material's map.
    file = scene_file();
    file.images[1].resize(40);
    scene::test::write_gltf(file, input, GltfStorage::Embedded);
    r = test::run_leanfade_in("bake " + test::shell_quote(input), dir, {}, test::cache_env(dir));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("image 1"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "scene.brick_wall.ktx2"));
    r = test::run_leanfade_in("bake " + test::shell_quote((dir / "missing.glb").string()), dir,
                              {}, test::cache_env(dir));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("missing.glb"), std::string::npos) << r.err;
}


namespace gltf_out {

// A normal texture with bumps that differ along u and v (anisotropic), 32 x 32.
std::vector<std::uint8_t> bumpy_normal_png() {
    std::vector<float> pixels;
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            const float a = 0.6f * std::sin(6.2831853f * float(x) / 4.0f);
            const glm::vec3 n = glm::normalize(glm::vec3(a, 0.05f * std::sin(float(y)), 1.0f));
            for (int c = 0; c < 3; ++c) pixels.push_back(0.5f * n[c] + 0.5f);
        }
    return scene::test::png_bytes(32, 32, 3, pixels);
}

// The file's bytes as its JSON (a .gltf) or the JSON chunk of a .glb.
nlohmann::json gltf_json(const fs::path& path) {
    const std::string bytes = test::read_text(path);
    if (bytes.rfind("glTF", 0) != 0) return nlohmann::json::parse(bytes);
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4);
    return nlohmann::json::parse(bytes.substr(20, length));
}

// The bytes an image or LEANFADE_lean_map entry of `gltf` stands for: the file its uri names
// beside it, or its buffer view in a .glb's binary chunk (buffer 0).
std::string resource_bytes(const fs::path& gltf, const nlohmann::json& entry) {
    if (entry.contains("uri")) return test::read_text(gltf.parent_path() / entry["uri"].get<std::string>());
    const std::string bytes = test::read_text(gltf);
    std::uint32_t json_length = 0, bin_length = 0;
    std::memcpy(&json_length, bytes.data() + 12, 4);
    std::memcpy(&bin_length, bytes.data() + 20 + json_length, 4);
    const std::string bin = bytes.substr(28 + json_length, bin_length);
    const nlohmann::json view =
        gltf_json(gltf)["bufferViews"][entry["bufferView"].get<std::size_t>()];
    EXPECT_EQ(view["buffer"], 0);
    return bin.substr(view.value("byteOffset", std::size_t(0)), view["byteLength"].get<std::size_t>());
}

// The same bytes as a file (for the readers that take a path).
fs::path resource_file(const fs::path& gltf, const nlohmann::json& entry, const std::string& name) {
    const fs::path file = gltf.parent_path() / ("resource." + name);
    std::ofstream(file, std::ios::binary) << resource_bytes(gltf, entry);
    return file;
}

}  // namespace gltf_out

// `bake SCENE -o OUT`: the materials point at filtered roughness and normal MIPs (KTX2 under
// KHR_texture_basisu with a PNG fallback), an anisotropy texture where the bumps are
// anisotropic, and the LEAN map (LEANFADE_lean_map); the rest of the file passes through; every
// file referenced exists and is what it says; nothing of the input is replaced.
TEST(CliGltfOut, WritesAFilteredCopyOfTheSceneAsGltfAndGlb) {
    for (const char* in_name : {"scene.gltf", "scene.glb"})
        for (const char* out_name : {"out/filtered.gltf", "out/filtered.glb"}) {
            const fs::path dir = cli_gltf_folder(std::string("out_") + fs::path(in_name).extension().string().substr(1) +
                                         "_" + fs::path(out_name).extension().string().substr(1));
            GltfTestFile file = scene_file();
            file.images.push_back(gltf_out::bumpy_normal_png());
            // Smooth (r = 0.2) and metallic, its bumps anisotropic; "metal" with a
            // metallic-roughness texture of another size than its normal texture.
            file.materials.push_back({"ribbed", glm::vec4(1.0f), -1, 2, 1.0f, 0.2f, 1.0f});
            file.materials[1].roughness = 0.5f;
            file.materials[1].metallic_roughness_image = 3;
            std::vector<float> mr;
            for (int t = 0; t < 8 * 8; ++t) mr.insert(mr.end(), {1.0f, 0.25f + 0.5f * float(t % 2), 0.8f});
            file.images.push_back(scene::test::png_bytes(8, 8, 3, mr));
            file.meshes.push_back({scene::test::unit_quad(4)});
            const fs::path input = dir / in_name;
            scene::test::write_gltf(file, input.string(),
                                    std::string(in_name).ends_with(".glb") ? GltfStorage::Binary
                                                                           : GltfStorage::External);
            fs::create_directories(dir / "out");
            std::map<fs::path, std::string> before;
            for (const auto& e : fs::directory_iterator(dir))
                if (e.is_regular_file()) before[e.path()] = test::read_text(e.path());
            const fs::path output = dir / out_name;
            // RGBA8 KTX2 (--compress none), whose texels are read back below; the default,
            // Basis Universal, is CompressBasisWritesKhrTextureBasisuImagesOfBasisUniversal's.
            const test::RunResult r = test::run_leanfade_in(
                "bake " + test::shell_quote(input.string()) + " -o " +
                    test::shell_quote(output.string()) + " --compress none",
                dir, {}, test::cache_env(dir));
            ASSERT_EQ(r.exit_code, 0) << r.err;
            for (const auto& [path, bytes] : before) EXPECT_EQ(test::read_text(path), bytes) << path;
            EXPECT_NE(r.out.find("wrote " + output.string()), std::string::npos) << r.out;

            const nlohmann::json j = gltf_out::gltf_json(output);
            const auto& used = j["extensionsUsed"];
            for (const char* ext : {"KHR_texture_basisu", "LEANFADE_lean_map", "KHR_materials_anisotropy"})
                EXPECT_NE(std::find(used.begin(), used.end(), ext), used.end()) << ext;
            EXPECT_FALSE(j.contains("extensionsRequired")) << "every extension is optional";
            ASSERT_EQ(j["materials"].size(), 5u);
            int anisotropic = 0;
            for (std::size_t m = 0; m < 5; ++m) {
                const auto& material = j["materials"][m];
                if (m == 3) {  // "plain": no normal texture, untouched
                    EXPECT_FALSE(material.contains("normalTexture"));
                    continue;
                }
                const auto& pbr = material["pbrMetallicRoughness"];
                EXPECT_EQ(pbr["roughnessFactor"], 1.0);
                for (const nlohmann::json* info :
                     {&pbr["metallicRoughnessTexture"], &material["normalTexture"]}) {
                    const auto& texture = j["textures"][(*info)["index"].get<std::size_t>()];
                    const auto& png = j["images"][texture["source"].get<std::size_t>()];
                    const auto& ktx2 = j["images"][texture["extensions"]["KHR_texture_basisu"]
                                                          ["source"]
                                                              .get<std::size_t>()];
                    EXPECT_EQ(png["mimeType"], "image/png");
                    EXPECT_EQ(ktx2["mimeType"], "image/ktx2");
                    // A .glb holds them in its binary chunk, a .gltf names files beside it.
                    EXPECT_EQ(ktx2.contains("bufferView"), output.extension() == ".glb");
                    EXPECT_EQ(png.contains("bufferView"), output.extension() == ".glb");
                    const fs::path ktx2_file = gltf_out::resource_file(output, ktx2, "ktx2");
                    const io::Ktx2Info info_ktx2 = io::inspect_ktx2(ktx2_file.string());
                    EXPECT_EQ(info_ktx2.vk_format, io::kVkFormatR8G8B8A8Unorm);
                    EXPECT_EQ(info_ktx2.level_count, m == 4 ? 6u : 5u) << ktx2_file;
                    EXPECT_EQ(gltf_out::resource_bytes(output, png).substr(1, 3), "PNG");
                    const auto& sampler = j["samplers"][texture["sampler"].get<std::size_t>()];
                    EXPECT_EQ(sampler["minFilter"], 9987);  // every level is used
                }
                const auto& lean = material["extensions"]["LEANFADE_lean_map"];
                EXPECT_EQ(lean.contains("bufferView"), output.extension() == ".glb");
                const PackedLeanMap map =
                    io::read_ktx2(gltf_out::resource_file(output, lean, "lean.ktx2").string());
                EXPECT_EQ(map.levels.size(), m == 4 ? 6u : 5u);
                anisotropic += material["extensions"].contains("KHR_materials_anisotropy");
            }
            // Metallic kept in B: "metal"'s texture's 0.8, resampled to its normal texture's
            // size; 1 where the material had no texture (metallicFactor applies as before).
            for (const auto& [m, blue] : {std::pair{1, 204}, std::pair{4, 255}}) {
                const auto& info = j["materials"][std::size_t(m)]["pbrMetallicRoughness"]
                                    ["metallicRoughnessTexture"];
                const auto& texture = j["textures"][info["index"].get<std::size_t>()];
                const auto& ktx2 = j["images"][texture["extensions"]["KHR_texture_basisu"]["source"]
                                                   .get<std::size_t>()];
                const auto levels = io::read_ktx2_rgba8(
                    gltf_out::resource_file(output, ktx2, "mr.ktx2").string());
                for (std::size_t t = 0; t < levels[0].texels.size(); t += 4)
                    ASSERT_NEAR(int(levels[0].texels[t + 2]), blue, 1) << "material " << m;
            }
            // Only "ribbed" has anisotropic bumps.
            EXPECT_EQ(anisotropic, 1);
            EXPECT_TRUE(j["materials"][4]["extensions"].contains("KHR_materials_anisotropy"));
            // Geometry passes through: every buffer the file names exists and holds its views.
            for (const auto& buffer : j["buffers"]) {
                if (!buffer.contains("uri")) continue;  // the GLB's binary chunk
                const fs::path bin = output.parent_path() / buffer["uri"].get<std::string>();
                ASSERT_TRUE(fs::exists(bin)) << bin;
                EXPECT_EQ(fs::file_size(bin), buffer["byteLength"].get<std::uintmax_t>());
            }
            EXPECT_EQ(j["meshes"].size(), 5u);
            EXPECT_EQ(j["accessors"].size(), gltf_out::gltf_json(input)["accessors"].size());
        }
}

// `bake SCENE -o OUT` (--compress basis, the default): every KHR_texture_basisu image is what the extension
// requires (KTX2 of Basis Universal UASTC, Zstandard or none, one UASTC RGB channel, primaries
// unspecified and linear transfer for non-colour data, sizes multiples of 4, no KTXswizzle) with
// the full chain of levels; the Khronos glTF-Validator finds no error; a second run takes the same
// bytes from the cache. --compress bc is refused for a glTF, and --compress without -o.
TEST(CliGltfOut, CompressBasisWritesKhrTextureBasisuImagesOfBasisUniversal) {
    ASSERT_NE(std::string(LEANFADE_NODE).find('/'), std::string::npos) << "Node.js is missing";
    const fs::path dir = cli_gltf_folder("out_basis");
    GltfTestFile file = scene_file();
    file.images.push_back(gltf_out::bumpy_normal_png());
    file.materials.push_back({"ribbed", glm::vec4(1.0f), -1, 2, 1.0f, 0.2f, 1.0f});
    file.meshes.push_back({scene::test::unit_quad(4)});
    const fs::path input = dir / "scene.gltf";
    scene::test::write_gltf(file, input.string(), GltfStorage::External);
    fs::create_directories(dir / "out");
    fs::create_directories(dir / "again");
    const auto bake = [&](const std::string& output, const std::string& flags) {
        return test::run_leanfade_in("bake " + test::shell_quote(input.string()) + " -o " +
                                         test::shell_quote((dir / output).string()) + flags,
                                     dir, {}, test::cache_env(dir));
    };
    const test::RunResult r = bake("out/filtered.gltf", "");  // Basis Universal by default
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json j = gltf_out::gltf_json(dir / "out" / "filtered.gltf");
    std::size_t images = 0;
    for (const auto& texture : j["textures"]) {
        if (!texture.contains("extensions")) continue;
        const auto& ktx2 =
            j["images"][texture["extensions"]["KHR_texture_basisu"]["source"].get<std::size_t>()];
        const fs::path path = dir / "out" / ktx2["uri"].get<std::string>();
        const io::UastcFileInfo info = io::inspect_ktx2_uastc(path.string());
        EXPECT_TRUE(info.zstd) << path;
        EXPECT_TRUE(info.linear) << path;
        EXPECT_TRUE(info.primaries_unspecified) << path;
        EXPECT_FALSE(info.alpha) << path;
        EXPECT_EQ(info.width % 4, 0) << path;
        EXPECT_EQ(info.height % 4, 0) << path;
        int chain = 1;
        for (int side = std::max(info.width, info.height); side > 1; side /= 2) ++chain;
        EXPECT_EQ(info.levels, chain) << path;
        EXPECT_EQ(test::read_text(path).find("KTXswizzle"), std::string::npos) << path;
        ++images;
    }
    // Roughness and normal of the two normal textures, and the ribbed one's anisotropy.
    EXPECT_EQ(images, 2u * 3u + 1u);
    // The Khronos glTF-Validator: no error (it does not read KTX2: the checks above do).
    const fs::path report = dir / "validator.json";
    const std::string command =
        test::shell_quote(LEANFADE_NODE) + " " + test::shell_quote(LEANFADE_GLTF_VALIDATOR_SCRIPT) +
        " " + test::shell_quote(LEANFADE_GLTF_VALIDATOR) + " " +
        test::shell_quote((dir / "out" / "filtered.gltf").string()) + " >" +
        test::shell_quote(report.string());
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    const nlohmann::json issues = nlohmann::json::parse(test::read_text(report))["issues"];
    EXPECT_EQ(issues["numErrors"], 0) << issues.dump(1);
    // From the cache: the same bytes.
    const test::RunResult again = bake("again/filtered.gltf", " --compress basis");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    for (const auto& e : fs::directory_iterator(dir / "out")) {
        if (e.path().extension() == ".ktx2") {
            EXPECT_EQ(test::read_text(e.path()),
                      test::read_text(dir / "again" / e.path().filename()))
                << e.path();
        }
    }
    for (const std::string flags : {" --compress bc", " --compress astc"}) {
        const test::RunResult refused = bake("out/bc.gltf", flags);
        EXPECT_EQ(refused.exit_code, 1) << flags;
        EXPECT_NE(refused.err.find("--compress"), std::string::npos) << refused.err;
        EXPECT_FALSE(fs::exists(dir / "out" / "bc.gltf"));
    }
    const test::RunResult no_output = test::run_leanfade_in(
        "bake " + test::shell_quote(input.string()) + " --compress basis", dir, {},
        test::cache_env(dir));
    EXPECT_EQ(no_output.exit_code, 1);
    EXPECT_NE(no_output.err.find("--compress"), std::string::npos) << no_output.err;
}

// -o into a folder that does not exist creates it, as for any bake; a run that fails removes it
// again.
TEST(CliGltfOut, OutputFolderIsCreatedAndRemovedOnFailure) {
    const fs::path dir = cli_gltf_folder("out_new_folder");
    const fs::path input = dir / "scene.glb";
    scene::test::write_gltf(scene_file(), input.string(), GltfStorage::Binary);
    const auto bake = [&](const std::string& output, const std::string& flags) {
        return test::run_leanfade_in("bake " + test::shell_quote(input.string()) + " -o " +
                                         test::shell_quote((dir / output).string()) + flags,
                                     dir, {}, test::cache_env(dir));
    };
    const test::RunResult ok = bake("new/deeper/filtered.glb", "");
    ASSERT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_TRUE(fs::is_regular_file(dir / "new" / "deeper" / "filtered.glb"));
    const test::RunResult refused = bake("other/filtered.glb", " --compress bc");
    EXPECT_EQ(refused.exit_code, 1);
    EXPECT_FALSE(fs::exists(dir / "other"));
}

// `bake SCENE -o OUT` keeps where every texture reference samples: the references it leaves
// alone (base colour, occlusion, emissive) as they were, texCoord and KHR_texture_transform
// (its texCoord override included); the filtered textures it adds (metallic-roughness, normal)
// with the normal texture's texCoord and transform, the set and mapping they were filtered in.
TEST(CliGltfOut, TextureCoordinateSetsAndTransformsAreKept) {
    const fs::path dir = cli_gltf_folder("out_tex_coords");
    GltfTestFile file;
    file.images = {normal_png({0.3f, 0.0f, 1.0f}), normal_png({0.0f, 0.0f, 1.0f})};
    const nlohmann::json turned = {{"KHR_texture_transform", {{"rotation", 0.5}}}};
    const nlohmann::json override_to_0 = {
        {"KHR_texture_transform", {{"offset", {0.25, 0.0}}, {"texCoord", 0}}}};
    file.materials = {{"two sets", glm::vec4(1.0f), 1, 0, 1.0f}};
    file.materials[0].patch = {
        {"normalTexture", {{"texCoord", 1}, {"extensions", turned}}},
        {"pbrMetallicRoughness",
         {{"baseColorTexture", {{"texCoord", 1}, {"extensions", override_to_0}}}}},
        {"occlusionTexture", {{"index", 1}, {"texCoord", 1}}},
        {"emissiveTexture", {{"index", 1}, {"extensions", turned}}}};
    file.meshes = {{scene::test::unit_quad(0)}};
    for (const glm::vec3& q : file.meshes[0][0].positions)
        file.meshes[0][0].uvs1.push_back(glm::vec2(q.y, q.x));
    file.patch = {{"extensionsUsed", {"KHR_texture_transform"}}};
    const fs::path input = dir / "scene.glb";
    scene::test::write_gltf(file, input.string(), GltfStorage::Binary);
    const fs::path output = dir / "filtered.glb";
    const test::RunResult r = test::run_leanfade_in(
        "bake " + test::shell_quote(input.string()) + " -o " + test::shell_quote(output.string()),
        dir, {}, test::cache_env(dir));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json before = gltf_out::gltf_json(input)["materials"][0];
    const nlohmann::json after = gltf_out::gltf_json(output)["materials"][0];
    for (const char* key : {"occlusionTexture", "emissiveTexture"})
        EXPECT_EQ(after[key], before[key]) << key;
    EXPECT_EQ(after["pbrMetallicRoughness"]["baseColorTexture"],
              before["pbrMetallicRoughness"]["baseColorTexture"]);
    for (const nlohmann::json& info :
         {after["normalTexture"], after["pbrMetallicRoughness"]["metallicRoughnessTexture"]}) {
        EXPECT_EQ(info["texCoord"], 1) << info.dump();
        EXPECT_EQ(info["extensions"], turned) << info.dump();
        EXPECT_NE(info["index"], before["normalTexture"]["index"]) << "a filtered texture";
    }
}

// The round trip: `render --scene OUT` draws the LEAN maps the file names (LEANFADE_lean_map),
// the same pixels as the original scene, and every technique reads them.
TEST(CliGltfOut, TheFilteredCopyRendersAsTheScene) {
    const fs::path dir = cli_gltf_folder("out_round_trip");
    const fs::path input = dir / "scene.glb";
    scene::test::write_gltf(scene_file(), input.string(), GltfStorage::Binary);
    fs::create_directories(dir / "out");
    const fs::path output = dir / "out" / "filtered.gltf";
    ASSERT_EQ(test::run_leanfade_in("bake " + test::shell_quote(input.string()) + " -o " +
                                        test::shell_quote(output.string()),
                                    dir, {}, test::cache_env(dir))
                  .exit_code,
              0);
    const auto render = [&](const fs::path& scene, const std::string& png) {
        return test::run_leanfade_in("render --scene " + test::shell_quote(scene.string()) +
                                         " --techniques bump,lean,two-lobe --distances 3,12 "
                                         "--size 64x64 -o " +
                                         test::shell_quote((dir / png).string()),
                                     dir, {}, test::cache_env(dir));
    };
    const test::RunResult a = render(input, "scene.png");
    const test::RunResult b = render(output, "filtered.png");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    ASSERT_EQ(b.exit_code, 0) << b.err;
    EXPECT_EQ(test::read_text(dir / "scene.png"), test::read_text(dir / "filtered.png"));
    // A .glb output holds its LEAN maps in its binary chunk: drawn from there, the same pixels,
    // and nothing written beside it but the .glb.
    const fs::path glb = dir / "glb" / "filtered.glb";
    fs::create_directories(glb.parent_path());
    ASSERT_EQ(test::run_leanfade_in("bake " + test::shell_quote(input.string()) + " -o " +
                                        test::shell_quote(glb.string()),
                                    dir, {}, test::cache_env(dir))
                  .exit_code,
              0);
    EXPECT_EQ(std::distance(fs::directory_iterator(glb.parent_path()), fs::directory_iterator()), 1);
    const test::RunResult c = render(glb, "embedded.png");
    ASSERT_EQ(c.exit_code, 0) << c.err;
    EXPECT_EQ(test::read_text(dir / "scene.png"), test::read_text(dir / "embedded.png"));
    // A buffer view that is not one, or runs past its buffer: a one-line error naming it.
    for (const int view : {99, -1}) {
        nlohmann::json root = gltf_out::gltf_json(output);
        for (auto& material : root["materials"])
            if (material.contains("extensions"))
                material["extensions"]["LEANFADE_lean_map"] = {{"bufferView", view}};
        const fs::path bad = dir / "out" / "bad_view.gltf";
        std::ofstream(bad) << root.dump();
        const test::RunResult r = render(bad, "bad.png");
        EXPECT_NE(r.exit_code, 0);
        EXPECT_NE(r.err.find("LEANFADE_lean_map bufferView"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(dir / "bad.png"));
    }
    // A LEAN map the file names that is missing is an error naming it, not a silent bake.
    fs::remove(dir / "out" / "filtered.metal.lean.ktx2");
    const test::RunResult missing = render(output, "missing.png");
    EXPECT_NE(missing.exit_code, 0);
    EXPECT_NE(missing.err.find("filtered.metal.lean.ktx2"), std::string::npos) << missing.err;
    EXPECT_FALSE(fs::exists(dir / "missing.png"));
}

// Safety: names derived from material names stay inside the output's folder and are unique; an
// output that would replace an input (the scene, its buffer, its images) is refused before
// anything is written.
TEST(CliGltfOut, NamesAreSafeAndNoInputIsReplaced) {
    const fs::path dir = cli_gltf_folder("out_safety");
    GltfTestFile file = scene_file();
    file.materials[0].name = "../../etc/passwd";
    file.materials[1].name = "../../etc/passwd";  // the same file name part: numbered
    const fs::path input = dir / "scene.gltf";
    scene::test::write_gltf(file, input.string(), GltfStorage::External);
    const test::RunResult ok = test::run_leanfade_in(
        "bake " + test::shell_quote(input.string()) + " -o " +
            test::shell_quote((dir / "out.gltf").string()),
        dir, {}, test::cache_env(dir));
    ASSERT_EQ(ok.exit_code, 0) << ok.err;
    EXPECT_TRUE(fs::exists(dir / "out.______etc_passwd.lean.ktx2")) << ok.out;
    EXPECT_TRUE(fs::exists(dir / "out.______etc_passwd-2.lean.ktx2")) << ok.out;
    for (const auto& e : fs::recursive_directory_iterator(dir.parent_path()))
        EXPECT_EQ(e.path().string().find("passwd/"), std::string::npos) << e.path();

    // An output named like one of the scene's own images, and -o the scene itself.
    const fs::path image = dir / "scene_image0.png";
    ASSERT_TRUE(fs::exists(image));
    const std::string image_before = test::read_text(image);
    fs::copy_file(image, dir / "x.______etc_passwd.roughness.png");
    nlohmann::json j = nlohmann::json::parse(test::read_text(input));
    j["images"][0]["uri"] = "x.______etc_passwd.roughness.png";
    std::ofstream(dir / "x_scene.gltf") << j.dump();
    const std::string x_before = test::read_text(dir / "x.______etc_passwd.roughness.png");
    for (const auto& [scene_file_name, out] :
         {std::pair{"x_scene.gltf", "x.gltf"}, std::pair{"scene.gltf", "scene.gltf"}}) {
        const test::RunResult r = test::run_leanfade_in(
            "bake " + test::shell_quote((dir / scene_file_name).string()) + " -o " +
                test::shell_quote((dir / out).string()),
            dir, {}, test::cache_env(dir));
        EXPECT_NE(r.exit_code, 0) << out;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(r.err.find("input"), std::string::npos) << r.err;
    }
    EXPECT_FALSE(fs::exists(dir / "x.gltf"));
    EXPECT_FALSE(fs::exists(dir / "x.______etc_passwd.lean.ktx2"));
    EXPECT_EQ(test::read_text(dir / "x.______etc_passwd.roughness.png"), x_before);
    EXPECT_EQ(test::read_text(image), image_before);
    // Not a glTF output name, and --out-dir with -o.
    for (const std::string& flags : {std::string("-o ") + test::shell_quote((dir / "o.ktx2").string()),
                                     "-o " + test::shell_quote((dir / "o.gltf").string()) +
                                         " --out-dir " + test::shell_quote(dir.string())}) {
        const test::RunResult r = test::run_leanfade_in(
            "bake " + test::shell_quote(input.string()) + " " + flags, dir, {}, test::cache_env(dir));
        EXPECT_NE(r.exit_code, 0) << flags;
        EXPECT_FALSE(fs::exists(dir / "o.gltf"));
    }
}

// A second run over the same scene copies its outputs (LEAN maps and engine textures) from the
// cache, the same bytes; a damaged cache entry (its manifest, or a file of another size) is made
// again.
TEST(CliGltfOut, ASecondRunTakesItsOutputsFromTheCache) {
    const fs::path dir = cli_gltf_folder("out_cache");
    const fs::path input = dir / "scene.glb";
    scene::test::write_gltf(scene_file(), input.string(), GltfStorage::Binary);
    const auto run = [&](const std::string& out) {
        const test::RunResult r = test::run_leanfade_in(
            "bake " + test::shell_quote(input.string()) + " -o " +
                test::shell_quote((dir / (out + ".gltf")).string()) + " --json " +
                test::shell_quote((dir / (out + ".json")).string()),
            dir, {}, test::cache_env(dir));
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return nlohmann::json::parse(test::read_text(dir / (out + ".json")));
    };
    const nlohmann::json first = run("a");
    const nlohmann::json second = run("b");
    ASSERT_EQ(first.size(), 3u);  // the materials with a normal texture
    // "brick again" has the textures and factors of "brick wall": it shares its files (written
    // once, one texture each in the JSON), in the first run too.
    const bool first_expected[] = {false, false, true};
    EXPECT_EQ(first[2]["same_files_as"], "brick wall");
    EXPECT_TRUE(first[0]["same_files_as"].is_null());
    EXPECT_EQ(first[2]["lean_map"], first[0]["lean_map"]);
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().find("brick_again"), std::string::npos)
            << e.path();
    {
        const nlohmann::json root = gltf_out::gltf_json(dir / "a.gltf");
        const nlohmann::json& materials = root["materials"];
        EXPECT_EQ(materials[2]["normalTexture"]["index"], materials[0]["normalTexture"]["index"]);
        EXPECT_EQ(materials[2]["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"],
                  materials[0]["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"]);
        EXPECT_NE(materials[1]["normalTexture"]["index"], materials[0]["normalTexture"]["index"]);
        EXPECT_EQ(materials[2]["extensions"]["LEANFADE_lean_map"]["uri"],
                  materials[0]["extensions"]["LEANFADE_lean_map"]["uri"]);
    }
    for (std::size_t i = 0; i < first.size(); ++i) {
        EXPECT_EQ(first[i]["textures_from_cache"].get<bool>(), first_expected[i]) << i;
        EXPECT_TRUE(second[i]["textures_from_cache"].get<bool>()) << i;
    }
    const char* const files[] = {".brick_wall.lean.ktx2", ".brick_wall.roughness.ktx2",
                                 ".brick_wall.normal.png", ".metal.normal.ktx2", ".metal.lean.ktx2"};
    for (const char* file : files)
        EXPECT_EQ(test::read_text(dir / (std::string("a") + file)),
                  test::read_text(dir / (std::string("b") + file)))
            << file;
    // Damaged entries (every manifest cut short) are not found: made again, the same bytes.
    int manifests = 0;
    for (const auto& e : fs::directory_iterator(dir / "cache" / "leanfade"))
        if (e.path().string().ends_with(".gltf-out.json")) {
            std::ofstream(e.path()) << "{";
            ++manifests;
        }
    EXPECT_EQ(manifests, 2);  // "brick again" shares the entry of "brick wall"
    const nlohmann::json third = run("c");
    for (std::size_t i = 0; i < third.size(); ++i)
        EXPECT_EQ(third[i]["textures_from_cache"].get<bool>(), first_expected[i]) << i;
    // A cached file of another size than its manifest says (cut short): made again.
    int cut = 0;
    for (const auto& e : fs::directory_iterator(dir / "cache" / "leanfade"))
        if (e.path().string().ends_with(".lean.ktx2")) {
            fs::resize_file(e.path(), 100);
            ++cut;
        }
    EXPECT_EQ(cut, 2);
    const nlohmann::json fourth = run("d");
    for (std::size_t i = 0; i < fourth.size(); ++i)
        EXPECT_EQ(fourth[i]["textures_from_cache"].get<bool>(), first_expected[i]) << i;
    for (const char* out : {"c", "d"})
        for (const char* file : files)
            EXPECT_EQ(test::read_text(dir / (std::string("a") + file)),
                      test::read_text(dir / (std::string(out) + file)))
                << out << file;
}

// The cache entries of `bake SCENE -o OUT` are verified, bounded and limited as a bake is.
namespace gltf_out {

std::vector<fs::path> cache_entries(const fs::path& dir, const std::string& suffix) {
    std::vector<fs::path> found;
    for (const auto& e : fs::directory_iterator(dir / "cache" / "leanfade"))
        if (e.path().string().ends_with(suffix)) found.push_back(e.path());
    std::sort(found.begin(), found.end());
    return found;
}

}  // namespace gltf_out

// Before: an entry was trusted on its size: a same-size corrupt LEAN map, or another key's files
// renamed, were published with exit 0; the manifest was read with a 4 GiB limit and parsed; and
// a cache hit skipped --max-size (exit 1 on an empty cache, 0 on a warm one). Now each copy must
// have the SHA-256 its manifest records, the manifest must name its own key and hold at most
// 4 KiB (unread beyond), and the limits apply to the sizes the entry records.
TEST(CliGltfOut, CacheEntriesAreVerifiedBoundedAndLimited) {
    const fs::path dir = cli_gltf_folder("out_cache_verified");
    const fs::path input = dir / "scene.glb";
    scene::test::write_gltf(scene_file(), input.string(), GltfStorage::Binary);
    const auto run = [&](const std::string& out, const std::string& flags = "") {
        return test::run_leanfade_in("bake " + test::shell_quote(input.string()) + " -o " +
                                         test::shell_quote((dir / (out + ".glb")).string()) +
                                         " --json " +
                                         test::shell_quote((dir / (out + ".json")).string()) +
                                         flags,
                                     dir, {}, test::cache_env(dir));
    };
    const auto from_cache = [&](const std::string& out) {
        std::vector<bool> flags;
        for (const auto& m : nlohmann::json::parse(test::read_text(dir / (out + ".json"))))
            flags.push_back(m["textures_from_cache"].get<bool>());
        return flags;
    };
    const std::vector<bool> remade = {false, false, true};  // "brick again" shares an entry
    const char* const files[] = {".brick_wall.lean.ktx2", ".brick_wall.roughness.ktx2",
                                 ".brick_wall.normal.png", ".metal.normal.ktx2",
                                 ".metal.lean.ktx2"};
    const auto same_as_first = [&](const std::string& out) {
        for (const char* file : files)
            EXPECT_EQ(test::read_text(dir / (std::string("a").append(file))),
                      test::read_text(dir / (std::string(out).append(file))))
                << out << file;
    };
    ASSERT_EQ(run("a").exit_code, 0);
    EXPECT_EQ(from_cache("a"), remade);
    ASSERT_EQ(run("warm").exit_code, 0);
    EXPECT_EQ(from_cache("warm"), (std::vector<bool>{true, true, true}));

    // A byte changed in the middle of every cached LEAN map: the size is right, the bytes not.
    const std::vector<fs::path> maps = gltf_out::cache_entries(dir, ".lean.ktx2");
    ASSERT_EQ(maps.size(), 2u);
    for (const fs::path& map : maps) {
        std::string bytes = test::read_text(map);
        bytes[bytes.size() / 2] = char(bytes[bytes.size() / 2] ^ 0x5A);
        std::ofstream(map, std::ios::binary) << bytes;
    }
    ASSERT_EQ(run("b").exit_code, 0);
    EXPECT_EQ(from_cache("b"), remade);
    same_as_first("b");

    // The two keys' normal textures swapped (same sizes, 16 x 16 each; other normals).
    const std::vector<fs::path> normals = gltf_out::cache_entries(dir, ".normal.ktx2");
    ASSERT_EQ(normals.size(), 2u);
    ASSERT_EQ(fs::file_size(normals[0]), fs::file_size(normals[1]));
    ASSERT_NE(test::read_text(normals[0]), test::read_text(normals[1]));
    fs::rename(normals[0], dir / "swap");
    fs::rename(normals[1], normals[0]);
    fs::rename(dir / "swap", normals[1]);
    ASSERT_EQ(run("c").exit_code, 0);
    EXPECT_EQ(from_cache("c"), remade);
    same_as_first("c");

    // Another key's whole entry, manifest included, under this key's names.
    std::vector<fs::path> manifests = gltf_out::cache_entries(dir, ".gltf-out.json");
    ASSERT_EQ(manifests.size(), 2u);
    const std::string key0 = manifests[0].filename().string().substr(0, 64);
    const std::string key1 = manifests[1].filename().string().substr(0, 64);
    for (const auto& e : fs::directory_iterator(dir / "cache" / "leanfade")) {
        const std::string name = e.path().filename().string();
        if (name.rfind(key1, 0) == 0 && name.find(".tmp-") == std::string::npos)
            fs::copy_file(e.path(), dir / "cache" / "leanfade" / (key0 + name.substr(64)),
                          fs::copy_options::overwrite_existing);
    }
    ASSERT_EQ(run("d").exit_code, 0);
    // Key 0's entry names key 1 inside: its material remade, the other's entry used.
    const std::vector<bool> d = from_cache("d");
    EXPECT_EQ(std::count(d.begin(), d.end(), false), 1);
    same_as_first("d");

    // A manifest of 200 kB (its JSON padded with spaces): not read, the material remade.
    manifests = gltf_out::cache_entries(dir, ".gltf-out.json");
    for (const fs::path& manifest : manifests) {
        const std::string text = test::read_text(manifest);
        std::ofstream(manifest, std::ios::binary) << text << std::string(200000, ' ');
    }
    ASSERT_EQ(run("e").exit_code, 0);
    EXPECT_EQ(from_cache("e"), remade);
    same_as_first("e");

    // --max-size below the textures' 16 x 16: the same refusal, whether the cache is warm (as
    // it is now) or empty.
    const test::RunResult warm = run("f", " --max-size 8");
    EXPECT_EQ(warm.exit_code, 1) << warm.err;
    EXPECT_NE(warm.err.find("image size 16x16 exceeds the limit of 8 texels per side"),
              std::string::npos)
        << warm.err;
    EXPECT_FALSE(fs::exists(dir / "f.glb"));
    const test::RunResult cold = test::run_leanfade_in(
        "bake " + test::shell_quote(input.string()) + " -o " +
            test::shell_quote((dir / "f.glb").string()) + " --json " +
            test::shell_quote((dir / "f.json").string()) + " --max-size 8",
        dir, {}, test::cache_env(dir / "empty"));
    EXPECT_EQ(cold.exit_code, 1) << cold.err;
    EXPECT_EQ(warm.err, cold.err);
}

// Before: `bake X.gltf -o OTHER/o.gltf` left a material's own LEANFADE_lean_map URI naming a file
// that was not copied, and a texture that is a symbolic link inside the scene's folder failed the
// copy with errno's "Too many levels of symbolic links". The map is copied beside the output and
// its URI rewritten; a linked texture is copied from the file it leads to.
TEST(CliGltfOut, OwnLeanMapsAndLinkedTexturesAreCopiedIntoAnotherFolder) {
    const fs::path dir = cli_gltf_folder("out_own_map_links");
    const fs::path input = dir / "scene.gltf";
    scene::test::write_gltf(scene_file(), input.string(), GltfStorage::External);
    // The plain material names a LEAN map of its own.
    ASSERT_EQ(test::run_leanfade_in("bake --builtin bumps --size 8 -o own.ktx2", dir, dir).exit_code,
              0);
    nlohmann::json j = nlohmann::json::parse(test::read_text(input));
    j["materials"][3]["extensions"]["LEANFADE_lean_map"] = {{"uri", "own.ktx2"}};
    std::ofstream(input) << j.dump(1);
    // The second normal texture is a link to a file in a subfolder of the scene's folder.
    fs::create_directories(dir / "textures");
    fs::rename(dir / "scene_image1.png", dir / "textures" / "metal.png");
    fs::create_symlink("textures/metal.png", dir / "scene_image1.png");
    fs::create_directories(dir / "other");
    const test::RunResult r = test::run_leanfade_in(
        "bake " + test::shell_quote(input.string()) + " -o " +
            test::shell_quote((dir / "other" / "o.gltf").string()),
        dir, {}, test::cache_env(dir));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const nlohmann::json out = gltf_out::gltf_json(dir / "other" / "o.gltf");
    const std::string own = out["materials"][3]["extensions"]["LEANFADE_lean_map"]["uri"];
    EXPECT_NE(own, "own.ktx2");
    ASSERT_TRUE(fs::is_regular_file(dir / "other" / own)) << own;
    EXPECT_EQ(test::read_text(dir / "other" / own), test::read_text(dir / "own.ktx2"));
    bool linked_copied = false;
    for (const auto& image : out["images"]) {
        const std::string uri = image["uri"];
        ASSERT_TRUE(fs::exists(dir / "other" / uri)) << uri;
        EXPECT_FALSE(fs::is_symlink(dir / "other" / uri)) << uri;
        if (test::read_text(dir / "other" / uri) == test::read_text(dir / "textures" / "metal.png"))
            linked_copied = true;
    }
    EXPECT_TRUE(linked_copied);
    // The same map given as another output's name is an input: refused before anything runs.
    const test::RunResult over = test::run_leanfade_in(
        "bake " + test::shell_quote(input.string()) + " -o " +
            test::shell_quote((dir / "o2.gltf").string()) + " --json " +
            test::shell_quote((dir / "own.ktx2").string()),
        dir, {}, test::cache_env(dir));
    EXPECT_EQ(over.exit_code, 1) << over.err;
    EXPECT_NE(over.err.find("is the same file as"), std::string::npos) << over.err;
    EXPECT_FALSE(fs::exists(dir / "o2.gltf"));
}

// ---- The file system's limits while the caches are written ----

namespace gltf_out {

// Every file under `dir` whose name holds ".tmp-" (a temporary), recursively.
std::vector<std::string> temporaries_under(const fs::path& dir) {
    std::vector<std::string> found;
    if (!fs::exists(dir)) return found;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (e.path().filename().string().find(".tmp-") != std::string::npos)
            found.push_back(e.path().string());
    return found;
}

std::size_t files_in(const fs::path& dir) {
    std::size_t count = 0;
    if (!fs::exists(dir)) return count;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (!e.is_directory()) ++count;
    return count;
}

}  // namespace gltf_out

// Before: under `ulimit -f` a write past the limit killed the run with SIGXFSZ (status 153, no
// message), leaving its temporaries, in the cache too. Every file is limited here to 4 KiB (8
// blocks of 512 bytes, dash). `render` of the scene writes a picture under the limit and LEAN
// maps over it into the cache: each store fails as a warning naming the entry, the picture is
// written (exit 0). `bake -o` (the glTF-out cache) and `bake --out-dir` (LEAN maps) fail on
// their outputs (exit 1). Nothing is left in the outputs' folder or the cache, and no message
// names a temporary.
TEST(CliGltfOut, FileSizeLimitLeavesNoTemporaryInTheOutputsOrTheCache) {
    const fs::path dir = cli_gltf_folder("out_cache_fsize");
    const fs::path input = dir / "scene.glb";
    scene::test::write_gltf(scene_file(), input.string(), GltfStorage::Binary);
    const std::string before = test::read_text(input);
    const std::string limited = test::cache_env(dir) + " sh -c 'ulimit -f 8 && exec \"$@\"' sh";
    const fs::path picture = dir / "out" / "r.png";
    struct Case {
        std::string flags;
        int exit_code;
    };
    for (const Case& c : {Case{"render --scene " + test::shell_quote(input.string()) +
                                   " --size 16x16 --techniques lean --distances 3 -o " +
                                   test::shell_quote(picture.string()),
                               0},
                          Case{"bake " + test::shell_quote(input.string()) + " -o " +
                                   test::shell_quote((dir / "out" / "f.glb").string()),
                               1},
                          // Uncompressed LEAN maps: over the limit (Zstandard's fit under it).
                          Case{"bake " + test::shell_quote(input.string()) + " --out-dir " +
                                   test::shell_quote((dir / "out").string()) +
                                   " --supercompression none",
                               1}}) {
        SCOPED_TRACE(c.flags);
        fs::remove_all(dir / "cache");
        fs::remove_all(dir / "out");
        fs::create_directories(dir / "out");
        const test::RunResult r = test::run_leanfade_in(c.flags, dir, {}, limited);
        EXPECT_EQ(r.exit_code, c.exit_code) << r.err;
        EXPECT_NE(r.err.find("File too large"), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find(".tmp-"), std::string::npos) << r.err;
        if (c.exit_code == 0) {
            // The stores' warnings name the entries.
            EXPECT_NE(r.err.find("cache: " + (dir / "cache" / "leanfade").string() + "/"),
                      std::string::npos)
                << r.err;
            EXPECT_TRUE(fs::is_regular_file(picture));
            EXPECT_EQ(gltf_out::files_in(dir / "out"), 1u);
        } else {
            EXPECT_EQ(gltf_out::files_in(dir / "out"), 0u);
        }
        EXPECT_EQ(gltf_out::temporaries_under(dir / "cache"), std::vector<std::string>{});
        EXPECT_EQ(gltf_out::temporaries_under(dir / "out"), std::vector<std::string>{});
        EXPECT_EQ(test::read_text(input), before);
        // Without the limit the same run writes its outputs and fills the cache.
        fs::remove_all(dir / "out");
        fs::create_directories(dir / "out");
        const test::RunResult ok = test::run_leanfade_in(c.flags, dir, {}, test::cache_env(dir));
        EXPECT_EQ(ok.exit_code, 0) << ok.err;
        EXPECT_GT(gltf_out::files_in(dir / "out"), 0u);
        EXPECT_GT(gltf_out::files_in(dir / "cache" / "leanfade"), 0u);
    }
}

// Before: a store into a full cache warned with the name of the entry's temporary ("cannot
// create temporary file .../KEY.ktx2.tmp-PID-N-RUN"). The cache's folder is full here (creating
// a file there fails with ENOSPC: tests/support/preload/full_folder.c): each run does its work
// and exits 0, each store is a warning naming its entry and the cause, none a temporary, and
// nothing is left in the cache.
TEST(CliGltfOut, AFullCacheIsAWarningNamingTheEntryNotItsTemporary) {
    const fs::path dir = cli_gltf_folder("out_cache_full");
    const fs::path input = dir / "scene.glb";
    scene::test::write_gltf(scene_file(), input.string(), GltfStorage::Binary);
    const fs::path cache = dir / "cache" / "leanfade";
    fs::create_directories(cache);
    const char* asan = std::getenv("ASAN_OPTIONS");
    // The preloaded library comes before the sanitizers' runtime, which checks that it is first.
    const std::string full =
        test::cache_env(dir) + " MESA_SHADER_CACHE_DISABLE=true LD_PRELOAD=" +
        test::shell_quote(LEANFADE_TEST_FULL_FOLDER_PRELOAD) +
        " LEANFADE_TEST_FULL_FOLDER=" + test::shell_quote((dir / "cache").string()) +
        " ASAN_OPTIONS=" +
        test::shell_quote((asan != nullptr && *asan != '\0' ? std::string(asan) + ":" : "") +
                          "verify_asan_link_order=0");
    fs::create_directories(dir / "out");
    for (const std::string& flags : {"render --scene " + test::shell_quote(input.string()) +
                                         " --size 16x16 --techniques lean --distances 3 -o " +
                                         test::shell_quote((dir / "out" / "r.png").string()),
                                     "bake " + test::shell_quote(input.string()) + " -o " +
                                         test::shell_quote((dir / "out" / "f.glb").string()),
                                     "bake " + test::shell_quote(input.string()) + " --out-dir " +
                                         test::shell_quote((dir / "out").string())}) {
        SCOPED_TRACE(flags);
        const test::RunResult r = test::run_leanfade_in(flags, dir, {}, full);
        EXPECT_EQ(r.exit_code, 0) << r.err;
        EXPECT_NE(r.err.find("cache: " + cache.string() + "/"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(": cannot create a temporary file in its folder (No space left on "
                             "device)"),
                  std::string::npos)
            << r.err;
        EXPECT_EQ(r.err.find(".tmp-"), std::string::npos) << r.err;
        EXPECT_EQ(gltf_out::files_in(dir / "cache"), 0u);
    }
    EXPECT_TRUE(fs::is_regular_file(dir / "out" / "r.png"));
    EXPECT_TRUE(fs::is_regular_file(dir / "out" / "f.glb"));
    EXPECT_TRUE(fs::is_regular_file(dir / "out" / "scene.brick_wall.ktx2"));
}

}  // namespace
// glTF normal textures are OpenGL (+Y): one that fits a height field clearly better with green
// flipped gets the convention warning on every bake path: `bake SCENE --out-dir`, and
// `bake SCENE -o OUT` whether its outputs are baked or taken from the cache.
TEST(CliGltfOut, DirectXLookingNormalTextureIsWarnedOnEveryPath) {
    const fs::path dir = cli_gltf_folder("out_convention");
    // The built-in bumps as an OpenGL normal map (a bake's lean1 rgb), its green flipped.
    const fs::path base = dir / "bumps";
    ASSERT_EQ(test::run_leanfade("bake --builtin bumps --size 96 --format png --bits 8 -o " +
                                     test::shell_quote(base.string() + ".png"),
                                 dir)
                  .exit_code,
              0);
    const Image lean1 = io::read_image(base.string() + ".lean1.png");
    std::vector<float> pixels;
    for (int y = 0; y < lean1.height; ++y)
        for (int x = 0; x < lean1.width; ++x)
            for (int c = 0; c < 3; ++c)
                pixels.push_back(c == 1 ? 1.0f - lean1.at(x, y, c) : lean1.at(x, y, c));
    GltfTestFile file;
    file.images = {scene::test::png_bytes(lean1.width, lean1.height, 3, pixels)};
    file.materials = {{"flipped", glm::vec4(1.0f), -1, 0, 1.0f}};
    file.meshes.push_back({scene::test::unit_quad(0)});
    const fs::path input = dir / "scene.glb";
    scene::test::write_gltf(file, input.string(), GltfStorage::Binary);
    const auto warned = [](const test::RunResult& r) {
        EXPECT_EQ(r.exit_code, 0) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        return r.err.find("looks like a DirectX (-Y) normal map") != std::string::npos;
    };
    fs::create_directories(dir / "maps");
    EXPECT_TRUE(warned(test::run_leanfade_in("bake " + test::shell_quote(input.string()) +
                                                 " --out-dir " +
                                                 test::shell_quote((dir / "maps").string()),
                                             dir, {}, test::cache_env(dir))));
    for (const char* out : {"a.glb", "b.glb"}) {  // baked, then from the cache
        const test::RunResult r = test::run_leanfade_in(
            "bake " + test::shell_quote(input.string()) + " -o " +
                test::shell_quote((dir / out).string()),
            dir, {}, test::cache_env(dir));
        EXPECT_TRUE(warned(r)) << out;
    }
}

}  // namespace leanfade
