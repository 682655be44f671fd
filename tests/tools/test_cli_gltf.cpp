// glTF scenes on the command line: `leanfade bake FILE.gltf|.glb` bakes every normal texture
// through the LEAN-map cache; broken scenes are one-line errors with no output.
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_runner.hpp"
#include "leanfade/io/ktx2.hpp"
#include "test_gltf_builder.hpp"
#include "leanfade/test/scratch.hpp"

namespace leanfade {
namespace {

namespace fs = std::filesystem;
using scene::test::GltfStorage;
using scene::test::GltfTestFile;

fs::path scratch(const std::string& name) {
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

std::string env(const fs::path& dir) {
    return "env XDG_CACHE_HOME=" + test::shell_quote((dir / "cache").string());
}

TEST(CliGltf, BakeWritesEveryNormalTextureAndReusesTheCache) {
    for (GltfStorage storage : {GltfStorage::External, GltfStorage::Binary}) {
        const fs::path dir = scratch(storage == GltfStorage::Binary ? "glb" : "gltf");
        const std::string input =
            (dir / (storage == GltfStorage::Binary ? "scene.glb" : "scene.gltf")).string();
        scene::test::write_gltf(scene_file(), input, storage);
        fs::create_directories(dir / "out");
        const std::string args = "bake " + test::shell_quote(input) + " --out-dir " +
                                 test::shell_quote((dir / "out").string());
        const test::RunResult first = test::run_leanfade_in(args, dir, {}, env(dir));
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
        const test::RunResult second = test::run_leanfade_in(args, dir, {}, env(dir));
        ASSERT_EQ(second.exit_code, 0) << second.err;
        EXPECT_EQ(second.out.find("baked"), std::string::npos) << second.out;
        EXPECT_NE(second.out.find("from the cache"), std::string::npos) << second.out;
        EXPECT_EQ(test::read_text(brick), before);
    }
}

TEST(CliGltf, FlagsOfImageBakesAreRefused) {
    const fs::path dir = scratch("flags");
    const std::string input = (dir / "scene.glb").string();
    scene::test::write_gltf(scene_file(), input, GltfStorage::Binary);
    for (const std::string flag : {"--directx", "--strength 2", "--wrap clamp"}) {
        const test::RunResult r = test::run_leanfade_in(
            "bake " + test::shell_quote(input) + " " + flag, dir, {}, env(dir));
        EXPECT_NE(r.exit_code, 0) << flag;
        EXPECT_NE(r.err.find("does not apply to a glTF scene"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    EXPECT_FALSE(fs::exists(dir / "scene.brick_wall.ktx2"));
}

TEST(CliGltf, BrokenScenesAreOneLineErrorsWithoutOutput) {
    const fs::path dir = scratch("broken");
    GltfTestFile file = scene_file();
    file.meshes[1][0].indices[4] = 9;  // out of range
    const std::string input = (dir / "scene.gltf").string();
    scene::test::write_gltf(file, input, GltfStorage::Embedded);
    test::RunResult r =
        test::run_leanfade_in("bake " + test::shell_quote(input), dir, {}, env(dir));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find(input), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("index 9 out of range"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    // A truncated normal texture: nothing is published, not even the other material's map.
    file = scene_file();
    file.images[1].resize(40);
    scene::test::write_gltf(file, input, GltfStorage::Embedded);
    r = test::run_leanfade_in("bake " + test::shell_quote(input), dir, {}, env(dir));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("image 1"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "scene.brick_wall.ktx2"));
    r = test::run_leanfade_in("bake " + test::shell_quote((dir / "missing.glb").string()), dir,
                              {}, env(dir));
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find("missing.glb"), std::string::npos) << r.err;
}

}  // namespace
// A bumpy normal map written in the DirectX convention (green = -v): the convention warning of
// `bake IMAGE` also comes for the same image as a glTF normal texture (baked, and from the
// cache), in `bake SCENE.gltf --json` and in the batch --json of `bake`.
TEST(CliGltf, NormalTexturesThatLookDirectXAreWarnedAbout) {
    const fs::path dir = scratch("convention");
    const int size = 64;
    std::vector<float> pixels;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            // h = 3 sin(2 pi x / 32) sin(2 pi y / 16) texels; OpenGL B = (-dh/dx, +dh/drow),
            // DirectX flips the second.
            const double a = 2.0 * M_PI / 32.0, b = 2.0 * M_PI / 16.0;
            const double dhdx = 3.0 * a * std::cos(a * x) * std::sin(b * y);
            const double dhdy = 3.0 * b * std::sin(a * x) * std::cos(b * y);
            const glm::vec3 n = glm::normalize(glm::vec3(float(-dhdx), float(-dhdy), 1.0f));
            for (int c = 0; c < 3; ++c) pixels.push_back(0.5f * n[c] + 0.5f);
        }
    const std::vector<std::uint8_t> png = scene::test::png_bytes(size, size, 3, pixels);
    scene::test::write_bytes((dir / "dx.png").string(), png);
    scene::test::write_bytes((dir / "dx2.png").string(), png);
    // `bake` of the images, as a batch with --json.
    const test::RunResult batch = test::run_leanfade_in(
        "bake dx.png dx2.png --json batch.json", dir, dir, env(dir));
    ASSERT_EQ(batch.exit_code, 0) << batch.err;
    EXPECT_NE(batch.err.find("dx.png looks like a DirectX (-Y) normal map"), std::string::npos)
        << batch.err;
    const nlohmann::json summaries = nlohmann::json::parse(test::read_text(dir / "batch.json"));
    ASSERT_EQ(summaries.size(), 2u);
    for (const nlohmann::json& s : summaries) EXPECT_TRUE(s["looks_like_other_convention"]);
    // As a glTF normal texture: bake (twice: the second from the cache) and render.
    GltfTestFile file;
    file.images = {png};
    file.materials = {{"wall", glm::vec4(1.0f), -1, 0, 1.0f}};
    file.meshes.push_back({scene::test::unit_quad(0)});
    scene::test::write_gltf(file, (dir / "scene.gltf").string(), GltfStorage::External);
    for (int run = 0; run < 2; ++run) {
        SCOPED_TRACE(run);
        const test::RunResult r =
            test::run_leanfade_in("bake scene.gltf --json scene.json", dir, dir, env(dir));
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_NE(r.out.find(run == 0 ? "baked" : "from the cache"), std::string::npos) << r.out;
        EXPECT_NE(r.err.find("looks like a DirectX (-Y) normal map"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("glTF normal textures are OpenGL (+Y)"), std::string::npos) << r.err;
        const nlohmann::json json = nlohmann::json::parse(test::read_text(dir / "scene.json"));
        EXPECT_TRUE(json[0]["looks_like_other_convention"]);
    }
    const test::RunResult render = test::run_leanfade_in(
        "render --scene scene.gltf --techniques lean --distances 3 --size 16x16 -o r.png", dir,
        dir, env(dir));
    ASSERT_EQ(render.exit_code, 0) << render.err;
    EXPECT_NE(render.err.find("looks like a DirectX (-Y) normal map"), std::string::npos)
        << render.err;
    // An OpenGL map gives no warning.
    for (std::size_t i = 1; i < pixels.size(); i += 3) pixels[i] = 1.0f - pixels[i];
    scene::test::write_bytes((dir / "gl.png").string(), scene::test::png_bytes(size, size, 3,
                                                                              pixels));
    const test::RunResult opengl = test::run_leanfade_in("bake gl.png", dir, dir, env(dir));
    ASSERT_EQ(opengl.exit_code, 0) << opengl.err;
    EXPECT_EQ(opengl.err, "");
}

// A normal texture with (0, 0, 0) padding outside its island bakes (the padding taken as flat),
// counted in the summary, its --json and the KTX2; --strict-normals refuses it.
TEST(CliGltf, PaddedNormalTexturesAreRepairedUnlessStrict) {
    const fs::path dir = scratch("padded");
    std::vector<float> pixels;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const bool padding = x >= 12;
            const glm::vec3 n = glm::normalize(glm::vec3(0.2f * float(y % 3), 0.1f, 1.0f));
            for (int c = 0; c < 3; ++c) pixels.push_back(padding ? 0.0f : 0.5f * n[c] + 0.5f);
        }
    GltfTestFile file;
    file.images = {scene::test::png_bytes(16, 16, 3, pixels)};
    file.materials = {{"wall", glm::vec4(1.0f), -1, 0, 1.0f}};
    file.meshes.push_back({scene::test::unit_quad(0)});
    scene::test::write_gltf(file, (dir / "scene.gltf").string(), GltfStorage::External);
    const test::RunResult r =
        test::run_leanfade_in("bake scene.gltf --json scene.json", dir, dir, env(dir));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("64 (0, 0, 0) padding texels taken as flat"), std::string::npos) << r.out;
    const nlohmann::json json = nlohmann::json::parse(test::read_text(dir / "scene.json"));
    EXPECT_EQ(json[0]["padding_texels"].get<int>(), 64);
    const PackedLeanMap map = io::read_ktx2((dir / "scene.wall.ktx2").string());
    EXPECT_EQ(map.normal_repairs.padding_texels, 64u);
    const test::RunResult strict =
        test::run_leanfade_in("bake scene.gltf --strict-normals --out-dir " +
                                  test::shell_quote(dir.string()),
                              dir, dir, env(dir));
    EXPECT_EQ(strict.exit_code, 1);
    EXPECT_NE(strict.err.find("refused by --strict-normals"), std::string::npos) << strict.err;
}

}  // namespace leanfade
