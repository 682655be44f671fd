// Scenes from their settings (leanfade/scene/scene_source.hpp): what build_scene builds for each
// kind of source, what it refuses by setting, what it reports, and the inputs it names.
#include <filesystem>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "leanfade/core/error.hpp"
#include "leanfade/core/image.hpp"
#include "leanfade/io/image_io.hpp"
#include "leanfade/scene/scene_source.hpp"

namespace leanfade::scene {
namespace {

namespace fs = std::filesystem;

class SceneSourceTest : public ::testing::Test {
  protected:
    void SetUp() override {
        std::random_device device;
        dir_ = fs::temp_directory_path() / ("leanfade_scene_source_" + std::to_string(device()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    fs::path dir_;
};

// The setting (or file) an error names.
template <typename F>
std::string refused_subject(F&& build) {
    try {
        build();
    } catch (const Error& e) {
        return e.file();
    }
    return "(not refused)";
}

SceneSource builtin_source(const std::string& scene) {
    SceneSource source;
    source.scene = scene;
    source.bumps.texture_size = 32;
    return source;
}

TEST_F(SceneSourceTest, BuiltinObjectHasOneMaterialWithItsMapAndPlateauLayer) {
    const Scene scene = build_scene(builtin_source("sphere"), ShadingSettings{});
    ASSERT_EQ(scene.objects.size(), 1u);
    ASSERT_EQ(scene.materials.size(), 1u);
    ASSERT_EQ(scene.lean_maps.size(), 1u);
    EXPECT_EQ(scene.materials[0].lean_map, 0);
    EXPECT_EQ(scene.lean_maps[0].levels.front().width, 32);
    // Two-lobe LEAN's plateau map on the single-map material (add_plateau_maps).
    EXPECT_GE(scene.materials[0].map(MapKind::Plateau), 0);
}

TEST_F(SceneSourceTest, PlaneRepeatsAUsersMapFiveTimesAcross) {
    // The same plane with a built-in set (uv 0..50) and with an image of one's own (uv 0..5).
    Image height(16, 16, 1);
    for (std::size_t t = 0; t < height.pixels.size(); ++t) height.pixels[t] = float(t % 7) / 7.0f;
    io::write_png(path("height.png"), height, 16);
    const Scene builtin = build_scene(builtin_source("plane"), ShadingSettings{});
    SceneSource own = builtin_source("plane");
    own.bumps.source = path("height.png");
    const Scene user = build_scene(own, ShadingSettings{});
    const auto& a = builtin.objects[0].mesh.vertices;
    const auto& b = user.objects[0].mesh.vertices;
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); i += 97) {
        EXPECT_FLOAT_EQ(b[i].uv.x, a[i].uv.x * kUserMapPlaneUvScale);
        EXPECT_FLOAT_EQ(b[i].uv1.y, a[i].uv.y * kUserMapPlaneUvScale);
    }
}

TEST_F(SceneSourceTest, LayersAndOceanBuildTheirMaterials) {
    SceneSource layered = builtin_source("teapot");
    layered.layers.sources = {"bumps", "noise"};
    const Scene scene = build_scene(layered, ShadingSettings{});
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].layered.layers.size(), 2u);
    EXPECT_EQ(scene.cross_terms.size(), 1u);  // textures: one pair

    SceneSource ocean = builtin_source(kOceanSceneName);
    ocean.bumps.texture_size = 64;
    EXPECT_TRUE(is_ocean_scene(ocean.scene));
    const Scene water = build_scene(ocean, ShadingSettings{});
    EXPECT_FALSE(water.materials.empty());
}

TEST_F(SceneSourceTest, RefusalsNameTheSetting) {
    SceneSource source = builtin_source("sphere");
    source.bumps.map_file(MapKind::BaseRoughness) = path("missing.png");
    // Blinn-Phong's base roughness is 1/s: the map needs Cook-Torrance (checked before any read).
    EXPECT_EQ(refused_subject([&] { build_scene(source, ShadingSettings{}); }), "roughness-map");
    ShadingSettings cook_torrance;
    cook_torrance.brdf = Brdf::CookTorrance;
    EXPECT_EQ(refused_subject([&] { build_scene(source, cook_torrance); }), path("missing.png"));

    SceneSource mips = builtin_source("sphere");
    mips.bumps.map_file(MapKind::RoughnessMips) = path("r_0.png");
    mips.layers.sources = {"bumps", "noise"};
    EXPECT_EQ(refused_subject([&] { build_scene(mips, ShadingSettings{}); }), "roughness-mips");

    SceneSource ocean = builtin_source(kOceanSceneName);
    ocean.bumps.texture_size = 64;
    ocean.ocean.layers = 9;
    EXPECT_EQ(refused_subject([&] { build_scene(ocean, ShadingSettings{}); }), "ocean_layers");

    SceneSource sizes = builtin_source("sphere");
    sizes.layers.sources = {"bumps", path("small.png")};
    io::write_png(path("small.png"), Image(8, 8, 1), 8);
    EXPECT_EQ(refused_subject([&] { build_scene(sizes, ShadingSettings{}); }), "layers");
}

TEST_F(SceneSourceTest, ReportsRepairedNormalsAsData) {
    // A normal map with (0, 0, 0) padding: taken as flat, reported (not printed).
    Image normals(8, 8, 3);
    for (std::size_t t = 0; t < normals.texel_count(); ++t) {
        const bool padding = t < 8;
        normals.pixels[3 * t] = padding ? 0.0f : 0.5f;
        normals.pixels[3 * t + 1] = padding ? 0.0f : 0.5f;
        normals.pixels[3 * t + 2] = padding ? 0.0f : 1.0f;
    }
    io::write_png(path("normal.png"), normals, 8);
    SceneSource source = builtin_source("sphere");
    source.bumps.source = path("normal.png");
    SceneSourceReport report;
    build_scene(source, ShadingSettings{}, &report);
    ASSERT_EQ(report.repaired.size(), 1u);
    EXPECT_EQ(report.repaired[0].first, path("normal.png"));
    EXPECT_EQ(report.repaired[0].second.padding_texels, 8u);
    // Strict: refused, naming the file.
    source.bumps.strict_normals = true;
    EXPECT_EQ(refused_subject([&] { build_scene(source, ShadingSettings{}); }), path("normal.png"));
}

TEST_F(SceneSourceTest, InputsAreTheExistingFilesItReads) {
    io::write_png(path("height.png"), Image(8, 8, 1), 8);
    io::write_png(path("weights.png"), Image(8, 8, 2), 8);
    SceneSource source = builtin_source("sphere");
    source.bumps.source = path("height.png");
    source.layers.sources = {"bumps", path("height.png")};
    source.layers.weight_map = path("weights.png");
    source.bumps.map_file(MapKind::BaseRoughness) = path("not-there.png");
    const std::vector<std::string> inputs = scene_source_inputs(source, path("preset.json"));
    EXPECT_EQ(inputs, (std::vector<std::string>{path("height.png"), path("weights.png"),
                                                path("height.png")}));
}

}  // namespace
}  // namespace leanfade::scene
